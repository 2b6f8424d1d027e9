//! Passes of the `erpt` sampler (energy redistribution path tracing, see
//! [`crate::sampler::erpt`]), rendering into the film's per-screen buffers with the tracing
//! and deposit code of [`super::mlt`].
//!
//! ```text
//! warm-up (initsamples uniform samples, once per session; keyed by the seed alone) --mean energy / chainlength--> ed
//! seed i (uniform sample, key (seed, stream, i); stratified by `basesampler`) --trace--> energy e --chain_plan--> n, q
//!   chain j of seed i: chainlength × { small_mutation --trace--> judge } --deposits--> pass film
//! ```
//!
//! A pass takes `⌈extent pixels × pixelsamples / (1 + chainlength)⌉` seeds (at least one), about
//! as many traces as a pass of the other samplers since a seed starts one chain on average.
//! Each seed counts `1 + chainlength` samples in the film and its deposits are scaled by the
//! same factor: the per-screen buffer's value (sum × pixels / count) is unchanged, and the
//! film's sample count (haltspp, the farm's budgets) follows the work done, as metropolis'
//! counts its steps.
//!
//! Determinism: seeds are traced in fixed batches of [`SEED_BATCH`], their chains run in
//! fixed groups of [`CHAIN_GROUP`] in parallel, [`STEP_BATCH`] steps at a time, and every
//! batch's deposits are added in chain order, so the film depends only on (seed, stream,
//! pass), never on threads. The quantum comes from warm-up samples of their own keys and is
//! fixed for the session, so it does not depend on the samples it weighs. Those keys depend
//! on the seed but not the stream, so all sessions of a scene and seed share the quantum: a
//! farm worker estimates it once per job and hands it to the job's later leases
//! ([`ErptState::set_quantum`]), whose films are the same as with a warm-up of their own. Every chain ends
//! within its pass: a pass film is a complete estimate, and films of passes, sessions and
//! farm workers (each on its own stream) add up exactly.
//!
//! A wrap-up (`super::stops`) ends a pass after a whole batch of seeds, all their chains run
//! to their end: the pass counts `1 + chainlength` samples per seed done, and the next pass
//! goes on at the next seed, as if this pass had been planned at the seeds it did. The
//! warm-up is never cut short (only cancelled): a wrapped-up first pass still estimates the
//! quantum and traces one batch of seeds.

use super::mlt::{deposit, frame, trace, trace_stream, ChainStats, Contribution, Frame};
use super::setup::Renderable;
use super::stops::{ChainPass, Stops};
use crate::film::Film;
use crate::integrator::SampleOut;
use crate::sampler::erpt::{
    chain_key, chain_plan, seed_key, seed_point, seed_xi, warm_up_key, BaseSampler, ErptChain,
};
use std::sync::atomic::{AtomicBool, Ordering};

/// Seeds traced together (their chains then run group by group).
pub const SEED_BATCH: u64 = 64;
/// Chains run in parallel.
pub const CHAIN_GROUP: usize = 16;
/// Steps each chain of a group takes between two merges of deposits into the pass film.
pub const STEP_BATCH: u32 = 256;
/// Warm-up samples per parallel unit (summed in unit order).
const WARM_UP_UNIT: u64 = 1024;
/// Warm-up units between two looks at the cancel flag.
const WARM_UP_WAVE: u64 = 64;

/// Seeds in a pass of `samples` (extent pixels × pixelsamples) traces with chains of
/// `chain_length` mutations.
pub fn seeds_per_pass(samples: u64, chain_length: u32) -> u64 {
    samples.div_ceil(samples_per_seed(chain_length)).max(1)
}

/// What one seed counts in the film's sample count (and scales its deposits by).
pub fn samples_per_seed(chain_length: u32) -> u64 {
    1 + u64::from(chain_length)
}

/// A traced seed.
struct Seed {
    key: u64,
    /// The ξ of its chain count.
    xi: f32,
    lum: f32,
    values: Vec<f32>,
    rec: Vec<Contribution>,
}

/// A running chain with the contributions of its current sample and reusable buffers.
struct Run {
    chain: ErptChain,
    current: Vec<Contribution>,
    proposal: Vec<Contribution>,
    values: Vec<f32>,
}

/// What a chain's batch of steps produced.
#[derive(Default)]
struct StepsOut {
    deposits: Vec<(Contribution, f32)>,
    invalid: u64,
}

/// A session's ERPT state: its keys, the quantum once estimated, the seeds drawn so far.
#[derive(Clone, Debug)]
pub struct ErptState {
    seed: u64,
    stream: u64,
    next_seed: u64,
    /// The energy quantum (mean warm-up energy per mutation; 0: the warm-up saw no light).
    ed: Option<f64>,
    stats: ChainStats,
}

impl ErptState {
    pub fn new(seed: u64, stream: u64) -> ErptState {
        ErptState {
            seed,
            stream,
            next_seed: 0,
            ed: None,
            stats: ChainStats::default(),
        }
    }

    /// Mutations proposed and accepted so far (completed passes).
    pub fn stats(&self) -> ChainStats {
        self.stats
    }

    /// The energy quantum, once the first pass has estimated it.
    pub fn quantum(&self) -> Option<f64> {
        self.ed
    }

    /// Takes the quantum another session of the same scene and seed estimated (any stream:
    /// the warm-up does not depend on it), so this one skips its warm-up. A quantum that is
    /// not positive and finite is ignored.
    pub fn set_quantum(&mut self, ed: f64) {
        if ed > 0.0 && ed.is_finite() {
            self.ed = Some(ed);
        }
    }

    /// Estimates the quantum from the warm-up samples; `None` when cancelled.
    fn warm_up(
        &self,
        scene: &Renderable,
        pool: &rayon::ThreadPool,
        cancel: &AtomicBool,
        frame: &Frame,
        count: u64,
        chain_length: u32,
    ) -> Option<f64> {
        use rayon::prelude::*;
        let units = count.div_ceil(WARM_UP_UNIT);
        let mut sum = 0.0f64;
        let mut first = 0;
        while first < units {
            if cancel.load(Ordering::Relaxed) {
                return None;
            }
            let last = (first + WARM_UP_WAVE).min(units);
            let sums: Vec<f64> = pool.install(|| {
                (first..last)
                    .into_par_iter()
                    .map(|u| {
                        let mut so = SampleOut::new(scene.world.groups().len());
                        let (mut rec, mut invalid, mut s) = (Vec::new(), 0, 0.0);
                        let end = ((u + 1) * WARM_UP_UNIT).min(count);
                        for i in u * WARM_UP_UNIT..end {
                            rec.clear();
                            let key = warm_up_key(self.seed, i);
                            let v = Vec::new();
                            let lum =
                                trace(scene, false, frame, v, key, &mut so, &mut rec, &mut invalid);
                            s += f64::from(lum.0);
                        }
                        s
                    })
                    .collect()
            });
            sum += sums.iter().sum::<f64>();
            first = last;
        }
        let mean = sum / count.max(1) as f64;
        Some(mean / f64::from(chain_length.max(1)))
    }

    /// Runs one pass of `seeds` seeds into `film` (cleared by the caller, the session's
    /// layout). A wrap-up (`stops`) ends it after a whole batch of seeds (the warm-up and at
    /// least one batch first), whose chains have all run to their end: the film is then an
    /// estimate over the seeds done, and the next pass starts at the next seed. Returns what
    /// the pass did, or `None` when cancelled (the partial film is to be discarded; the next
    /// pass draws the same seeds again).
    pub fn run_pass(
        &mut self,
        scene: &Renderable,
        pool: &rayon::ThreadPool,
        stops: &Stops,
        seeds: u64,
        film: &mut Film,
    ) -> Option<ChainPass> {
        let Some(params) = scene.setup.sampler.erpt().copied() else {
            return Some(ChainPass::default());
        };
        let fp = &scene.setup.film_params;
        let range = params.range_pixels(fp.x_pixel_count as f32, fp.y_pixel_count as f32);
        let frame = frame(scene, range, film.variance().is_some());
        let m = params.chain_length.max(1);
        let ed = match self.ed {
            Some(ed) => ed,
            None => {
                let ed = self.warm_up(
                    scene,
                    pool,
                    stops.cancel,
                    &frame,
                    u64::from(params.init_samples),
                    m,
                )?;
                self.ed = Some(ed);
                ed
            }
        };
        let scale = samples_per_seed(m) as f64;
        let mut stats = self.stats;
        let mut invalid = 0;
        let mut first = 0;
        while first < seeds {
            if first > 0 && stops.wrap_up_due() {
                break;
            }
            let last = (first + SEED_BATCH).min(seeds);
            let traced =
                self.trace_seeds(scene, pool, &frame, params.base, first..last, &mut invalid);
            let plans: Vec<(usize, u32, f64)> = traced
                .iter()
                .enumerate()
                .flat_map(|(i, s)| {
                    let (n, q) = chain_plan(f64::from(s.lum), ed, m, s.xi);
                    (0..n).map(move |j| (i, j, q * scale))
                })
                .collect();
            for group in plans.chunks(CHAIN_GROUP) {
                let mut runs: Vec<Run> = group
                    .iter()
                    .filter_map(|&(i, j, q)| traced.get(i).map(|s| (s, j, q)))
                    .map(|(s, j, q)| Run {
                        chain: ErptChain::new(chain_key(s.key, j), s.values.clone(), s.lum, q),
                        current: s.rec.clone(),
                        proposal: Vec::new(),
                        values: Vec::new(),
                    })
                    .collect();
                invalid += run_group(scene, pool, stops.cancel, &frame, m, &mut runs, film)?;
                for r in &runs {
                    stats.proposed += r.chain.proposed;
                    stats.accepted += r.chain.accepted;
                }
            }
            first = last;
        }
        self.next_seed += first;
        self.stats = stats;
        Some(ChainPass {
            invalid,
            samples: first.saturating_mul(samples_per_seed(m)),
            wrapped_up: first < seeds,
        })
    }

    /// Traces the seeds `range` (indices within this pass) in parallel, in order.
    fn trace_seeds(
        &self,
        scene: &Renderable,
        pool: &rayon::ThreadPool,
        frame: &Frame,
        base: BaseSampler,
        range: std::ops::Range<u64>,
        invalid: &mut u64,
    ) -> Vec<Seed> {
        use rayon::prelude::*;
        let out: Vec<(Seed, u64)> = pool.install(|| {
            range
                .into_par_iter()
                .map(|i| {
                    let index = self.next_seed + i;
                    let key = seed_key(self.seed, self.stream, index);
                    let mut st = frame.stream(Vec::new(), key);
                    let mut xi = seed_xi(key);
                    if base == BaseSampler::Stratified {
                        let p = seed_point(self.seed, self.stream, index);
                        st = st.with_stratified_fresh(p);
                        xi = p.chain_xi();
                    }
                    let mut so = SampleOut::new(scene.world.groups().len());
                    let (mut rec, mut bad) = (Vec::new(), 0);
                    let (lum, values) =
                        trace_stream(scene, false, frame, st, &mut so, &mut rec, &mut bad);
                    let seed = Seed {
                        key,
                        xi,
                        lum,
                        values,
                        rec,
                    };
                    (seed, bad)
                })
                .collect()
        });
        out.into_iter()
            .map(|(s, bad)| {
                *invalid += bad;
                s
            })
            .collect()
    }
}

/// Runs a group of chains to their end (`m` steps each), adding their deposits to `film`
/// in chain order after every batch of steps; returns the invalid contributions, or `None`
/// when cancelled.
fn run_group(
    scene: &Renderable,
    pool: &rayon::ThreadPool,
    cancel: &AtomicBool,
    frame: &Frame,
    m: u32,
    runs: &mut [Run],
    film: &mut Film,
) -> Option<u64> {
    use rayon::prelude::*;
    let mut invalid = 0;
    let mut done = 0u32;
    while done < m {
        if cancel.load(Ordering::Relaxed) {
            return None;
        }
        let k = STEP_BATCH.min(m - done);
        let outs: Vec<StepsOut> = pool.install(|| {
            runs.par_iter_mut()
                .map(|r| {
                    let mut so = SampleOut::new(scene.world.groups().len());
                    let mut out = StepsOut::default();
                    for _ in 0..k {
                        step(scene, frame, r, &mut so, &mut out);
                    }
                    out
                })
                .collect()
        });
        for o in outs {
            deposit(scene, frame, film, &o.deposits);
            invalid += o.invalid;
        }
        done += k;
    }
    for r in runs.iter_mut() {
        let w = r.chain.flush() as f32;
        if w > 0.0 {
            let d: Vec<_> = r.current.iter().map(|c| (*c, w)).collect();
            deposit(scene, frame, film, &d);
        }
    }
    Some(invalid)
}

/// One mutation of a chain: propose, trace, judge, record the deposits.
fn step(scene: &Renderable, frame: &Frame, r: &mut Run, so: &mut SampleOut, out: &mut StepsOut) {
    let mut values = std::mem::take(&mut r.values);
    r.chain.propose(frame.range_xy, &mut values);
    let mut rec = std::mem::take(&mut r.proposal);
    rec.clear();
    let key = r.chain.step_key();
    let (lum, mut values) = trace(
        scene,
        false,
        frame,
        values,
        key,
        so,
        &mut rec,
        &mut out.invalid,
    );
    let d = r.chain.judge(&mut values, lum);
    if d.accepted {
        let w = d.current_weight as f32;
        if w > 0.0 {
            out.deposits.extend(r.current.iter().map(|c| (*c, w)));
        }
        std::mem::swap(&mut r.current, &mut rec);
    } else {
        let w = d.proposal_weight as f32;
        if w > 0.0 {
            out.deposits.extend(rec.iter().map(|c| (*c, w)));
        }
    }
    r.values = values;
    r.proposal = rec;
}
