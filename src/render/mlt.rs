//! Passes of the `metropolis` sampler: a fixed set of Markov chains per session, each over
//! the primary sample space (see [`crate::sampler::metropolis`]), rendering into the film's
//! per-screen buffers.
//!
//! ```text
//! Chain::propose --values--> Sampler::start_primary --stream--> camera + integrator
//!   --contributions (eye at the sample's film position, light splats elsewhere)-->
//! Chain::judge --weights--> deposits --(chain order, after each batch)--> pass film
//! ```
//!
//! A pass takes `extent pixels × pixelsamples` steps (`super::extent`), shared among
//! [`CHAINS`] chains. Chains run in parallel in fixed batches of [`BATCH`] steps; each
//! batch's deposits are added to the pass film in chain order and the large steps'
//! luminance (the normaliser) is updated in chain order too, so the film depends only on
//! (seed, stream, pass), never on threads.
//! Within a batch the normaliser is fixed (from the earlier batches and [`BOOTSTRAP`]
//! uniform samples drawn before the first one).
//! At the end of a pass every chain's pending weight is deposited, so a pass film is a
//! complete estimate and films of passes, sessions and farm workers add up exactly.
//!
//! A wrap-up (`super::stops`) ends a pass at a batch boundary after at least one batch: the
//! pending weights are deposited as at a planned end and the pass counts the steps taken
//! (the per-screen buffer's normaliser), so it estimates the same image; the chains and the
//! normaliser go on in the next pass. Wrapped up after k batches, a pass is bit for bit one
//! planned at k × [`BATCH`] steps per chain.
//!
//! Under a sampling map (`noiseaware`, or the user's), as in LuxRender, a chain's target is
//! the luminance times the map's density at the sample's film position, and fresh samples
//! (large steps, the bootstrap) draw their film position by the map
//! ([`crate::sampler::map_warp::MapWarp`]); large steps are accepted with the ratio of
//! luminances, small ones with the ratio of targets, and every deposit is divided by the
//! density, so the film estimates the same image while the samples gather where the map is
//! high. A new map restarts the chains from a new bootstrap (LuxRender resets its chains' state
//! on a new map version too).
//!
//! Film positions are drawn over the sample extent (beyond the buffer by the filter's
//! width, as LuxRender samples, `super::extent`); every contribution, the eye's and the
//! light paths' splats alike (the camera's importance is normalised over the same extent),
//! is scaled by extent pixels / buffer pixels for the per-screen buffer's normalisation.

use super::buffers::LIGHT_BUFFER;
use super::setup::Renderable;
use super::stops::{ChainPass, Stops};
use crate::film::Film;
use crate::integrator::SampleOut;
use crate::sampler::map::SamplingMap;
use crate::sampler::map_warp::MapWarp;
use crate::sampler::metropolis::{Chain, MltParams};
use crate::sampler::{combine, unit_f32};
use crate::sampler::{SampleStream, Sampler};
use crate::spectrum::rgb_to_xyz;
use glam::Vec2;
use std::sync::Arc;

/// Chains per session (fixed, so that the film does not depend on the thread count).
pub const CHAINS: usize = 16;
/// Steps each chain takes between two merges of deposits into the pass film.
pub const BATCH: u64 = 256;
/// Uniform samples drawn before a session's first step to estimate the normaliser (the mean
/// luminance), so that no chain's weights depend on its own large steps of the same batch
/// (a chain that found a bright region would otherwise weigh it up: a bias toward bright
/// regions). They add nothing to the film; each chain starts at one of them, drawn in
/// proportion to its luminance, so a session's chains need no burn-in.
pub const BOOTSTRAP: u64 = 8192;

/// One contribution of a sample to the film.
#[derive(Clone, Copy, Debug)]
pub(super) struct Contribution {
    p_film: Vec2,
    buffer: usize,
    group: usize,
    xyz: [f32; 3],
    alpha: f32,
}

/// A chain with the contributions of its current sample and reusable buffers.
#[derive(Clone, Debug)]
struct Slot {
    chain: Chain,
    current: Vec<Contribution>,
    proposal: Vec<Contribution>,
    values: Vec<f32>,
}

/// The chains of a session, the large steps' luminance so far, and the sampling map they
/// follow (if any).
#[derive(Clone, Debug)]
pub struct MltState {
    slots: Vec<Slot>,
    large_sum: f64,
    large_count: f64,
    map: Option<Arc<SamplingMap>>,
    warp: Option<Arc<MapWarp>>,
}

/// What a chain's batch produced.
#[derive(Default)]
struct BatchOut {
    deposits: Vec<(Contribution, f32)>,
    large_sum: f64,
    large_count: f64,
    invalid: u64,
}

/// Acceptance statistics of a session's chains.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ChainStats {
    pub proposed: u64,
    pub accepted: u64,
}

/// Where film positions are drawn and how contributions are scaled (shared with
/// [`super::erpt`]).
pub(super) struct Frame {
    origin: Vec2,
    span: Vec2,
    /// Raster position of the film's pixel (0, 0).
    film0: [i64; 2],
    scale: f32,
    /// The small mutations' film range per axis, as a fraction of the span.
    pub range_xy: [f32; 2],
    /// The sampling map over the span: fresh film positions are drawn by it.
    warp: Option<Arc<MapWarp>>,
    /// Whether black eye contributions are kept: a noise-aware film counts them in its
    /// variance sums (LuxRender deposits them), though they add nothing to the image.
    keep_black: bool,
}

impl Frame {
    /// A primary stream over `values` on this frame, drawing missing dimensions from `key`.
    pub(super) fn stream(&self, values: Vec<f32>, key: u64) -> SampleStream {
        Sampler::start_primary(values, key, self.origin, self.span)
    }

    /// The density with which fresh film positions are drawn at the film position of
    /// `values` (1 without a map).
    fn q(&self, values: &[f32]) -> f32 {
        match (&self.warp, values) {
            (Some(w), [x, y, ..]) => w.density([*x, *y]),
            _ => 1.0,
        }
    }
}

impl MltState {
    pub fn new(seed: u64, stream: u64) -> MltState {
        MltState {
            slots: (0..CHAINS as u64)
                .map(|i| Slot {
                    chain: Chain::new(seed, stream, i),
                    current: Vec::new(),
                    proposal: Vec::new(),
                    values: Vec::new(),
                })
                .collect(),
            large_sum: 0.0,
            large_count: 0.0,
            map: None,
            warp: None,
        }
    }

    /// Follows `map` from now on (`None`: uniform). A new map changes the chains' target
    /// (luminance × map density) and the normaliser: like LuxRender's sampler on a new map
    /// version, the state starts over, here with a new bootstrap, so every pass's estimate
    /// stays unbiased.
    fn follow(&mut self, map: Option<&Arc<SamplingMap>>, frame: &Frame, extent: [i64; 4]) {
        let same = match (&self.map, map) {
            (None, None) => true,
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            _ => false,
        };
        if same {
            return;
        }
        self.map = map.cloned();
        self.warp = map.and_then(|m| {
            let [x0, y0, fx, fy] = extent;
            let (w, h) = (frame.span.x as u32, frame.span.y as u32);
            MapWarp::new(m, w, h, [x0 - fx, y0 - fy]).map(Arc::new)
        });
        self.large_sum = 0.0;
        self.large_count = 0.0;
    }

    pub fn stats(&self) -> ChainStats {
        self.slots
            .iter()
            .fold(ChainStats::default(), |s, c| ChainStats {
                proposed: s.proposed + c.chain.proposed,
                accepted: s.accepted + c.chain.accepted,
            })
    }

    /// Estimates the mean luminance from [`BOOTSTRAP`] uniform samples (keys of their own)
    /// and starts each chain at one of them, drawn from the whole set in proportion to its
    /// luminance. A chain started at a uniform point would weigh the film toward the wrong
    /// regions until it reached its stationary distribution: a bias that grows with the
    /// number of sessions a render is cut into (farm leases are sessions). Drawing from all
    /// of them, not a chain's own share, keeps the resampling's own bias small.
    fn bootstrap(
        &mut self,
        scene: &Renderable,
        pool: &rayon::ThreadPool,
        frame: &Frame,
        params: &MltParams,
        pixels: f64,
    ) {
        use rayon::prelude::*;
        let per = BOOTSTRAP / CHAINS as u64;
        let lums: Vec<Vec<f32>> = pool.install(|| {
            self.slots
                .par_iter()
                .map(|slot| {
                    let mut so = SampleOut::new(scene.world.groups().len());
                    let (mut rec, mut invalid) = (Vec::new(), 0);
                    (0..per)
                        .map(|i| {
                            rec.clear();
                            let key = slot.chain.bootstrap_key(i);
                            trace_fresh(scene, params, frame, key, &mut so, &mut rec, &mut invalid)
                                .0
                        })
                        .collect()
                })
                .collect()
        });
        for l in &lums {
            self.large_sum += l.iter().map(|&x| f64::from(x)).sum::<f64>();
            self.large_count += l.len() as f64;
        }
        let all: Vec<f32> = lums.concat();
        let starts: Vec<Option<u64>> = (self.slots.iter())
            .map(|slot| {
                let j = slot.chain.pick_start(&all)? as u64;
                let owner = self.slots.get((j / per) as usize)?;
                Some(owner.chain.bootstrap_key(j % per))
            })
            .collect();
        // The large mutation probability of the first batch (see `run_pass`).
        let p_large = if params.cooldown && (BOOTSTRAP as f64) < pixels {
            0.5
        } else {
            params.large_prob
        };
        pool.install(|| {
            self.slots
                .par_iter_mut()
                .zip(starts.par_iter())
                .for_each(|(slot, start)| {
                    let Some(key) = *start else {
                        slot.chain.restart();
                        slot.current.clear();
                        return;
                    };
                    let mut so = SampleOut::new(scene.world.groups().len());
                    let (mut rec, mut invalid) = (Vec::new(), 0);
                    let (lum, values) =
                        trace_fresh(scene, params, frame, key, &mut so, &mut rec, &mut invalid);
                    let q = frame.q(&values);
                    slot.chain.start_at(values, lum, q, p_large);
                    slot.current = rec;
                })
        });
    }

    fn mean(&self) -> f64 {
        if self.large_count > 0.0 {
            self.large_sum / self.large_count
        } else {
            0.0
        }
    }

    /// Runs one pass of `steps` steps into `film` (cleared by the caller, the session's
    /// layout), following sampling map `map` (`None`: uniform). A wrap-up (`stops`) ends it
    /// at a batch boundary after at least one batch, with the steps taken so far: the
    /// chains' pending weights are deposited as at a planned end, so the film is an estimate
    /// over those steps. Returns what the pass did, or `None` when cancelled (the chains have
    /// then moved on; the partial film is to be discarded).
    pub fn run_pass(
        &mut self,
        scene: &Renderable,
        pool: &rayon::ThreadPool,
        stops: &Stops,
        steps: u64,
        film: &mut Film,
        map: Option<&Arc<SamplingMap>>,
    ) -> Option<ChainPass> {
        use rayon::prelude::*;
        let Some(params) = scene.setup.sampler.mlt().copied() else {
            return Some(ChainPass::default());
        };
        let fp = &scene.setup.film_params;
        let range = params.range_pixels(fp.x_pixel_count as f32, fp.y_pixel_count as f32);
        let mut frame = frame(scene, range, film.variance().is_some());
        let e = scene.setup.sample_extent();
        let extent = [
            i64::from(e.x0),
            i64::from(e.y0),
            frame.film0[0],
            frame.film0[1],
        ];
        self.follow(map, &frame, extent);
        frame.warp = self.warp.clone();
        let n = self.slots.len() as u64;
        let share = |i: u64| steps / n + u64::from(i < steps % n);
        let mut done = vec![0u64; self.slots.len()];
        let mut invalid = 0;
        let pixels = f64::from(film.width()) * f64::from(film.height());
        if self.large_count == 0.0 {
            self.bootstrap(scene, pool, &frame, &params, pixels);
        }
        let mut wrapped_up = false;
        loop {
            if stops.cancelled() {
                return None;
            }
            let todo: Vec<u64> = (0..n)
                .map(|i| share(i).saturating_sub(done[i as usize]).min(BATCH))
                .collect();
            if todo.iter().all(|&t| t == 0) {
                break;
            }
            if done.iter().any(|&d| d > 0) && stops.wrap_up_due() {
                wrapped_up = true;
                break;
            }
            let (sum0, count0) = (self.large_sum, self.large_count);
            let p_large = if params.cooldown && count0 < pixels {
                0.5
            } else {
                params.large_prob
            };
            let outs: Vec<BatchOut> = pool.install(|| {
                self.slots
                    .par_iter_mut()
                    .zip(todo.par_iter())
                    .map(|(slot, &k)| {
                        let mut out = BatchOut::default();
                        let mut so = SampleOut::new(scene.world.groups().len());
                        let mean = if count0 > 0.0 { sum0 / count0 } else { 0.0 };
                        for _ in 0..k {
                            step(
                                scene, &params, &frame, p_large, mean, slot, &mut so, &mut out,
                            );
                        }
                        out
                    })
                    .collect()
            });
            for (i, o) in outs.into_iter().enumerate() {
                deposit(scene, &frame, film, &o.deposits);
                self.large_sum += o.large_sum;
                self.large_count += o.large_count;
                invalid += o.invalid;
                done[i] += todo[i];
            }
        }
        let mean = self.mean();
        let p_large = params.large_prob;
        for slot in &mut self.slots {
            let w = slot.chain.flush(mean, p_large);
            let d: Vec<_> = slot.current.iter().map(|c| (*c, w)).collect();
            deposit(scene, &frame, film, &d);
        }
        Some(ChainPass {
            invalid,
            samples: done.iter().sum(),
            wrapped_up,
        })
    }
}

/// The frame of a session: film positions over the sample extent, small mutations moving
/// them by at most `range` pixels.
pub(super) fn frame(scene: &Renderable, range: f32, keep_black: bool) -> Frame {
    let fp = &scene.setup.film_params;
    let e = scene.setup.sample_extent();
    let span = Vec2::new((e.x1 - e.x0).max(1) as f32, (e.y1 - e.y0).max(1) as f32);
    Frame {
        origin: Vec2::new(e.x0 as f32, e.y0 as f32),
        span,
        film0: [i64::from(fp.x_pixel_start), i64::from(fp.y_pixel_start)],
        scale: e.per_screen_scale(),
        range_xy: [(range / span.x).min(1.0), (range / span.y).min(1.0)],
        warp: None,
        keep_black,
    }
}

/// [`trace`] of a sample whose values are all drawn afresh from `key` (the bootstrap's
/// uniform samples, and the one a chain starts from).
fn trace_fresh(
    scene: &Renderable,
    params: &MltParams,
    frame: &Frame,
    key: u64,
    so: &mut SampleOut,
    rec: &mut Vec<Contribution>,
    invalid: &mut u64,
) -> (f32, Vec<f32>) {
    trace(
        scene,
        params.use_variance,
        frame,
        Vec::new(),
        key,
        so,
        rec,
        invalid,
    )
}

/// Traces the sample whose primary values are `values` (grown from `key` as needed):
/// records its contributions in `rec` and returns its target luminance (with
/// `use_variance`, the integrator's MIS-weighted hint where it gives one) and its values.
#[allow(clippy::too_many_arguments)]
pub(super) fn trace(
    scene: &Renderable,
    use_variance: bool,
    frame: &Frame,
    values: Vec<f32>,
    key: u64,
    so: &mut SampleOut,
    rec: &mut Vec<Contribution>,
    invalid: &mut u64,
) -> (f32, Vec<f32>) {
    let mut values = values;
    if let (Some(w), true) = (&frame.warp, values.is_empty()) {
        // A fresh sample under a map: its film position drawn by the map.
        let u = |salt: u64| unit_f32(combine(key, salt));
        values.extend(w.warp([u(0x6d61_7078), u(0x6d61_7079)]));
    }
    let st = frame.stream(values, key);
    trace_stream(scene, use_variance, frame, st, so, rec, invalid)
}

/// [`trace`] of the primary stream `st` (from [`Sampler::start_primary`]).
pub(super) fn trace_stream(
    scene: &Renderable,
    use_variance: bool,
    frame: &Frame,
    mut st: SampleStream,
    so: &mut SampleOut,
    rec: &mut Vec<Contribution>,
    invalid: &mut u64,
) -> (f32, Vec<f32>) {
    let (setup, world) = (&scene.setup, &scene.world);
    let cs = st.camera_sample();
    let mut lum = 0.0f32;
    if let Some((ray, w)) = setup.camera.generate_ray(&cs).filter(|(_, w)| *w > 0.0) {
        setup
            .integrator
            .sample(world, &setup.camera, ray, &mut st, so);
        let k = w * frame.scale;
        let eye = so.l.iter().zip(&so.weight_lum).enumerate();
        for (g, (c, wl)) in eye {
            let xyz = rgb_to_xyz(*c * k);
            let hint = (use_variance && *wl > 0.0).then_some(*wl * k);
            let black = frame.keep_black;
            lum += record(rec, cs.p_film, 0, g, xyz, so.alpha, hint, black, invalid);
        }
        for sp in &so.splats {
            let xyz = rgb_to_xyz(sp.l * k);
            let hint = (use_variance && sp.weight > 0.0).then(|| sp.weight * xyz[1]);
            let g = sp.group as usize;
            lum += record(
                rec,
                sp.p_film,
                LIGHT_BUFFER,
                g,
                xyz,
                1.0,
                hint,
                false,
                invalid,
            );
        }
    }
    (lum, st.into_values())
}

/// One Metropolis step of a chain: propose, trace, judge, record the deposits; `mean` is
/// the normaliser in force for this batch.
#[allow(clippy::too_many_arguments)]
fn step(
    scene: &Renderable,
    params: &MltParams,
    frame: &Frame,
    p_large: f32,
    mean: f64,
    slot: &mut Slot,
    so: &mut SampleOut,
    out: &mut BatchOut,
) {
    let mut values = std::mem::take(&mut slot.values);
    slot.chain.propose(frame.range_xy, &mut values);
    let mut rec = std::mem::take(&mut slot.proposal);
    rec.clear();
    let key = slot.chain.step_key();
    let (lum, mut values) = trace(
        scene,
        params.use_variance,
        frame,
        values,
        key,
        so,
        &mut rec,
        &mut out.invalid,
    );
    if slot.chain.is_large() {
        out.large_sum += f64::from(lum);
        out.large_count += 1.0;
    }
    let q = frame.q(&values);
    let d = slot
        .chain
        .judge(&mut values, lum, q, mean, p_large, params.max_rejects);
    if d.accepted {
        if d.current_weight > 0.0 {
            out.deposits
                .extend(slot.current.iter().map(|c| (*c, d.current_weight)));
        }
        std::mem::swap(&mut slot.current, &mut rec);
    } else if d.proposal_weight > 0.0 {
        out.deposits
            .extend(rec.iter().map(|c| (*c, d.proposal_weight)));
    }
    slot.values = values;
    slot.proposal = rec;
}

/// Records a contribution when it is usable (a black one only when `keep_black`); returns
/// its part of the chain's target (its luminance, or the variance `hint` when given).
#[allow(clippy::too_many_arguments)]
fn record(
    rec: &mut Vec<Contribution>,
    p_film: Vec2,
    buffer: usize,
    group: usize,
    xyz: [f32; 3],
    alpha: f32,
    hint: Option<f32>,
    keep_black: bool,
    invalid: &mut u64,
) -> f32 {
    if !xyz.iter().all(|v| v.is_finite()) || xyz[1] < 0.0 || !p_film.is_finite() {
        *invalid += 1;
        return 0.0;
    }
    let black = xyz[1] == 0.0 && xyz[0] == 0.0 && xyz[2] == 0.0;
    if !black || keep_black {
        rec.push(Contribution {
            p_film,
            buffer,
            group,
            xyz,
            alpha,
        });
    }
    if black {
        return 0.0;
    }
    hint.filter(|h| h.is_finite() && *h > 0.0).unwrap_or(xyz[1])
}

/// Adds weighted contributions to the film through the pixel filter (a black one only to its
/// variance sums: it adds nothing to the image).
pub(super) fn deposit(
    scene: &Renderable,
    frame: &Frame,
    film: &mut Film,
    deposits: &[(Contribution, f32)],
) {
    let filter = &scene.setup.filter;
    let nbuf = film.buffer_types().len();
    for (c, w) in deposits {
        let buffer = if c.buffer < nbuf { c.buffer } else { 0 };
        let black = c.xyz == [0.0; 3];
        filter.splat(c.p_film, |x, y, fw| {
            let (lx, ly) = (i64::from(x) - frame.film0[0], i64::from(y) - frame.film0[1]);
            if !((0..=i64::from(u32::MAX)).contains(&lx) && (0..=i64::from(u32::MAX)).contains(&ly))
            {
                return;
            }
            if !black {
                film.add_buffer_splat(
                    c.group,
                    buffer,
                    lx as u32,
                    ly as u32,
                    c.xyz,
                    c.alpha,
                    fw * w,
                );
            }
            film.add_variance(lx as u32, ly as u32, c.xyz[1], fw * w);
        });
    }
}
