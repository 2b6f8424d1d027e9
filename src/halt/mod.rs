//! The halt rules of a render, in one place for `luxfarm render` and the master: given the
//! film (its samples and spp), the elapsed time and the convergence state, is the render done,
//! and why.
//!
//! The rules are LuxRender's fleximage film's (DESIGN.md):
//! - `haltspp`: done once the film's samples reach haltspp x the pixels of its sample extent
//!   (LuxRender's `samplePerPass`: the image's pixels widened by the pixel filter's width,
//!   which every pass samples; the convention is stated in `crate::render::extent`);
//! - `halttime`: done once the render has run that many seconds;
//! - `haltthreshold`: every `convergencestep` spp the display image (tonemapped, clamped, gamma
//!   applied) is compared with the previous snapshot by Yee's perceptual test
//!   ([`convergence`]); done once the fraction of pixels still changing visibly is at most
//!   the threshold. The first snapshot only starts the comparison.
//!
//! Data flows in from the film and the tonemapper (`film` -> `tonemap` -> here); nothing below
//! imports this module. Callers keep their own loop and bookkeeping: the local render asks
//! [`HaltRules::check`] after every pass; the master asks [`HaltRules::spp_reached`] and
//! [`HaltRules::test_convergence`] after merges (cloning its film only when
//! [`HaltRules::convergence_due`]) and [`HaltRules::time_reached`] on its timer.

pub mod convergence;

pub use convergence::{ConvergenceTest, YeeParams};

use crate::film::{Film, FilmParams};
use crate::tonemap::{tonemap_display, RgbImage, TonemapParams};

/// When a render stops. A rule left `None` never stops it.
#[derive(Clone, Debug, PartialEq)]
pub struct HaltRules {
    /// `haltspp`: samples per pixel.
    pub spp: Option<f64>,
    /// `halttime`: seconds of rendering.
    pub time: Option<f64>,
    /// `haltthreshold`: the largest fraction of pixels that may still fail the convergence
    /// test.
    pub threshold: Option<f64>,
    /// `convergencestep`: spp between two convergence tests.
    pub step: f64,
}

/// Halt rules a render cannot run with.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum HaltError {
    #[error("haltthreshold {0} is not a fraction in [0, 1]")]
    Threshold(f64),
    #[error("haltspp {0} is not a positive number")]
    Spp(f64),
    #[error("halttime {0} is not a positive number of seconds")]
    Time(f64),
}

/// Why a render is done; its `Display` is the reason logs and job records show.
#[derive(Clone, Debug, PartialEq)]
pub enum HaltReason {
    /// `haltspp` reached; the film's spp when it was.
    Spp { haltspp: f64, spp: f64 },
    /// `halttime` reached.
    Time { halttime: f64 },
    /// `haltthreshold` reached; the failing fraction of the last test.
    Threshold { haltthreshold: f64, failing: f64 },
}

impl std::fmt::Display for HaltReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            HaltReason::Spp { haltspp, spp } => {
                write!(f, "haltspp {haltspp} reached ({spp:.2} spp)")
            }
            HaltReason::Time { halttime } => write!(f, "halttime {halttime} s reached"),
            HaltReason::Threshold {
                haltthreshold,
                failing,
            } => write!(
                f,
                "haltthreshold {haltthreshold} reached ({failing:.4} of pixels failing)"
            ),
        }
    }
}

/// The state of the `haltthreshold` test between two checks: the spp of the last test, the
/// running perceptual comparison and its last result.
#[derive(Clone, Debug, Default)]
pub struct Convergence {
    last_spp: f64,
    snapshots: u64,
    test: ConvergenceTest,
    /// Failing-pixel fraction of the last test; `None` until two snapshots were compared.
    pub last_failing: Option<f64>,
}

impl Convergence {
    /// The running perceptual test (its per-pixel noise map and failing pixels).
    pub fn test(&self) -> &ConvergenceTest {
        &self.test
    }
}

impl HaltRules {
    /// The Film statement's rules (`haltspp`, `halttime`, `haltthreshold`,
    /// `convergencestep`).
    pub fn from_film(p: &FilmParams) -> HaltRules {
        HaltRules {
            spp: p.haltspp.map(f64::from),
            time: p.halttime.map(f64::from),
            threshold: p.haltthreshold.map(f64::from),
            step: p.convergence_step,
        }
    }

    /// These rules with each rule given (a command-line option, a job submission's
    /// override) in place of the Film's.
    pub fn with_overrides(
        self,
        spp: Option<f64>,
        time: Option<f64>,
        threshold: Option<f64>,
    ) -> HaltRules {
        HaltRules {
            spp: spp.or(self.spp),
            time: time.or(self.time),
            threshold: threshold.or(self.threshold),
            step: self.step,
        }
    }

    /// Refuses values no render can honour.
    pub fn validate(&self) -> Result<(), HaltError> {
        if let Some(t) = self.threshold.filter(|t| !(0.0..=1.0).contains(t)) {
            return Err(HaltError::Threshold(t));
        }
        if let Some(s) = self.spp.filter(|s| !(s.is_finite() && *s > 0.0)) {
            return Err(HaltError::Spp(s));
        }
        if let Some(t) = self.time.filter(|t| !(t.is_finite() && *t > 0.0)) {
            return Err(HaltError::Time(t));
        }
        Ok(())
    }

    /// True when no rule is set: the render would never stop by itself.
    pub fn is_unbounded(&self) -> bool {
        self.spp.is_none() && self.time.is_none() && self.threshold.is_none()
    }

    /// `haltspp`: `samples` (the film's sample count) against haltspp x `pixels` (the sample
    /// extent's pixels, which a pass samples).
    pub fn spp_reached(&self, samples: f64, pixels: f64) -> Option<HaltReason> {
        let haltspp = self.spp?;
        (samples >= haltspp * pixels).then(|| HaltReason::Spp {
            haltspp,
            spp: if pixels > 0.0 { samples / pixels } else { 0.0 },
        })
    }

    /// `halttime`: `secs` seconds of rendering against the limit.
    pub fn time_reached(&self, secs: f64) -> Option<HaltReason> {
        let halttime = self.time?;
        (secs >= halttime).then_some(HaltReason::Time { halttime })
    }

    /// Whether a convergence test is due at `spp` (`convergencestep` spp after the last).
    pub fn convergence_due(&self, state: &Convergence, spp: f64) -> bool {
        self.threshold.is_some() && spp >= state.last_spp + self.step
    }

    /// Runs the convergence test on the film's display image (call it when
    /// [`HaltRules::convergence_due`]); done when the failing fraction is at most the
    /// threshold. The first snapshot is only kept for the next test.
    pub fn test_convergence(
        &self,
        state: &mut Convergence,
        film: &Film,
        tonemap: &TonemapParams,
    ) -> Option<HaltReason> {
        self.threshold?;
        self.test_convergence_display(state, film.spp(), &tonemap_display(film, tonemap))
    }

    /// As [`HaltRules::test_convergence`], on the film's display image already made
    /// (`tonemap_display`) at `spp`.
    pub fn test_convergence_display(
        &self,
        state: &mut Convergence,
        spp: f64,
        display: &RgbImage,
    ) -> Option<HaltReason> {
        let haltthreshold = self.threshold?;
        state.last_spp = spp;
        let failing = state.test.update(display);
        state.snapshots += 1;
        if state.snapshots < 2 {
            return None;
        }
        state.last_failing = Some(failing);
        (failing <= haltthreshold).then_some(HaltReason::Threshold {
            haltthreshold,
            failing,
        })
    }

    /// Passes of `pass_samples` samples each that may run before a rule needs checking
    /// again: until `haltspp` (counted as [`Self::spp_reached`] counts, over `pass_pixels`)
    /// and until the next convergence test (at least 1). `None` when neither rule is set;
    /// `halttime` is for the caller to bound (`crate::render::Session::passes_within`).
    pub fn passes_until_check(
        &self,
        state: &Convergence,
        film: &Film,
        pass_pixels: f64,
        pass_samples: f64,
    ) -> Option<u64> {
        let passes = |samples_left: f64| {
            if pass_samples > 0.0 && samples_left.is_finite() {
                (samples_left / pass_samples).ceil().max(1.0) as u64
            } else {
                1
            }
        };
        let to_spp = self
            .spp
            .map(|haltspp| passes(haltspp * pass_pixels - film.total_samples()));
        let buffer_pixels = film.pixel_count() as f64;
        let to_test = self
            .threshold
            .map(|_| passes((state.last_spp + self.step - film.spp()) * buffer_pixels));
        match (to_spp, to_test) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Every rule at once, as a local render asks after each pass: haltspp (against
    /// `pass_pixels`, the sample extent's pixels), halttime, then (when due) the convergence
    /// test.
    pub fn check(
        &self,
        state: &mut Convergence,
        film: &Film,
        tonemap: &TonemapParams,
        secs: f64,
        pass_pixels: f64,
    ) -> Option<HaltReason> {
        self.spp_reached(film.total_samples(), pass_pixels)
            .or_else(|| self.time_reached(secs))
            .or_else(|| {
                self.convergence_due(state, film.spp())
                    .then(|| self.test_convergence(state, film, tonemap))
                    .flatten()
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rules(spp: Option<f64>, time: Option<f64>, threshold: Option<f64>) -> HaltRules {
        HaltRules {
            spp,
            time,
            threshold,
            step: 4.0,
        }
    }

    /// A 2x1 film with `passes` samples per pixel of a constant value.
    fn film(passes: u32) -> Film {
        let mut f = Film::new(2, 1, vec![]);
        for _ in 0..passes {
            for x in 0..2 {
                f.add_splat(0, x, 0, [0.5, 0.5, 0.5], 1.0, 1.0);
            }
            f.add_sample_count(2.0);
        }
        f
    }

    #[test]
    fn haltspp_counts_samples_against_pixels() {
        let r = rules(Some(3.0), None, None);
        assert_eq!(r.spp_reached(5.0, 2.0), None);
        assert_eq!(
            r.spp_reached(6.0, 2.0),
            Some(HaltReason::Spp {
                haltspp: 3.0,
                spp: 3.0
            })
        );
        let mut c = Convergence::default();
        let tp = TonemapParams::default();
        assert_eq!(r.check(&mut c, &film(2), &tp, 0.0, 2.0), None);
        let reason = r.check(&mut c, &film(3), &tp, 0.0, 2.0).unwrap();
        assert_eq!(reason.to_string(), "haltspp 3 reached (3.00 spp)");
        // Counted against the sample extent's pixels (here 3, wider than the film's 2).
        assert_eq!(r.check(&mut c, &film(4), &tp, 0.0, 3.0), None);
        assert!(r.check(&mut c, &film(5), &tp, 0.0, 3.0).is_some());
    }

    /// Sweeps stop where haltspp is reached and where the next convergence test is due.
    #[test]
    fn passes_until_check_stops_at_haltspp_and_the_next_test() {
        let c = Convergence::default();
        // haltspp 10 over 3 extent pixels: 30 samples; 2 of them taken, 3 a pass.
        let r = rules(Some(10.0), None, None);
        assert_eq!(r.passes_until_check(&c, &film(1), 3.0, 3.0), Some(10));
        // Reached or passed: still one pass (the caller checks the rules first).
        assert_eq!(r.passes_until_check(&c, &film(20), 3.0, 3.0), Some(1));
        // The convergence test every 4 spp of the 2-pixel film: 8 samples, 2 a pass.
        let t = rules(None, None, Some(0.1));
        assert_eq!(t.passes_until_check(&c, &film(1), 2.0, 2.0), Some(3));
        let both = rules(Some(100.0), None, Some(0.1));
        assert_eq!(both.passes_until_check(&c, &film(1), 2.0, 2.0), Some(3));
        assert_eq!(
            rules(None, Some(5.0), None).passes_until_check(&c, &film(1), 2.0, 2.0),
            None
        );
    }

    #[test]
    fn halttime_and_precedence() {
        let r = rules(Some(10.0), Some(2.5), None);
        assert_eq!(r.time_reached(2.4), None);
        assert_eq!(
            r.time_reached(2.5).map(|h| h.to_string()),
            Some("halttime 2.5 s reached".into())
        );
        let mut c = Convergence::default();
        let tp = TonemapParams::default();
        assert!(matches!(
            r.check(&mut c, &film(1), &tp, 3.0, 2.0),
            Some(HaltReason::Time { .. })
        ));
        // haltspp is reported first when both hold
        assert!(matches!(
            r.check(&mut c, &film(10), &tp, 3.0, 2.0),
            Some(HaltReason::Spp { .. })
        ));
    }

    #[test]
    fn threshold_tests_every_step_and_needs_two_snapshots() {
        let r = rules(None, None, Some(0.0));
        let tp = TonemapParams::default();
        let mut c = Convergence::default();
        assert!(!r.convergence_due(&c, 3.9));
        assert!(r.convergence_due(&c, 4.0));
        // a constant film: the first snapshot only starts the comparison
        assert_eq!(r.check(&mut c, &film(4), &tp, 0.0, 2.0), None);
        assert_eq!(c.last_failing, None);
        assert!(!r.convergence_due(&c, 7.0));
        assert_eq!(r.check(&mut c, &film(7), &tp, 0.0, 2.0), None);
        // the second compares with the first: identical, nothing fails
        let reason = r.check(&mut c, &film(8), &tp, 0.0, 2.0).unwrap();
        assert_eq!(c.last_failing, Some(0.0));
        assert!(reason.to_string().starts_with("haltthreshold 0 reached"));
        // without a threshold no test is ever due
        assert!(!rules(Some(1.0), None, None).convergence_due(&Convergence::default(), 100.0));
    }

    #[test]
    fn overrides_and_validation() {
        let mut p = FilmParams::with_resolution(4, 4);
        p.haltspp = Some(8);
        p.haltthreshold = Some(0.1);
        let r = HaltRules::from_film(&p);
        assert_eq!(
            (r.spp, r.time, r.threshold, r.step),
            (Some(8.0), None, Some(0.1f32 as f64), 32.0)
        );
        let r = r.with_overrides(None, Some(5.0), Some(0.5));
        assert_eq!(
            (r.spp, r.time, r.threshold),
            (Some(8.0), Some(5.0), Some(0.5))
        );
        assert!(r.validate().is_ok());
        assert!(!r.is_unbounded());
        assert!(HaltRules::from_film(&FilmParams::with_resolution(4, 4)).is_unbounded());
        assert_eq!(
            rules(None, None, Some(2.0)).validate(),
            Err(HaltError::Threshold(2.0))
        );
        assert_eq!(
            rules(Some(f64::NAN), None, None)
                .validate()
                .map_err(|e| e.to_string()),
            Err("haltspp NaN is not a positive number".into())
        );
        assert!(rules(None, Some(0.0), None).validate().is_err());
    }
}
