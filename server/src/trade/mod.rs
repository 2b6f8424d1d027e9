//! The speed/accuracy trade of a running job: an error estimate over time, a power-law fit of
//! it, the projected time to a target error, and the convergence map as a picture.
//!
//! ```text
//! merges --tick (crate::analysis)--> convergence test every convergencestep spp (the
//!   haltthreshold test of `luxfarm::halt`, or this module's own test for jobs without a threshold)
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
//! in the job's run state and is saved beside each checkpoint (`jobs/ID/trade.json`, the
//! points as JSON): a master restart takes it back (points read again one by one through the
//! same checks, the file's size bounded), and an ended job's history stays readable. The
//! relative-error snapshots are not saved: after a restart the next point comes once a new
//! snapshot was taken.
//!
//! `history`: the bounded, evenly thinned list of points; `fit`: the fit and the projection;
//! here: the estimates from the film, the view, and the convergence map picture.

mod fit;
mod history;

pub use fit::{PowerFit, Projection, ProjectionStatus};
pub use history::{ErrorHistory, Metric, TradePoint};

use fit::project;
use luxfarm::halt::ConvergenceTest;
use luxfarm::imageio::{encode_png_preview, LdrImage};
use luxfarm::tonemap::{RgbImage, XyzImage};
use std::path::Path;

/// The file of a job's saved history, in its job directory.
pub const SAVED_FILE: &str = "trade.json";
/// The largest saved history read back (200 points take about 20 KB).
pub const MAX_SAVED_BYTES: u64 = 1 << 20;

/// Saves a history's points (JSON) atomically at `path`.
pub fn save(history: &ErrorHistory, path: &Path) -> Result<(), String> {
    let json = serde_json::to_vec(&history.points()).map_err(|e| e.to_string())?;
    luxfarm::atomic_write::write_bytes_atomic(path, &json).map_err(|e| e.to_string())
}

/// Reads a saved history back: an absent file is an empty history; a larger file than
/// [`MAX_SAVED_BYTES`] or one that is not a list of points is an error naming the file;
/// points the history refuses (bad values, time going back) are left out.
pub fn load(path: &Path) -> Result<ErrorHistory, String> {
    let mut history = ErrorHistory::default();
    let len = match std::fs::metadata(path) {
        Ok(m) => m.len(),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(history),
        Err(e) => return Err(format!("{}: {e}", path.display())),
    };
    if len > MAX_SAVED_BYTES {
        return Err(format!(
            "{}: {len} bytes, more than a saved history may hold ({MAX_SAVED_BYTES})",
            path.display()
        ));
    }
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let points: Vec<TradePoint> =
        serde_json::from_slice(&bytes).map_err(|e| format!("{}: {e}", path.display()))?;
    for p in points {
        history.push(p);
    }
    Ok(history)
}

/// What the estimate of the history is (the `estimate` field of the view).
pub const ESTIMATE_KIND: &str = "relative_error";

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
            threshold_projection: threshold.map(|t| project(&history, Metric::FailingFraction, t)),
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
    /// The state of a job resumed with a saved history.
    pub fn with_history(history: ErrorHistory) -> TradeState {
        TradeState {
            history,
            ..TradeState::default()
        }
    }

    /// Takes a convergence test's moment: the film's luminance ([`luminance`] of a copy of the
    /// merged film) at `spp` and the test's failing fraction, at `secs` since the first lease.
    /// Adds a point once the previous snapshot gives a relative error.
    pub fn observe(&mut self, y: Vec<f32>, spp: f64, secs: f64, failing: Option<f64>) {
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

    /// Runs this module's own convergence test on the display image (`tonemap_display`) of (a
    /// copy of) the merged film at `spp`; the failing fraction, once two snapshots were
    /// compared.
    pub fn own_test(&mut self, spp: f64, display: &RgbImage) -> Option<f64> {
        self.own_spp = spp;
        let failing = self.own.update(display);
        self.own_tests += 1;
        (self.own_tests >= 2).then_some(failing)
    }

    /// The per-pixel noise of this module's own last test (empty before one ran).
    pub fn own_noise(&self) -> &[f32] {
        self.own.noise_map()
    }
}

/// The luminance (Y) of a film's XYZ image (`film_xyz`): what the relative error compares.
pub fn luminance(xyz: &XyzImage) -> Vec<f32> {
    xyz.xyz.iter().map(|p| p[1]).collect()
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
pub fn overlay_png(
    noise: &[f32],
    width: u32,
    height: u32,
    max_size: u32,
) -> Result<Vec<u8>, String> {
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
    use luxfarm::film::Film;
    use luxfarm::tonemap::{film_xyz, tonemap_display, TonemapParams};

    const REL: Metric = Metric::RelativeError;

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
        assert_eq!(
            relative_error(&prev, &[1.0; 4], 4.0),
            None,
            "no new samples"
        );
        assert_eq!(relative_error(&prev, &[0.0; 4], 8.0), None, "black image");
        assert_eq!(relative_error(&prev, &[1.0; 4], 8.0), Some(0.0));
    }

    #[test]
    fn observing_a_film_adds_points_from_the_second_snapshot_on() {
        let tp = TonemapParams::default();
        let mut t = TradeState::default();
        let mut f = Film::new(2, 1, vec![]);
        let add = |f: &mut Film, v: f32| {
            for x in 0..2 {
                f.add_splat(0, x, 0, [v, v, v], 1.0, 1.0);
            }
            f.add_sample_count(2.0);
        };
        add(&mut f, 0.5);
        add(&mut f, 0.7);
        let y = |f: &Film| luminance(&film_xyz(f, &tp));
        t.observe(y(&f), f.spp(), 1.0, None);
        assert!(t.history.points().is_empty());
        add(&mut f, 0.3);
        add(&mut f, 0.4);
        t.observe(y(&f), f.spp(), 2.0, Some(0.5));
        let pts = t.history.points();
        assert_eq!(pts.len(), 1);
        assert!(
            pts[0].estimate > 0.0 && pts[0].estimate.is_finite(),
            "{pts:?}"
        );
        assert_eq!(
            (pts[0].secs, pts[0].spp, pts[0].failing),
            (2.0, 4.0, Some(0.5))
        );
        // snapshots are kept as the spp doubles, two at most; the older is compared with
        let marks = |t: &TradeState| t.marks.iter().map(|m| m.spp).collect::<Vec<_>>();
        assert_eq!(marks(&t), [2.0, 4.0]);
        add(&mut f, 0.6);
        t.observe(y(&f), f.spp(), 3.0, None);
        assert_eq!(marks(&t), [2.0, 4.0]);
        for _ in 0..3 {
            add(&mut f, 0.6);
        }
        t.observe(y(&f), f.spp(), 4.0, None);
        assert_eq!(marks(&t), [4.0, 8.0]);
        assert_eq!(t.history.points().len(), 3);
    }

    #[test]
    fn a_saved_history_comes_back_and_bad_files_are_errors() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(SAVED_FILE);
        assert_eq!(load(&path).unwrap().points(), []);
        let mut h = ErrorHistory::default();
        for i in 1..=5 {
            h.push(TradePoint {
                secs: f64::from(i),
                spp: f64::from(4 * i),
                estimate: 1.0 / f64::from(i),
                failing: (i > 2).then_some(0.01),
            });
        }
        save(&h, &path).unwrap();
        assert_eq!(load(&path).unwrap().points(), h.points());
        // bad points are left out, a file of something else is an error naming it
        std::fs::write(
            &path,
            r#"[{"secs":1,"spp":1,"estimate":0.5,"failing":null},
               {"secs":0.5,"spp":2,"estimate":0.4,"failing":null},
               {"secs":2,"spp":3,"estimate":-1,"failing":null}]"#,
        )
        .unwrap();
        assert_eq!(load(&path).unwrap().points().len(), 1);
        std::fs::write(&path, b"{\"not\": \"points\"}").unwrap();
        assert!(load(&path).unwrap_err().contains("trade.json"));
        std::fs::write(&path, vec![b' '; MAX_SAVED_BYTES as usize + 1]).unwrap();
        assert!(load(&path).unwrap_err().contains("more than"));
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
        let display = tonemap_display(&f, &tp);
        assert_eq!(t.own_test(f.spp(), &display), None);
        assert_eq!(t.own_noise().len(), 8);
        assert!(!t.own_due(f.spp() + 1.0, 4.0));
        assert!(t.own_due(f.spp() + 4.0, 4.0));
        // the same image again: nothing fails
        assert_eq!(t.own_test(f.spp(), &display), Some(0.0));
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
