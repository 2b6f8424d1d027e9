//! A job's error history: its points (time, spp, relative error, failing fraction) and the
//! bounded, evenly thinned list that keeps them (see `super` for the data flow).
//!
//! At most [`MAX_POINTS`] points. Every observation is numbered; while the kept list grows
//! past the bound every second kept point is dropped and from then on only every `stride`-th
//! observation is kept (the stride doubles with each thinning), so the kept points stay evenly
//! spaced over the whole run. The latest observation is always shown, as a tail point, even
//! between two kept ones.

/// Most points of a job's history (kept points plus the latest observation).
pub const MAX_POINTS: usize = 200;

/// One observation of a job's error estimate.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize, utoipa::ToSchema)]
pub struct TradePoint {
    /// Seconds since the job's first lease.
    pub secs: f64,
    /// Merged samples per pixel.
    pub spp: f64,
    /// The film's relative RMS error (of luminance, against the image's mean), estimated from
    /// the previous snapshot.
    pub estimate: f64,
    /// The failing-pixel fraction of the convergence test at this point (0..1).
    pub failing: Option<f64>,
}

/// Which value of the points a fit or projection uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, utoipa::ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum Metric {
    /// `estimate`: the relative error.
    RelativeError,
    /// `failing`: the convergence test's failing fraction (haltthreshold's measure).
    FailingFraction,
}

impl Metric {
    /// The exponent of the metric's decay where theory gives one: -1/2 for the relative
    /// error of an unbiased Monte Carlo estimate; the failing fraction has none.
    pub fn exponent(self) -> Option<f64> {
        match self {
            Metric::RelativeError => Some(-0.5),
            Metric::FailingFraction => None,
        }
    }

    /// The value of `p` this metric reads (None: the point has none).
    pub fn of(self, p: &TradePoint) -> Option<f64> {
        match self {
            Metric::RelativeError => Some(p.estimate),
            Metric::FailingFraction => p.failing,
        }
    }
}

/// A job's error history, bounded and evenly thinned (see the module docs).
#[derive(Clone, Debug)]
pub struct ErrorHistory {
    kept: Vec<TradePoint>,
    /// The latest observation when it was not kept.
    tail: Option<TradePoint>,
    /// Only observations whose number is a multiple of this are kept.
    stride: u64,
    /// Observations accepted so far.
    seen: u64,
}

impl Default for ErrorHistory {
    fn default() -> ErrorHistory {
        ErrorHistory {
            kept: Vec::new(),
            tail: None,
            stride: 1,
            seen: 0,
        }
    }
}

impl ErrorHistory {
    /// Records an observation. Values that are not finite, negative times, spp or estimate,
    /// a failing fraction outside [0, 1], or a time before the latest point are ignored
    /// (false).
    pub fn push(&mut self, p: TradePoint) -> bool {
        let valid = p.secs.is_finite()
            && p.spp.is_finite()
            && p.estimate.is_finite()
            && p.secs >= 0.0
            && p.spp >= 0.0
            && p.estimate >= 0.0
            && p.failing.is_none_or(|f| (0.0..=1.0).contains(&f));
        if !valid || self.last().is_some_and(|l| p.secs < l.secs) {
            return false;
        }
        if self.seen.is_multiple_of(self.stride) {
            self.kept.push(p);
            self.tail = None;
            if self.kept.len() >= MAX_POINTS {
                self.thin();
            }
        } else {
            self.tail = Some(p);
        }
        self.seen += 1;
        true
    }

    /// Drops every second kept point and doubles the stride.
    fn thin(&mut self) {
        self.kept = self.kept.iter().step_by(2).copied().collect();
        self.stride = self.stride.saturating_mul(2);
    }

    /// The latest observation.
    pub fn last(&self) -> Option<&TradePoint> {
        self.tail.as_ref().or(self.kept.last())
    }

    /// The points in time order: the kept ones, then the latest observation if not kept.
    pub fn points(&self) -> Vec<TradePoint> {
        let mut v = self.kept.clone();
        v.extend(self.tail);
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pt(secs: f64, estimate: f64) -> TradePoint {
        TradePoint {
            secs,
            spp: secs * 10.0,
            estimate,
            failing: Some(estimate),
        }
    }

    #[test]
    fn history_is_bounded_and_evenly_thinned() {
        let mut h = ErrorHistory::default();
        for i in 0..10_000u32 {
            assert!(h.push(pt(f64::from(i), 0.5)));
            assert!(
                h.points().len() <= MAX_POINTS,
                "{} points",
                h.points().len()
            );
        }
        let pts = h.points();
        assert!(pts.len() >= MAX_POINTS / 2, "{} points", pts.len());
        // The first observation stays, the latest is shown, and the kept ones are evenly
        // spaced (the stride: a power of two).
        assert_eq!(pts.first().map(|p| p.secs), Some(0.0));
        assert_eq!(pts.last().map(|p| p.secs), Some(9999.0));
        let kept = &pts[..pts.len() - 1];
        let gaps: Vec<f64> = kept.windows(2).map(|w| w[1].secs - w[0].secs).collect();
        assert!(gaps.iter().all(|g| *g == gaps[0]), "{gaps:?}");
        assert!((gaps[0] as u64).is_power_of_two(), "{}", gaps[0]);
    }

    #[test]
    fn history_refuses_bad_points() {
        let mut h = ErrorHistory::default();
        assert!(h.push(pt(2.0, 0.5)));
        assert!(!h.push(pt(1.0, 0.4)), "time going back");
        assert!(!h.push(pt(f64::NAN, 0.4)));
        assert!(!h.push(pt(3.0, f64::INFINITY)));
        assert!(!h.push(pt(3.0, 1.5)));
        assert!(!h.push(pt(-1.0, 0.5)));
        assert_eq!(h.points().len(), 1);
    }
}
