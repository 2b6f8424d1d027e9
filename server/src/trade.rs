//! The speed/accuracy trade of a running job: an error estimate over time, a power-law fit of
//! it, the projected time to a target error, and the convergence map as a picture.
//!
//! ```text
//! merge --halt::after_merge--> convergence test every convergencestep spp (the haltthreshold
//!   test of `luxfarm::halt`, or this module's own test for jobs without a threshold)
//!   --copy of the merged film, failing fraction--> TradeState::observe
//!   --relative error against the previous snapshot--> ErrorHistory::push
//!      (secs since the first lease, merged spp, relative error, failing fraction)
//! views: ErrorHistory::points --project(metric, target)--> Projection (fit on recent points)
//!        the last test's per-pixel noise --overlay_png--> convergence.png
//! ```
//!
//! Two estimates are kept per point:
//! - the **relative error** of the merged film, from two nested snapshots: the film's
//!   luminance at spp N1 (kept from an earlier test, 4 bytes a pixel) and now at N2. For an
//!   unbiased Monte Carlo estimate the N2 mean contains the N1 mean plus N2 - N1 independent
//!   samples, so the difference d of the two has variance sigma^2 (N2 - N1) / (N1 N2) while the
//!   film's own error has sigma^2 / N2: the film's RMS error is rms(d) sqrt(N1 / (N2 - N1)),
//!   divided by the image's mean luminance to make it relative. It falls as t^-1/2 and is what
//!   the typed target of the dashboard projects. A snapshot is kept each time the spp doubled
//!   (two at most) and the older one is compared with, so N1 lies between N2/4 and N2/2: half
//!   or more of the samples are new, which keeps the estimate steady (against the previous
//!   test only a few spp apart, fireflies make it jump by tens of percent);
//! - the **failing fraction** of the perceptual convergence test (Yee's test between the two
//!   display snapshots, LuxRender's `haltthreshold` measure), which the projection to the
//!   job's haltthreshold uses. It counts pixels, so on small films it is coarse and noisy;
//!   the projection says so ("noisy") rather than guessing.
//!
//! The fit is least squares of ln(value) against ln(secs) over the recent points, the exponent
//! taken from the data (-1/2 for the relative error of an unbiased render). The history lives
//! in the job's run state only: after a master restart it starts empty again (the job's clock,
//! its first lease time, is kept by the store, so new points carry on at the right times).
//!
//! The history is bounded: at most [`MAX_POINTS`] points, thinned evenly. Every observation
//! is numbered; while the kept list grows past the bound every second kept point is dropped
//! and from then on only every `stride`-th observation is kept (the stride doubles with each
//! thinning), so the kept points stay evenly spaced over the whole run. The latest
//! observation is always shown, as a tail point, even between two kept ones.

use luxfarm::film::Film;
use luxfarm::halt::ConvergenceTest;
use luxfarm::imageio::{encode_png_preview, LdrImage};
use luxfarm::tonemap::{film_xyz, tonemap_display, TonemapParams};

/// Most points of a job's history (kept points plus the latest observation).
pub const MAX_POINTS: usize = 200;
/// The fit uses at most this many of the most recent points.
pub const FIT_POINTS: usize = 24;
/// Fewer usable points than this are "not enough data".
pub const MIN_FIT_POINTS: usize = 5;
/// The fitted points must span at least this ratio of times (last / first): the fit is in
/// log time, where a short span says nothing about the slope.
pub const MIN_TIME_SPAN: f64 = 1.2;
/// An exponent at or above this is no downward trend (a flat or rising estimate).
pub const MAX_EXPONENT: f64 = -0.02;
/// A fit explaining less of the variance of ln(estimate) than this is too noisy to project.
pub const MIN_R2: f64 = 0.5;
/// A projected time beyond this many seconds (about 30 years) is reported as unreachable.
pub const HORIZON_SECS: f64 = 1e9;

/// What the estimate of the history is (the `estimate` field of the view).
pub const ESTIMATE_KIND: &str = "relative_error";

/// One observation of a job's error estimate.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, utoipa::ToSchema)]
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
    fn of(self, p: &TradePoint) -> Option<f64> {
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
        if self.seen % self.stride == 0 {
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

/// estimate = coefficient x secs^exponent, fitted on the recent history.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, utoipa::ToSchema)]
pub struct PowerFit {
    pub exponent: f64,
    pub coefficient: f64,
    /// Share of the variance of ln(estimate) the fit explains.
    pub r2: f64,
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

/// The recent points usable in log–log space (time and value above 0).
fn usable(points: &[TradePoint], metric: Metric) -> Vec<(f64, f64)> {
    let usable: Vec<(f64, f64)> = points
        .iter()
        .filter_map(|p| Some((p.secs, metric.of(p)?)))
        .filter(|(t, v)| *t > 0.0 && *v > 0.0)
        .map(|(t, v)| (t.ln(), v.ln()))
        .collect();
    let from = usable.len().saturating_sub(FIT_POINTS);
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
    let syy: f64 = xy.iter().map(|p| (p.1 - my).powi(2)).sum();
    if sxx <= 0.0 || !sxx.is_finite() {
        return Err(ProjectionStatus::NotEnoughData);
    }
    let exponent = sxy / sxx;
    if !exponent.is_finite() || exponent >= MAX_EXPONENT {
        return Err(ProjectionStatus::NoTrend);
    }
    // syy > 0 here: a flat series has a zero slope.
    let r2 = (sxy * sxy / (sxx * syy)).clamp(0.0, 1.0);
    if !(r2 >= MIN_R2) {
        return Err(ProjectionStatus::Noisy);
    }
    let coefficient = (my - exponent * mx).exp();
    if !(coefficient.is_finite() && coefficient > 0.0) {
        return Err(ProjectionStatus::Unreachable);
    }
    Ok(PowerFit {
        exponent,
        coefficient,
        r2,
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

/// A target relative error from text (the `target` query parameter): a number in (0, 10].
pub fn parse_target(text: &str) -> Result<f64, String> {
    let text = text.trim();
    match text.parse::<f64>() {
        Ok(t) if t > 0.0 && t <= 10.0 => Ok(t),
        _ => Err(format!(
            "parameter target: {text:?} is not a relative error in (0, 10]"
        )),
    }
}

/// The trade of one job as the API shows it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, utoipa::ToSchema)]
pub struct TradeView {
    /// What `estimate` of the history points is: `relative_error`.
    pub estimate: String,
    /// (seconds since the first lease, merged spp, relative error, failing fraction), at
    /// most 200 points, evenly thinned; empty until two convergence tests ran, and after a
    /// master restart.
    pub history: Vec<TradePoint>,
    /// The projected time to the job's haltthreshold (failing fraction); none without one.
    pub threshold_projection: Option<Projection>,
    /// The projected time to the requested relative error (`/trade?target=`).
    pub target_projection: Option<Projection>,
}

impl TradeView {
    /// The view of a history with projections to the haltthreshold and to a target relative
    /// error, when given.
    pub fn new(history: Vec<TradePoint>, threshold: Option<f64>, target: Option<f64>) -> TradeView {
        TradeView {
            estimate: ESTIMATE_KIND.to_string(),
            threshold_projection: threshold
                .map(|t| project(&history, Metric::FailingFraction, t)),
            target_projection: target.map(|t| project(&history, Metric::RelativeError, t)),
            history,
        }
    }
}

/// The film's luminance at a convergence test, kept for the next one.
#[derive(Clone, Debug, Default)]
struct Snapshot {
    spp: f64,
    y: Vec<f32>,
}

/// The relative RMS error of the film now (luminance `y` at `spp`) from the previous snapshot
/// (see the module docs); None when they cannot be compared (size change, no new samples, a
/// black image).
fn relative_error(prev: &Snapshot, y: &[f32], spp: f64) -> Option<f64> {
    if prev.y.len() != y.len() || y.is_empty() || !(prev.spp > 0.0 && spp > prev.spp) {
        return None;
    }
    let (mut d2, mut sum, mut n) = (0.0f64, 0.0f64, 0usize);
    for (a, b) in prev.y.iter().zip(y) {
        let (a, b) = (f64::from(*a), f64::from(*b));
        if a.is_finite() && b.is_finite() {
            d2 += (b - a) * (b - a);
            sum += b;
            n += 1;
        }
    }
    if n == 0 || sum <= 0.0 {
        return None;
    }
    let mean = sum / n as f64;
    let var_now = d2 / n as f64 * prev.spp / (spp - prev.spp);
    Some(var_now.sqrt() / mean).filter(|e| e.is_finite())
}

/// A job's trade state, kept in its run state.
#[derive(Clone, Debug, Default)]
pub struct TradeState {
    pub history: ErrorHistory,
    /// The convergence test of a job without haltthreshold (a job with one shares the halt
    /// test's result and map).
    own: ConvergenceTest,
    /// Spp at this module's last test.
    own_spp: f64,
    own_tests: u64,
    /// The film's luminance at (at most two) earlier observations, taken each time the spp
    /// doubled; the older one is compared with.
    marks: Vec<Snapshot>,
}

impl TradeState {
    /// Takes a convergence test's moment: the film (a copy of the merged one) and the test's
    /// failing fraction, at `secs` since the first lease. Adds a point once the previous
    /// snapshot gives a relative error.
    pub fn observe(
        &mut self,
        film: &Film,
        tonemap: &TonemapParams,
        secs: f64,
        failing: Option<f64>,
    ) {
        let y: Vec<f32> = film_xyz(film, tonemap).xyz.iter().map(|p| p[1]).collect();
        let spp = film.spp();
        let err = self.marks.first().and_then(|s| relative_error(s, &y, spp));
        if self.marks.last().is_none_or(|m| spp >= 2.0 * m.spp) {
            self.marks.push(Snapshot { spp, y });
            if self.marks.len() > 2 {
                self.marks.remove(0);
            }
        }
        if let Some(estimate) = err {
            self.history.push(TradePoint {
                secs,
                spp,
                estimate,
                failing,
            });
        }
    }

    /// Whether this module's own test is due at `spp` (every `step` spp).
    pub fn own_due(&self, spp: f64, step: f64) -> bool {
        self.own_tests == 0 || spp >= self.own_spp + step
    }

    /// Runs this module's own convergence test on (a copy of) the merged film; the failing
    /// fraction, once two snapshots were compared.
    pub fn own_test(&mut self, film: &Film, tonemap: &TonemapParams) -> Option<f64> {
        self.own_spp = film.spp();
        let failing = self.own.update(&tonemap_display(film, tonemap));
        self.own_tests += 1;
        (self.own_tests >= 2).then_some(failing)
    }

    /// The per-pixel noise of this module's own last test (empty before one ran).
    pub fn own_noise(&self) -> &[f32] {
        self.own.noise_map()
    }
}

/// The colour of a pixel's visible difference relative to the threshold `r` (Yee's ratio;
/// above 1 the pixel fails): passing pixels dark blue, brighter towards 1; failing ones from
/// yellow (just failing) to red (100 times the threshold or more, or not yet compared).
pub fn overlay_colour(r: f32) -> [f32; 3] {
    if r.is_nan() || r > 1.0 {
        let u = if r.is_finite() {
            (r.log10() / 2.0).clamp(0.0, 1.0)
        } else {
            1.0
        };
        [1.0, 1.0 - u, 0.0]
    } else {
        [0.0, 0.15 * r.max(0.0), 0.2 + 0.6 * r.max(0.0)]
    }
}

/// A PNG of a convergence noise map (`width` x `height`, row by row), its longer side at most
/// `max_size` (0: full size).
pub fn overlay_png(noise: &[f32], width: u32, height: u32, max_size: u32) -> Result<Vec<u8>, String> {
    let rgb: Vec<[f32; 3]> = noise.iter().map(|&r| overlay_colour(r)).collect();
    let img = LdrImage {
        width,
        height,
        rgb: &rgb,
        gray: &[],
        alpha: &[],
    };
    let mut out = Vec::new();
    encode_png_preview(&mut out, &img, max_size).map_err(|e| e.to_string())?;
    Ok(out)
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
        (1..=n).map(|i| pt(i as f64, c / (i as f64).sqrt())).collect()
    }

    #[test]
    fn history_is_bounded_and_evenly_thinned() {
        let mut h = ErrorHistory::default();
        for i in 0..10_000u32 {
            assert!(h.push(pt(f64::from(i), 0.5)));
            assert!(h.points().len() <= MAX_POINTS, "{} points", h.points().len());
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

    #[test]
    fn a_sqrt_series_projects_the_right_time() {
        // 0.5 / sqrt(t) reaches 0.01 at t = 2500 s.
        let pts = sqrt_series(0.5, 60);
        let f = fit(&pts, REL).unwrap();
        assert!((f.exponent + 0.5).abs() < 1e-9, "{f:?}");
        assert!((f.coefficient - 0.5).abs() < 1e-9, "{f:?}");
        assert!(f.r2 > 0.999_999);
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
        let rising: Vec<TradePoint> = (1..=30).map(|i| pt(f64::from(i), 0.01 * f64::from(i))).collect();
        check(&rising, ProjectionStatus::NoTrend);
        // a falling trend buried in noise (a fixed pseudo-random sequence)
        let mut s = 12345u64;
        let noisy: Vec<TradePoint> = (1..=30)
            .map(|i| {
                s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                let r = (s >> 33) as f64 / (1u64 << 31) as f64; // 0..1
                pt(f64::from(i), (0.5 / f64::from(i).powf(0.05)) * (0.2 + 1.6 * r))
            })
            .collect();
        let f = fit(&noisy, REL);
        assert!(matches!(f, Err(ProjectionStatus::Noisy | ProjectionStatus::NoTrend)), "{f:?}");
    }

    #[test]
    fn a_zero_target_or_a_slow_decay_is_unreachable() {
        let pts = sqrt_series(0.5, 30);
        let p = project(&pts, REL, 0.0);
        assert_eq!(p.status, ProjectionStatus::Unreachable);
        assert_eq!(p.at_secs, None);
        // t^-0.05 from 0.9 needs far more than the horizon to reach 1e-6
        let slow: Vec<TradePoint> = (1..=30).map(|i| pt(f64::from(i), 0.9 * f64::from(i).powf(-0.05))).collect();
        let p = project(&slow, REL, 1e-6);
        assert_eq!(p.status, ProjectionStatus::Unreachable, "{p:?}");
    }

    #[test]
    fn the_failing_fraction_projects_from_its_own_points() {
        // failing fraction 0.2 t^-1 on every second point only; the relative error is flat
        let pts: Vec<TradePoint> = (1..=40)
            .map(|i| TradePoint {
                secs: f64::from(i),
                spp: f64::from(i),
                estimate: 0.3,
                failing: (i % 2 == 0).then(|| 0.2 / f64::from(i)),
            })
            .collect();
        let p = project(&pts, Metric::FailingFraction, 0.001);
        assert_eq!(p.status, ProjectionStatus::Projected, "{p:?}");
        assert!((p.at_secs.unwrap() - 200.0).abs() < 1e-6, "{p:?}");
        assert_eq!(p.metric, Metric::FailingFraction);
        assert_eq!(project(&pts, REL, 0.01).status, ProjectionStatus::NoTrend);
        let v = TradeView::new(pts, Some(0.001), None);
        assert!(v.threshold_projection.is_some() && v.target_projection.is_none());
    }

    /// A film-like luminance of `n` pixels: per pixel the mean of `spp` samples of
    /// 1 + uniform noise in [-1, 1] (variance 1/3), nested: the first `spp` samples of a
    /// longer run are the same.
    fn noisy_means(n: usize, spp: u32, seed: u64) -> Vec<f32> {
        (0..n)
            .map(|px| {
                let mut s = seed ^ (px as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
                let mut sum = 0.0f64;
                for _ in 0..spp {
                    s = s
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    sum += 1.0 + ((s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0);
                }
                (sum / f64::from(spp)) as f32
            })
            .collect()
    }

    #[test]
    fn nested_snapshots_estimate_the_films_relative_error() {
        // True relative RMS error at N samples: sqrt(1/3 / N) / 1.
        for (n1, n2) in [(16u32, 32u32), (64, 80), (100, 400)] {
            let prev = Snapshot {
                spp: f64::from(n1),
                y: noisy_means(20_000, n1, 7),
            };
            let now = noisy_means(20_000, n2, 7);
            let e = relative_error(&prev, &now, f64::from(n2)).unwrap();
            let truth = (1.0 / 3.0 / f64::from(n2)).sqrt();
            assert!((e / truth - 1.0).abs() < 0.05, "{n1}->{n2}: {e} vs {truth}");
        }
        let prev = Snapshot {
            spp: 4.0,
            y: vec![1.0; 4],
        };
        assert_eq!(relative_error(&prev, &[1.0; 3], 8.0), None, "size change");
        assert_eq!(relative_error(&prev, &[1.0; 4], 4.0), None, "no new samples");
        assert_eq!(relative_error(&prev, &[0.0; 4], 8.0), None, "black image");
        assert_eq!(relative_error(&prev, &[1.0; 4], 8.0), Some(0.0));
    }

    #[test]
    fn observing_a_film_adds_points_from_the_second_snapshot_on() {
        let tp = TonemapParams::default();
        let mut t = TradeState::default();
        let mut f = Film::new(2, 1, vec![]);
        let mut add = |f: &mut Film, v: f32| {
            for x in 0..2 {
                f.add_splat(0, x, 0, [v, v, v], 1.0, 1.0);
            }
            f.add_sample_count(2.0);
        };
        add(&mut f, 0.5);
        add(&mut f, 0.7);
        t.observe(&f, &tp, 1.0, None);
        assert!(t.history.points().is_empty());
        add(&mut f, 0.3);
        add(&mut f, 0.4);
        t.observe(&f, &tp, 2.0, Some(0.5));
        let pts = t.history.points();
        assert_eq!(pts.len(), 1);
        assert!(pts[0].estimate > 0.0 && pts[0].estimate.is_finite(), "{pts:?}");
        assert_eq!((pts[0].secs, pts[0].spp, pts[0].failing), (2.0, 4.0, Some(0.5)));
        // snapshots are kept as the spp doubles, two at most; the older is compared with
        let marks = |t: &TradeState| t.marks.iter().map(|m| m.spp).collect::<Vec<_>>();
        assert_eq!(marks(&t), [2.0, 4.0]);
        add(&mut f, 0.6);
        t.observe(&f, &tp, 3.0, None);
        assert_eq!(marks(&t), [2.0, 4.0]);
        for _ in 0..3 {
            add(&mut f, 0.6);
        }
        t.observe(&f, &tp, 4.0, None);
        assert_eq!(marks(&t), [4.0, 8.0]);
        assert_eq!(t.history.points().len(), 3);
    }

    #[test]
    fn targets_parse_as_relative_errors() {
        assert_eq!(parse_target(" 0.01 "), Ok(0.01));
        assert_eq!(parse_target("1.5"), Ok(1.5));
        for bad in ["0", "-0.1", "11", "NaN", "inf", "x", ""] {
            assert!(parse_target(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn own_test_needs_two_snapshots_and_keeps_its_map() {
        let mut f = Film::new(4, 2, vec![]);
        for x in 0..4 {
            f.add_splat(0, x, 0, [0.5, 0.5, 0.5], 1.0, 1.0);
        }
        f.add_sample_count(8.0);
        let mut t = TradeState::default();
        let tp = TonemapParams::default();
        assert!(t.own_due(0.0, 4.0));
        assert_eq!(t.own_test(&f, &tp), None);
        assert_eq!(t.own_noise().len(), 8);
        assert!(!t.own_due(f.spp() + 1.0, 4.0));
        assert!(t.own_due(f.spp() + 4.0, 4.0));
        // the same image again: nothing fails
        assert_eq!(t.own_test(&f, &tp), Some(0.0));
    }

    #[test]
    fn overlay_is_a_png_of_the_map_colours() {
        assert_eq!(overlay_colour(f32::INFINITY), [1.0, 0.0, 0.0]);
        assert_eq!(overlay_colour(100.0), [1.0, 0.0, 0.0]);
        assert_eq!(overlay_colour(1.5)[0], 1.0);
        assert_eq!(overlay_colour(0.0), [0.0, 0.0, 0.2]);
        assert_eq!(overlay_colour(f32::NAN)[0], 1.0);
        let png = overlay_png(&[0.0, 0.5, 2.0, f32::INFINITY, 1.0, 1000.0], 3, 2, 0).unwrap();
        assert_eq!(&png[1..4], b"PNG");
        // a map that does not match the size is an error, not a panic
        assert!(overlay_png(&[0.0; 5], 3, 2, 0).is_err());
    }
}
