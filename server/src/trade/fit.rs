//! The power-law fit of a history and the projected time to a target, with the reasons there
//! is no projection (too few points, no downward trend, too noisy, out of reach). Nothing it
//! returns is NaN.
//!
//! On the recent points, in log–log space: a least-squares line first says whether the value
//! falls at all (its slope below [`MAX_EXPONENT`]). The model then is value = c t^b with b the
//! metric's own exponent where theory gives one — -1/2 for the relative error of an unbiased
//! Monte Carlo render, which is steadier than a slope fitted to a few jumpy points (fireflies
//! move the estimate by tens of percent) — and the fitted slope otherwise (the failing
//! fraction); c is the geometric mean that fits the points best for that b. The points'
//! scatter about the model (RMS of the log residuals) above [`MAX_SCATTER`] is "noisy".

use super::history::{Metric, TradePoint};

/// The fit uses this many of the most recent points, or more when those span less than
/// [`MIN_TIME_SPAN`] (a history not thinned yet holds a point every half second, so 24 points
/// late in a long render cover too short a span to fit).
pub const FIT_POINTS: usize = 24;
/// Fewer usable points than this are "not enough data".
pub const MIN_FIT_POINTS: usize = 5;
/// The fitted points must span at least this ratio of times (last / first): the fit is in
/// log time, where a short span says nothing about the slope.
pub const MIN_TIME_SPAN: f64 = 1.2;
/// An exponent at or above this is no downward trend (a flat or rising estimate).
pub const MAX_EXPONENT: f64 = -0.02;
/// Points scattering about the model by more than this (RMS of the natural-log residuals, a
/// factor of 1.35) are too noisy to project.
pub const MAX_SCATTER: f64 = 0.3;
/// A projected time beyond this many seconds (about 30 years) is reported as unreachable.
pub const HORIZON_SECS: f64 = 1e9;

/// estimate = coefficient x secs^exponent, fitted on the recent history.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, utoipa::ToSchema)]
pub struct PowerFit {
    pub exponent: f64,
    pub coefficient: f64,
    /// RMS of the points' natural-log residuals about the model.
    pub scatter: f64,
    /// Points the fit used.
    pub points: usize,
}

impl PowerFit {
    /// The time (seconds since the first lease) at which the fit reaches `target`.
    fn time_of(&self, target: f64) -> f64 {
        ((target.ln() - self.coefficient.ln()) / self.exponent).exp()
    }
}

/// Why a projection could or could not be made.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, utoipa::ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum ProjectionStatus {
    /// The fit reaches the target at `at_secs`.
    Projected,
    /// The latest estimate is at or below the target already.
    Reached,
    /// Too few usable points, or too short a span of time, to fit.
    NotEnoughData,
    /// The estimate does not fall over the recent points.
    NoTrend,
    /// The points scatter too much about the fit.
    Noisy,
    /// The fit never reaches the target within [`HORIZON_SECS`] (or the target is 0).
    Unreachable,
}

/// The projected time to a target value of one metric.
#[derive(Clone, Debug, PartialEq, serde::Serialize, utoipa::ToSchema)]
pub struct Projection {
    pub metric: Metric,
    /// The target (the job's haltthreshold for the failing fraction, or the relative error
    /// asked for).
    pub target: f64,
    pub status: ProjectionStatus,
    /// Seconds since the first lease when the target is reached (projected or reached).
    pub at_secs: Option<f64>,
    /// Seconds from the latest point to `at_secs` (0 once reached).
    pub remaining_secs: Option<f64>,
    pub fit: Option<PowerFit>,
}

/// The recent points usable in log–log space (time and value above 0): the last
/// [`FIT_POINTS`], and earlier ones as far back as it takes to span [`MIN_TIME_SPAN`].
fn usable(points: &[TradePoint], metric: Metric) -> Vec<(f64, f64)> {
    let usable: Vec<(f64, f64)> = points
        .iter()
        .filter_map(|p| Some((p.secs, metric.of(p)?)))
        .filter(|(t, v)| *t > 0.0 && *v > 0.0)
        .map(|(t, v)| (t.ln(), v.ln()))
        .collect();
    let mut from = usable.len().saturating_sub(FIT_POINTS);
    if let Some(&(last, _)) = usable.last() {
        while from > 0
            && usable
                .get(from)
                .is_some_and(|p| last - p.0 < MIN_TIME_SPAN.ln())
        {
            from -= 1;
        }
    }
    usable.get(from..).map(<[_]>::to_vec).unwrap_or_default()
}

/// Least squares of ln(value) against ln(secs) on the recent points; the status says why
/// there is no usable fit.
pub fn fit(points: &[TradePoint], metric: Metric) -> Result<PowerFit, ProjectionStatus> {
    let xy = usable(points, metric);
    let n = xy.len();
    let (Some(first), Some(last)) = (xy.first(), xy.last()) else {
        return Err(ProjectionStatus::NotEnoughData);
    };
    if n < MIN_FIT_POINTS || last.0 - first.0 < MIN_TIME_SPAN.ln() {
        return Err(ProjectionStatus::NotEnoughData);
    }
    let nf = n as f64;
    let mx = xy.iter().map(|p| p.0).sum::<f64>() / nf;
    let my = xy.iter().map(|p| p.1).sum::<f64>() / nf;
    let sxx: f64 = xy.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = xy.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    if sxx <= 0.0 || !sxx.is_finite() {
        return Err(ProjectionStatus::NotEnoughData);
    }
    let slope = sxy / sxx;
    if !slope.is_finite() || slope >= MAX_EXPONENT {
        return Err(ProjectionStatus::NoTrend);
    }
    let exponent = metric.exponent().unwrap_or(slope);
    let log_c = my - exponent * mx;
    let scatter = (xy
        .iter()
        .map(|p| (p.1 - log_c - exponent * p.0).powi(2))
        .sum::<f64>()
        / nf)
        .sqrt();
    if scatter.is_nan() || scatter > MAX_SCATTER {
        return Err(ProjectionStatus::Noisy);
    }
    let coefficient = log_c.exp();
    if !(coefficient.is_finite() && coefficient > 0.0) {
        return Err(ProjectionStatus::Unreachable);
    }
    Ok(PowerFit {
        exponent,
        coefficient,
        scatter,
        points: n,
    })
}

/// The projected time to `target` of `metric` from the history's points (in time order).
pub fn project(points: &[TradePoint], metric: Metric, target: f64) -> Projection {
    let mut p = Projection {
        metric,
        target,
        status: ProjectionStatus::NotEnoughData,
        at_secs: None,
        remaining_secs: None,
        fit: None,
    };
    let Some((last_secs, last_value)) = points
        .iter()
        .rev()
        .find_map(|q| Some((q.secs, metric.of(q)?)))
    else {
        return p;
    };
    if last_value <= target {
        p.status = ProjectionStatus::Reached;
        p.at_secs = Some(last_secs);
        p.remaining_secs = Some(0.0);
        return p;
    }
    let f = match fit(points, metric) {
        Ok(f) => f,
        Err(status) => {
            p.status = status;
            return p;
        }
    };
    p.fit = Some(f);
    let at = if target > 0.0 {
        f.time_of(target)
    } else {
        f64::INFINITY
    };
    if at.is_finite() && at <= HORIZON_SECS {
        p.status = ProjectionStatus::Projected;
        p.at_secs = Some(at);
        p.remaining_secs = Some((at - last_secs).max(0.0));
    } else {
        p.status = ProjectionStatus::Unreachable;
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    const REL: Metric = Metric::RelativeError;

    fn pt(secs: f64, estimate: f64) -> TradePoint {
        TradePoint {
            secs,
            spp: secs * 10.0,
            estimate,
            failing: Some(estimate),
        }
    }

    /// estimate = c t^-1/2 at t = 1, 2, ..., n seconds.
    fn sqrt_series(c: f64, n: usize) -> Vec<TradePoint> {
        (1..=n)
            .map(|i| pt(i as f64, c / (i as f64).sqrt()))
            .collect()
    }

    #[test]
    fn a_long_dense_history_still_projects() {
        // A point every half second for 83 s (a history not thinned yet): the last 24 points
        // span 71.5..83 s, too short alone, so the fit reaches back to span 1.2.
        let pts: Vec<TradePoint> = (1..=166)
            .map(|i| {
                let t = i as f64 * 0.5;
                pt(t, 0.5 / t.sqrt())
            })
            .collect();
        let f = fit(&pts, REL).expect("a fit");
        assert!((f.coefficient - 0.5).abs() < 1e-9, "{f:?}");
        assert!(f.points > FIT_POINTS, "{f:?}");
        let first = pts[pts.len() - f.points].secs;
        assert!(83.0 / first >= MIN_TIME_SPAN, "{first}");
        assert!(
            83.0 / (first + 0.5) < MIN_TIME_SPAN,
            "no more points than the span needs"
        );
    }

    #[test]
    fn a_sqrt_series_projects_the_right_time() {
        // 0.5 / sqrt(t) reaches 0.01 at t = 2500 s.
        let pts = sqrt_series(0.5, 60);
        let f = fit(&pts, REL).unwrap();
        assert!((f.exponent + 0.5).abs() < 1e-9, "{f:?}");
        assert!((f.coefficient - 0.5).abs() < 1e-9, "{f:?}");
        assert!(f.scatter < 1e-9, "{f:?}");
        let p = project(&pts, REL, 0.01);
        assert_eq!(p.status, ProjectionStatus::Projected);
        let at = p.at_secs.unwrap();
        assert!((at - 2500.0).abs() < 1e-6, "{p:?}");
        assert!((p.remaining_secs.unwrap() - 2440.0).abs() < 1e-6, "{p:?}");
        // only the recent points are fitted
        assert_eq!(f.points, FIT_POINTS);
        // a steeper early phase does not bend the projection of the recent points
        let mut bent: Vec<TradePoint> = (1..=30).map(|i| pt(f64::from(i) / 100.0, 0.9)).collect();
        bent.extend(sqrt_series(0.5, 60));
        let q = project(&bent, REL, 0.01);
        assert!((q.at_secs.unwrap() - 2500.0).abs() < 1e-6, "{q:?}");
    }

    #[test]
    fn the_relative_error_keeps_the_monte_carlo_exponent() {
        // a jumpy t^-1/2 series (a firefly raises every fifth point by 30 %) projects as t^-1/2
        let pts: Vec<TradePoint> = (1..=30)
            .map(|i| {
                let jump = if i % 5 == 0 { 1.3 } else { 1.0 };
                pt(f64::from(i), jump * 2.0 / f64::from(i).sqrt())
            })
            .collect();
        let f = fit(&pts, REL).unwrap();
        assert_eq!(f.exponent, -0.5);
        let p = project(&pts, REL, 0.02);
        assert_eq!(p.status, ProjectionStatus::Projected);
        // 2 t^-1/2 reaches 0.02 at 10^4 s; the jumps raise the coefficient a little
        let at = p.at_secs.unwrap();
        assert!((10_000.0..12_000.0).contains(&at), "{p:?}");
        // the failing fraction's exponent is the fitted slope
        let g = fit(&pts, Metric::FailingFraction).unwrap();
        assert!(
            g.exponent != -0.5 && (g.exponent + 0.5).abs() < 0.1,
            "{g:?}"
        );
    }

    #[test]
    fn a_reached_target_is_reached_now() {
        let pts = sqrt_series(0.5, 10);
        let p = project(&pts, REL, 0.2);
        assert_eq!(p.status, ProjectionStatus::Reached);
        assert_eq!(p.at_secs, Some(10.0));
        assert_eq!(p.remaining_secs, Some(0.0));
    }

    #[test]
    fn short_flat_and_noisy_series_give_no_projection() {
        let check = |pts: &[TradePoint], want: ProjectionStatus| {
            let p = project(pts, REL, 0.001);
            assert_eq!(p.status, want, "{p:?}");
            assert_eq!(p.at_secs, None);
            assert_eq!(p.remaining_secs, None);
            // never NaN in the JSON
            let json = serde_json::to_string(&p).unwrap();
            assert!(!json.contains("NaN") && !json.contains("null,\"fit\":{\"exponent\":null"));
        };
        check(&[], ProjectionStatus::NotEnoughData);
        check(&sqrt_series(0.5, 4), ProjectionStatus::NotEnoughData);
        // many points within a few percent of time
        let tight: Vec<TradePoint> = (0..20).map(|i| pt(100.0 + f64::from(i), 0.5)).collect();
        check(&tight, ProjectionStatus::NotEnoughData);
        // points at time 0 or estimate 0 are not usable in log space
        let zeros: Vec<TradePoint> = (0..20).map(|_| pt(0.0, 0.5)).collect();
        check(&zeros, ProjectionStatus::NotEnoughData);
        let flat: Vec<TradePoint> = (1..=30).map(|i| pt(f64::from(i), 0.3)).collect();
        check(&flat, ProjectionStatus::NoTrend);
        let rising: Vec<TradePoint> = (1..=30)
            .map(|i| pt(f64::from(i), 0.01 * f64::from(i)))
            .collect();
        check(&rising, ProjectionStatus::NoTrend);
        // a falling trend buried in noise (a fixed pseudo-random sequence)
        let mut s = 12345u64;
        let noisy: Vec<TradePoint> = (1..=30)
            .map(|i| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let r = (s >> 33) as f64 / (1u64 << 31) as f64; // 0..1
                pt(
                    f64::from(i),
                    (0.5 / f64::from(i).powf(0.05)) * (0.2 + 1.6 * r),
                )
            })
            .collect();
        let f = fit(&noisy, REL);
        assert!(
            matches!(f, Err(ProjectionStatus::Noisy | ProjectionStatus::NoTrend)),
            "{f:?}"
        );
    }

    #[test]
    fn a_zero_target_or_a_slow_decay_is_unreachable() {
        let pts = sqrt_series(0.5, 30);
        let p = project(&pts, REL, 0.0);
        assert_eq!(p.status, ProjectionStatus::Unreachable);
        assert_eq!(p.at_secs, None);
        // t^-0.05 from 0.9 needs far more than the horizon to reach 1e-6 (the failing
        // fraction: its exponent is the fitted one)
        let slow: Vec<TradePoint> = (1..=30)
            .map(|i| pt(f64::from(i), 0.9 * f64::from(i).powf(-0.05)))
            .collect();
        let p = project(&slow, Metric::FailingFraction, 1e-6);
        assert_eq!(p.status, ProjectionStatus::Unreachable, "{p:?}");
    }
}
