//! How a session renders one pass: the pixel samplers' tiles in parallel (in fixed batches
//! with their splats when the integrator splats), or the metropolis and erpt chains into a
//! pass film; then the pass is counted (under a map, each pixel's samples too:
//! `super::counts`) and the sampling map rebuilt when due. The session
//! itself, its maps and its film are in `mod.rs`.
//!
//! A sweep renders several passes at once where nothing changes between them (a pixel
//! sampler without sampling maps and an integrator without splats): each tile takes the
//! passes' samples in one visit, at the indices the passes would have given them, so a
//! sweep of n passes draws exactly the samples of n single passes. Only the order in which
//! they are summed differs (tile film before session film). With `pixelsamples` 1 on a small
//! image a pass is a few tens of milliseconds, and allocating, merging and waiting for the
//! slowest tile once per pass cost about 5% of the render; a sweep pays them once.
//!
//! A pass of the chain samplers may be wrapped up before its planned end ([`super::stops`]:
//! [`Session::set_deadline`], [`Session::wrap_up_flag`]) and then counts the samples it
//! took; a tile pass always runs whole (or is cancelled and discarded).

use super::counts::SampleCounts;
use super::setup::Renderable;
use super::stops::{ChainPass, Stops};
use super::tile::Tile;
use super::{buffers, erpt, tile, tiles, PassStats, Session, SPLAT_BATCH};
use crate::film::{BufferType, Film, ZBuffer};
use crate::sampler::map::SamplingMap;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

/// A sweep takes this many samples, or just over (at most [`MAX_SWEEP`] passes).
const SWEEP_SAMPLES: u64 = 1 << 20;

/// Passes in a sweep at most.
const MAX_SWEEP: u64 = 64;

impl Session {
    /// Renders one more pass of `pixelsamples` samples over every pixel of the sample extent
    /// ([`extent`]) into the film.
    pub fn render_pass(&mut self) -> PassStats {
        self.render_passes(1)
    }

    /// Renders up to `max` passes (at least one) in one sweep, as many as
    /// [`Self::sweep_passes`] allows; the stats say how many.
    pub fn render_passes(&mut self, max: u64) -> PassStats {
        if self.mlt.is_some() {
            return self.render_pass_mlt();
        }
        if self.erpt.is_some() {
            return self.render_pass_erpt();
        }
        if self.scene.setup.integrator.splats() {
            return self.render_pass_splatting();
        }
        let start = Instant::now();
        let passes = max.clamp(1, self.sweep_passes());
        self.start_counts();
        let scene = &*self.scene;
        let fp = &scene.setup.film_params;
        let list = tiles(fp.x_pixel_count, fp.y_pixel_count);
        let (buffers, map) = (self.buffers.clone(), self.map.clone());
        let mut ctx = self.pass_ctx(&buffers, map.as_deref(), self.counts.as_ref());
        ctx.passes = u32::try_from(passes).unwrap_or(1);
        let Some(results) = render_tiles(&self.pool, scene, &list, &ctx, &self.cancel) else {
            return cancelled(start);
        };
        let (mut rejected, mut outliers, mut samples) = (0, 0, 0);
        for r in &results {
            samples += r.samples;
            merge_tile(&mut self.film, self.depth.as_mut(), r);
            rejected += r.discarded.invalid;
            outliers += r.discarded.outliers;
        }
        self.finish_passes(passes, start, samples, rejected, outliers)
    }

    /// Passes one sweep may render ([`Self::render_passes`]): enough for about
    /// 2²⁰ samples (`SWEEP_SAMPLES`) when nothing changes between passes, else 1.
    pub fn sweep_passes(&self) -> u64 {
        let batchable = self.mlt.is_none()
            && self.erpt.is_none()
            && !self.scene.setup.integrator.splats()
            && !self.noise_aware()
            && self.map.is_none();
        if !batchable {
            return 1;
        }
        SWEEP_SAMPLES
            .div_ceil(self.pass_samples().max(1))
            .clamp(1, MAX_SWEEP)
    }

    /// What the tiles of the next pass share (borrowing only the buffer layout and the map,
    /// so the pass can still write the depth buffer).
    fn pass_ctx<'a>(
        &self,
        buffers: &'a [BufferType],
        map: Option<&'a SamplingMap>,
        counts: Option<&'a SampleCounts>,
    ) -> tile::PassCtx<'a> {
        tile::PassCtx {
            pass: self.pass,
            passes: 1,
            spp: self.scene.setup.sampler.pixel_samples().max(1),
            seed: self.opts.seed,
            stream: self.opts.stream,
            buffers,
            extent: self.scene.setup.sample_extent(),
            map,
            counts,
            depth: self.depth.is_some(),
            variance: self.film.variance().is_some(),
        }
    }

    /// Starts each pixel's sample count when the passes first follow a map: every pixel has
    /// taken `pixelsamples` a pass so far (`super::counts`).
    fn start_counts(&mut self) {
        if self.map.is_some() && self.counts.is_none() {
            let spp = u64::from(self.scene.setup.sampler.pixel_samples().max(1));
            self.counts = Some(SampleCounts::new(
                self.scene.setup.sample_extent(),
                self.pass * spp,
            ));
        }
    }

    /// Adds a complete pass's samples to each pixel's count (with the map the pass used).
    fn advance_counts(&mut self) {
        let Some(mut counts) = self.counts.take() else {
            return;
        };
        let map = self.map.clone();
        let ctx = self.pass_ctx(&[], map.as_deref(), None);
        let fp = &self.scene.setup.film_params;
        counts.advance(|px, py| ctx.plan_at(fp, px, py));
        self.counts = Some(counts);
    }

    /// A pass of an integrator with splats: tiles in fixed batches, each batch's tile films
    /// and then its splats (tile order) added to a pass film, merged into the session film
    /// once the pass is complete.
    fn render_pass_splatting(&mut self) -> PassStats {
        let start = Instant::now();
        self.start_counts();
        let scene = &*self.scene;
        let fp = &scene.setup.film_params;
        let list = tiles(fp.x_pixel_count, fp.y_pixel_count);
        let (buffers, map) = (self.buffers.clone(), self.map.clone());
        let ctx = self.pass_ctx(&buffers, map.as_deref(), self.counts.as_ref());
        let mut pass_film = self.film.clone();
        pass_film.clear();
        let origin = [fp.x_pixel_start, fp.y_pixel_start];
        // Each sample's light path lands per screen: scaled as the extent's samples are.
        let splat_scale = ctx.extent.per_screen_scale();
        let (mut rejected, mut outliers, mut samples) = (0, 0, 0);
        for batch in list.chunks(SPLAT_BATCH) {
            let Some(results) = render_tiles(&self.pool, scene, batch, &ctx, &self.cancel) else {
                return cancelled(start);
            };
            for r in &results {
                samples += r.samples;
                merge_tile(&mut pass_film, self.depth.as_mut(), r);
                rejected += r.discarded.invalid
                    + buffers::apply_splats(
                        &mut pass_film,
                        buffers::LIGHT_BUFFER,
                        &scene.setup.filter,
                        origin,
                        &r.splats,
                        splat_scale,
                    );
                outliers += r.discarded.outliers;
            }
        }
        if let Err(e) = self.film.merge(&pass_film) {
            tracing::error!("pass merge failed: {e}");
        }
        self.finish_pass(start, samples, rejected, outliers)
    }

    /// A pass of the erpt sampler: seeds for about `extent pixels × pixelsamples` traces and
    /// their chains into a pass film, merged into the session film once complete or wrapped
    /// up (then over the seeds done).
    fn render_pass_erpt(&mut self) -> PassStats {
        let start = Instant::now();
        let Some(m) = self.scene.setup.sampler.erpt().map(|p| p.chain_length) else {
            return PassStats::default();
        };
        let seeds = erpt::seeds_per_pass(self.traces_per_pass(), m);
        let mut pass_film = self.empty_pass_film();
        let stops = Stops {
            cancel: &self.cancel,
            wrap_up: &self.wrap_up,
            deadline: self.deadline,
        };
        let Some(state) = self.erpt.as_mut() else {
            return PassStats::default();
        };
        let out = state.run_pass(&self.scene, &self.pool, &stops, seeds, &mut pass_film);
        self.merge_chain_pass(start, out.map(|o| (pass_film, o)))
    }

    /// A pass of the metropolis sampler: `extent pixels × pixelsamples` chain steps into a
    /// pass film, merged into the session film once complete or wrapped up (then over the
    /// steps taken).
    fn render_pass_mlt(&mut self) -> PassStats {
        let start = Instant::now();
        let steps = self.traces_per_pass();
        let mut pass_film = self.empty_pass_film();
        let map = self.map.clone();
        let stops = Stops {
            cancel: &self.cancel,
            wrap_up: &self.wrap_up,
            deadline: self.deadline,
        };
        let Some(state) = self.mlt.as_mut() else {
            return PassStats::default();
        };
        let out = state.run_pass(
            &self.scene,
            &self.pool,
            &stops,
            steps,
            &mut pass_film,
            map.as_ref(),
        );
        self.merge_chain_pass(start, out.map(|o| (pass_film, o)))
    }

    /// Samples traced per pass of a chain sampler: `extent pixels × pixelsamples`, as many
    /// as a pass of the pixel samplers draws ([`extent`]).
    pub(super) fn traces_per_pass(&self) -> u64 {
        let spp = self.scene.setup.sampler.pixel_samples().max(1);
        self.scene.setup.sample_extent().pass_samples(spp)
    }

    /// A cleared film of the session's layout for one chain pass.
    fn empty_pass_film(&self) -> Film {
        let mut f = self.film.clone();
        f.clear();
        f
    }

    /// Merges a chain sampler's pass (its film, complete or wrapped up, and what it did)
    /// into the session film and counts the samples it took; a cancelled pass (`None`) is
    /// discarded. A wrapped-up pass counts as a pass; the pace of passes
    /// ([`Self::passes_within`]) is that of a whole one, extrapolated from its samples.
    fn merge_chain_pass(&mut self, start: Instant, pass: Option<(Film, ChainPass)>) -> PassStats {
        let Some((pass_film, out)) = pass else {
            return cancelled(start);
        };
        if let Err(e) = self.film.merge(&pass_film) {
            tracing::error!("pass merge failed: {e}");
        }
        let mut stats = self.finish_pass(start, out.samples, out.invalid, 0);
        if out.wrapped_up {
            stats.wrapped_up = true;
            let whole = self.traces_per_pass() as f64 / out.samples.max(1) as f64;
            self.pass_seconds = Some(stats.seconds * whole.max(1.0));
        }
        stats
    }

    /// Counts a completed pass: its samples in the film, its discarded samples; then the
    /// sampling map is rebuilt when due.
    fn finish_pass(
        &mut self,
        start: Instant,
        samples: u64,
        rejected: u64,
        outliers: u64,
    ) -> PassStats {
        self.finish_passes(1, start, samples, rejected, outliers)
    }

    /// [`Self::finish_pass`] for a sweep of `passes` passes (no map, so no counts to advance
    /// when there are more than one).
    fn finish_passes(
        &mut self,
        passes: u64,
        start: Instant,
        samples: u64,
        rejected: u64,
        outliers: u64,
    ) -> PassStats {
        self.film.add_sample_count(samples as f64);
        // The film's count (kept in FLM deltas) covers both kinds, as LuxRender's does.
        self.film.add_rejected(rejected + outliers);
        self.rejected += rejected;
        self.outliers += outliers;
        self.advance_counts();
        self.pass += passes;
        self.update_map();
        let seconds = start.elapsed().as_secs_f64();
        self.pass_seconds = Some(seconds / passes as f64);
        PassStats {
            samples,
            rejected,
            outliers,
            seconds,
            passes,
            complete: true,
            wrapped_up: false,
        }
    }
}

/// Renders `list` on the pool, results in `list`'s order; `None` when the pass was cancelled
/// meanwhile (the tiles rendered are then dropped: a pass counts only whole).
///
/// Under a sampling map the tiles' work differs, and every pool thread takes the next tile
/// of the [`schedule`] from a shared counter until none is left (greedy, longest first): a
/// tile holding many of the pass's samples starts early rather than last, where it would
/// leave the other threads idle. Without one, rayon splits the list as it likes (measured
/// 1-2 % faster there than the counter).
fn render_tiles(
    pool: &rayon::ThreadPool,
    scene: &Renderable,
    list: &[Tile],
    ctx: &tile::PassCtx,
    cancel: &AtomicBool,
) -> Option<Vec<tile::TileOut>> {
    use rayon::prelude::*;
    let render = |i: usize| {
        (!cancel.load(Ordering::Relaxed)).then(|| tile::render_tile(scene, &list[i], ctx))
    };
    if ctx.map.is_none() {
        let results: Vec<Option<tile::TileOut>> =
            pool.install(|| (0..list.len()).into_par_iter().map(render).collect());
        return results.into_iter().collect();
    }
    let fp = &scene.setup.film_params;
    let work: Vec<u64> =
        pool.install(|| list.par_iter().map(|t| ctx.tile_samples(fp, t)).collect());
    let order = schedule(&work);
    let next = AtomicUsize::new(0);
    let per_thread: Vec<Vec<(usize, Option<tile::TileOut>)>> = pool.broadcast(|_| {
        let mut done = Vec::new();
        while let Some(&i) = order.get(next.fetch_add(1, Ordering::Relaxed)) {
            done.push((i, render(i)));
        }
        done
    });
    let mut results: Vec<(usize, Option<tile::TileOut>)> =
        per_thread.into_iter().flatten().collect();
    results.sort_unstable_by_key(|r| r.0);
    for (i, r) in &results {
        debug_assert!(
            r.as_ref().is_none_or(|r| r.samples == work[*i]),
            "tile {i}'s plan"
        );
    }
    results.into_iter().map(|r| r.1).collect()
}

/// The order in which to start tiles of the given work (samples): the most first, ties in
/// list order.
fn schedule(work: &[u64]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..work.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(work[i]));
    order
}

/// Adds a tile's film (and depth) at its place.
fn merge_tile(film: &mut Film, depth: Option<&mut ZBuffer>, r: &tile::TileOut) {
    let t = &r.tile;
    // Layouts match by construction; an error here would be a bug, not input.
    if let Err(e) = film.merge_at(&r.film, t.fx0, t.fy0) {
        tracing::error!("tile merge failed: {e}");
    }
    if let (Some(z), Some(tz)) = (depth, r.depth.as_ref()) {
        z.merge_at(tz, t.fx0, t.fy0);
    }
}

/// The stats of a cancelled pass: its time only.
fn cancelled(start: Instant) -> PassStats {
    PassStats {
        seconds: start.elapsed().as_secs_f64(),
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use super::schedule;

    #[test]
    fn tiles_with_more_samples_start_first() {
        assert_eq!(schedule(&[5, 5, 5, 5]), vec![0, 1, 2, 3]);
        assert_eq!(schedule(&[10, 40, 10, 90, 40]), vec![3, 1, 4, 0, 2]);
    }
}
