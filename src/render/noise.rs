//! Building noise-aware sampling maps from a film, for the local render driver (the
//! [`super::Session`] of a `noiseaware` sampler) and for the farm's master (its merged film).
//!
//! ```text
//! film --every convergencestep spp: tonemap_display--> ConvergenceTest (crate::halt)
//!   --per-pixel noise (from the second test on)--> memory: max(noise, remembered × 0.85)
//!   --> SamplingMap::from_noise --> session / wire
//! ```
//!
//! The map is rebuilt whenever the film's spp has grown by `convergencestep` (the Film
//! parameter, LuxRender's default 32, at least 4) since the last rebuild, as LuxRender updates
//! its noise-aware map with its convergence test. A local render thus rebuilds it every
//! N = ceil(convergencestep / pixelsamples) passes (8 passes with the defaults), the first
//! map after the second test (the first only gives the test its reference image). Until then
//! sampling is uniform.
//!
//! The map is built from a memory of the tests, not from the last one alone: a pixel that
//! changed visibly keeps its noise, fading by [`MEMORY_DECAY`] a test, so a pixel lit by
//! rare paths is not taken for converged the first time a test finds it quiet (the bias
//! this avoids is explained in `crate::sampler::map`).

use crate::film::Film;
use crate::halt::{ConvergenceTest, YeeParams};
use crate::sampler::map::{SamplingMap, NOISE_CAP};
use crate::tonemap::{tonemap_display, TonemapParams};

/// How much of a pixel's remembered noise is left one test later: a pixel that changed
/// visibly keeps a raised density for a while (noise 16 fades to 1 in 17 tests) instead of
/// dropping back the moment one test finds it unchanged.
pub const MEMORY_DECAY: f32 = 0.85;

/// The running convergence test behind a sampling map, and when it is next due.
#[derive(Clone, Debug)]
pub struct MapBuilder {
    test: ConvergenceTest,
    step: f64,
    last_spp: f64,
    tests: u64,
    version: u64,
    /// Per pixel, the noise the map was last built from, fading by [`MEMORY_DECAY`] a test.
    memory: Vec<f32>,
}

impl MapBuilder {
    /// A builder testing every `step` spp (`convergencestep`; at least 1).
    pub fn new(step: f64) -> MapBuilder {
        MapBuilder {
            test: ConvergenceTest::new(YeeParams::default()),
            step: if step.is_finite() {
                step.max(1.0)
            } else {
                32.0
            },
            last_spp: 0.0,
            tests: 0,
            version: 0,
            memory: Vec::new(),
        }
    }

    /// Whether a film at `spp` is due for a new map.
    pub fn due(&self, spp: f64) -> bool {
        spp >= self.last_spp + self.step
    }

    /// Runs the convergence test on `film` and returns the new map (`None` after the first
    /// test, which only keeps its image, or for an empty film).
    pub fn update(&mut self, film: &Film, tonemap: &TonemapParams) -> Option<SamplingMap> {
        self.last_spp = film.spp();
        self.test.update(&tonemap_display(film, tonemap));
        self.tests += 1;
        if self.tests < 2 {
            return None;
        }
        self.remember();
        let map = SamplingMap::from_noise(&self.memory, film.width(), film.height());
        match map {
            Ok(m) => {
                self.version += 1;
                Some(m)
            }
            Err(e) => {
                tracing::warn!("no sampling map: {e}");
                None
            }
        }
    }

    /// Folds the last test's noise into the memory: each pixel keeps the larger of its new
    /// noise and its remembered noise faded by [`MEMORY_DECAY`].
    fn remember(&mut self) {
        let noise = self.test.noise_map();
        let capped = noise.iter().map(|v| {
            if v.is_nan() {
                NOISE_CAP
            } else {
                v.clamp(0.0, NOISE_CAP)
            }
        });
        if self.memory.len() != noise.len() {
            self.memory = capped.collect();
            return;
        }
        for (m, n) in self.memory.iter_mut().zip(capped) {
            *m = n.max(*m * MEMORY_DECAY);
        }
    }

    /// Maps built so far (the version of the last one).
    pub fn version(&self) -> u64 {
        self.version
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A film whose left half flickers between two values from one snapshot to the next
    /// while its right half stays put.
    fn film(w: u32, h: u32, round: u32) -> Film {
        let mut f = Film::new(w, h, vec![]);
        for y in 0..h {
            for x in 0..w {
                let v = if x < w / 2 && (x + y + round).is_multiple_of(2) {
                    0.9
                } else {
                    0.3
                };
                f.add_splat(0, x, y, [v, v, v], 1.0, 1.0);
            }
        }
        f.add_sample_count(f64::from(w * h) * 4.0 * f64::from(round + 1));
        f
    }

    /// A film of uniform grey with one pixel's value set.
    fn film_with(w: u32, h: u32, at: (u32, u32), v: f32, spp: f64) -> Film {
        let mut f = Film::new(w, h, vec![]);
        for y in 0..h {
            for x in 0..w {
                let c = if (x, y) == at { v } else { 0.3 };
                f.add_splat(0, x, y, [c, c, c], 1.0, 1.0);
            }
        }
        f.add_sample_count(f64::from(w * h) * spp);
        f
    }

    #[test]
    fn a_pixels_noise_fades_over_tests_instead_of_vanishing() {
        let tm = TonemapParams::default();
        let mut b = MapBuilder::new(4.0);
        let (w, h) = (40, 40);
        b.update(&film_with(w, h, (20, 20), 0.3, 4.0), &tm);
        // The pixel changes once ...
        let changed = b.update(&film_with(w, h, (20, 20), 0.9, 8.0), &tm).unwrap();
        let peak = changed.density(20, 20);
        assert!(peak > 2.0, "{peak}");
        // ... then holds still: its density stays raised, falling test by test.
        let mut last = peak;
        for k in 0..3 {
            let m = b.update(
                &film_with(w, h, (20, 20), 0.9, 12.0 + 4.0 * f64::from(k)),
                &tm,
            );
            let d = m.unwrap().density(20, 20);
            assert!(d > 1.5, "test {k}: {d}");
            assert!(d <= last * 1.0001, "test {k}: {d} after {last}");
            last = d;
        }
    }

    #[test]
    fn the_map_follows_the_changing_half_after_the_second_test() {
        let tm = TonemapParams::default();
        let mut b = MapBuilder::new(4.0);
        assert!(b.due(4.0) && !b.due(3.0));
        assert!(b.update(&film(32, 16, 0), &tm).is_none());
        assert!(!b.due(4.0));
        let m = b.update(&film(32, 16, 1), &tm).expect("a map");
        assert_eq!(b.version(), 1);
        let half = |x0: u32, x1: u32| -> f32 {
            (0..16)
                .flat_map(|y| (x0..x1).map(move |x| (x, y)))
                .map(|(x, y)| m.density(x, y))
                .sum::<f32>()
        };
        let (left, right) = (half(0, 16), half(16, 32));
        assert!(left > 3.0 * right, "left {left} right {right}");
    }
}
