//! Building noise-aware sampling maps from a film, for the local render driver (the
//! [`super::Session`] of a `noiseaware` sampler) and for the farm's master (its merged film),
//! as LuxRender 1.x's film does (`FlexImageFilm::ConvUpdateThreadImpl`,
//! `Film::GenerateNoiseAwareMap`).
//!
//! ```text
//! film's variance sums (crate::film::variance) --per pixel--> standard deviation of one
//!   contribution's luminance --\
//! film --tonemap_display--> threshold versus intensity (crate::halt::convergence::tvi_map) --+
//!   --> SamplingMap::from_deviation --> session / wire
//! ```
//!
//! **When.** The first map is built once the film has `convergencestep` spp (the Film
//! parameter, LuxRender's default 32, at least 4), and the step doubles after every map: maps
//! at 32, 96, 224, 480, ... spp with the defaults, as LuxRender's `noiseAwareStep` doubles. A
//! pixel's spread of single contributions settles as samples arrive (it does not shrink with
//! their number, unlike the error of the pixel's mean), so an early map stays good and later
//! ones refine it. Until the first map, and while some pixel has no contribution yet,
//! sampling is uniform.
//!
//! **Threshold.** LuxRender takes each pixel's threshold from its last convergence test,
//! which compares two display images and adapts to their mean; luxfarm computes it from the
//! display image the map is built at, so a map needs no earlier test.
//!
//! Why a map built from the pixels' own samples does not bias the image, and where it is only
//! consistent, is said in `crate::sampler::map`.

use crate::film::Film;
use crate::halt::convergence::tvi_map;
use crate::halt::YeeParams;
use crate::sampler::map::SamplingMap;
use crate::tonemap::{tonemap_display, TonemapParams};

/// When the next map of a film is due, and how many were built.
#[derive(Clone, Debug)]
pub struct MapBuilder {
    /// Spp the film must gain before the next map (doubles after each).
    step: f64,
    last_spp: f64,
    version: u64,
}

impl MapBuilder {
    /// A builder whose first map is due at `step` spp (`convergencestep`; at least 1).
    pub fn new(step: f64) -> MapBuilder {
        MapBuilder {
            step: if step.is_finite() {
                step.max(1.0)
            } else {
                32.0
            },
            last_spp: 0.0,
            version: 0,
        }
    }

    /// Whether a film at `spp` is due for a new map.
    pub fn due(&self, spp: f64) -> bool {
        spp >= self.last_spp + self.step
    }

    /// Builds the map of `film` from its variance sums and its display image, and doubles
    /// the step to the next. `None` (sampling stays as it is, the version too) for a film
    /// without variance sums, with a pixel no contribution has reached yet, or without
    /// noise or threshold (see [`SamplingMap::from_deviation`]).
    pub fn update(&mut self, film: &Film, tonemap: &TonemapParams) -> Option<SamplingMap> {
        self.last_spp = film.spp();
        self.step *= 2.0;
        let sigma = film.variance()?.deviations()?;
        let tvi = tvi_map(&tonemap_display(film, tonemap), &YeeParams::default());
        match SamplingMap::from_deviation(&sigma, &tvi, film.width(), film.height()) {
            Ok(Some(m)) => {
                self.version += 1;
                Some(m)
            }
            Ok(None) => {
                tracing::debug!("no noise information yet: the sampling map stays as it is");
                None
            }
            Err(e) => {
                tracing::warn!("no sampling map: {e}");
                None
            }
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
    use crate::film::VarianceBuffer;

    /// A grey film whose pixels left of `split` get contributions spread by `noisy` and the
    /// others a constant, `spp` per pixel.
    fn film(w: u32, h: u32, split: u32, noisy: f32, spp: u32) -> Film {
        let mut f = Film::new(w, h, vec![]);
        f.set_variance(Some(VarianceBuffer::new(w, h))).unwrap();
        for y in 0..h {
            for x in 0..w {
                for k in 0..spp {
                    let d = if x < split && k % 2 == 0 { noisy } else { 0.0 };
                    let v = 0.3 + d - if x < split && k % 2 == 1 { noisy } else { 0.0 };
                    f.add_splat(0, x, y, [v, v, v], 1.0, 1.0);
                    f.add_variance(x, y, v, 1.0);
                }
            }
        }
        f.add_sample_count(f64::from(w * h * spp));
        f
    }

    #[test]
    fn maps_are_due_on_a_doubling_schedule() {
        let tm = TonemapParams::default();
        let mut b = MapBuilder::new(32.0);
        assert!(!b.due(31.0) && b.due(32.0));
        assert!(b.update(&film(40, 20, 20, 0.2, 32), &tm).is_some());
        // next at 32 + 64, then 96 + 128
        assert!(!b.due(95.0) && b.due(96.0));
        assert!(b.update(&film(40, 20, 20, 0.2, 96), &tm).is_some());
        assert!(!b.due(223.0) && b.due(224.0));
        assert_eq!(b.version(), 2);
    }

    /// A film without noise gives no new map: sampling keeps the last one, and the
    /// version stays (LuxRender's `GenerateNoiseAwareMap` does not bump it either).
    #[test]
    fn a_film_without_noise_keeps_the_last_map() {
        let tm = TonemapParams::default();
        let mut b = MapBuilder::new(4.0);
        assert!(b.update(&film(40, 20, 20, 0.2, 8), &tm).is_some());
        assert_eq!(b.version(), 1);
        assert!(b.update(&film(40, 20, 20, 0.0, 24), &tm).is_none());
        assert_eq!(b.version(), 1);
        // and the schedule still doubles
        assert!(!b.due(24.0 + 15.9) && b.due(24.0 + 16.0));
    }

    #[test]
    fn the_map_follows_the_spread_of_the_contributions() {
        let tm = TonemapParams::default();
        let (w, h) = (64u32, 32u32);
        let m = MapBuilder::new(4.0)
            .update(&film(w, h, 32, 0.2, 8), &tm)
            .expect("a map");
        let half = |x0: u32, x1: u32| -> f32 {
            (0..h)
                .flat_map(|y| (x0..x1).map(move |x| (x, y)))
                .map(|(x, y)| m.density(x, y))
                .sum::<f32>()
        };
        // well inside each half (the box filter blends 6 pixels either side of the edge)
        let (left, right) = (half(0, 25), half(39, 64));
        assert!(left > 5.0 * right, "left {left} right {right}");
    }

    #[test]
    fn no_map_without_variance_sums_or_before_every_pixel_has_one() {
        let tm = TonemapParams::default();
        let mut plain = Film::new(8, 8, vec![]);
        plain.add_sample_count(64.0);
        assert!(MapBuilder::new(4.0).update(&plain, &tm).is_none());
        let mut f = film(8, 8, 4, 0.2, 4);
        let mut v = VarianceBuffer::new(8, 8);
        v.add(0, 0, 0.5, 1.0);
        f.set_variance(Some(v)).unwrap();
        assert!(MapBuilder::new(4.0).update(&f, &tm).is_none());
    }
}
