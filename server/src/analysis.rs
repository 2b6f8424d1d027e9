//! The merged film's analyses, run on the master's tick instead of on the upload path: the
//! `haltthreshold` convergence test, the trade view's own test for jobs without one
//! (`crate::trade`), each every `convergencestep` spp, and the noise-aware sampling map
//! (`crate::noisemap`), first at `convergencestep` spp and then at doubling steps.
//!
//! ```text
//! merge (upload path: decode, merge, ledger, haltspp, ack) --> film version bumped
//! tick --due, and the job's share of time allows?--> the film copied into the job's kept copy
//!   --> one tonemap: luminance (error history) + display image (convergence / own test);
//!   map builder; each on its state taken out of the job's run state --> results put back; a
//!   threshold that holds begins the halt; the next round waits by the time this one took
//! ```
//!
//! Tonemapping a large film for these tests costs more than merging a delta (a 1080p film:
//! hundreds of milliseconds), so on the upload path it delayed every acknowledgement and,
//! with many workers, ran once per `convergencestep` spp however far behind the master was.
//! On the tick it runs at most once per tick per job, coalescing however many merges arrived,
//! and never holds the job's state lock while it tonemaps: acknowledgements (which read the
//! current sampling map) and views go on meanwhile, reading the state as it was before the
//! test (it is copied out and written back; only the tick changes it, so nothing is lost).
//!
//! What one round costs is bounded three ways:
//! - the film is copied into the job's kept copy (`JobRt::copy`, shared with checkpoints), not
//!   into fresh memory;
//! - the film is tonemapped once: its XYZ image gives both the luminance the error history
//!   compares and the display image the convergence test compares;
//! - a job's analyses run at most `--analysis-share` of the time (a round uses every core):
//!   after a round that took `d`, the next waits `d (1 - share) / share`. Tests stay at least `convergencestep` spp
//!   apart, as before; when the film grows faster than the master can test it, they are further
//!   apart (a haltthreshold then holds a little later, never sooner).

use crate::db::JobRow;
use crate::farm::{lock, now_ms, Farm, JobRt};
use crate::halt::{begin_halt, rules};
use crate::scene::Film;
use luxfarm::tonemap::{display_from_xyz, film_xyz, RgbImage};
use std::sync::Arc;
use std::time::Instant;

/// Which analyses are due for the film at `spp`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Due {
    convergence: bool,
    own: bool,
    map: bool,
}

impl Due {
    fn any(self) -> bool {
        self.convergence || self.own || self.map
    }
}

/// The analyses due for every loaded job, on the master's tick after `crate::halt::tick`
/// (one job's fault never stops another's).
pub fn tick(farm: &Farm) {
    let jobs: Vec<Arc<JobRt>> = lock(&farm.jobs).values().cloned().collect();
    for rt in jobs {
        match farm.job_row(&rt.id) {
            Ok(row) => run(farm, &row, &rt),
            Err(e) => tracing::error!(job = %rt.id, error = %e, "job analysis skipped"),
        }
    }
}

/// Runs the analyses due for the job's merged film (none once the job is halting, none
/// before the job's share of time allows).
fn run(farm: &Farm, row: &JobRow, rt: &JobRt) {
    let spp = lock(&rt.film).spp();
    let rules = rules(row, rt);
    let due = {
        let st = lock(&rt.state);
        if st.halting.is_some() || st.analysis_after.is_some_and(|t| Instant::now() < t) {
            return;
        }
        Due {
            convergence: rules.convergence_due(&st.convergence, spp),
            own: rules.threshold.is_none() && st.trade.own_due(spp, rt.info.convergence_step),
            map: rt.info.noise_aware && st.noise_map.due(spp),
        }
    };
    if !due.any() {
        return;
    }
    let started = Instant::now();
    {
        let mut copy = lock(&rt.copy);
        let (film, ()) = rt.copy_film(&mut copy, |_| ());
        if due.convergence || due.own {
            let xyz = film_xyz(film, &rt.info.params.tonemap);
            let y = crate::trade::luminance(&xyz);
            let display = display_from_xyz(xyz, &rt.info.params.tonemap);
            let failing = if due.convergence {
                convergence(farm, rt, &rules, film.spp(), &display)
            } else {
                own_test(rt, film.spp(), &display)
            };
            observe(rt, y, film.spp(), failing);
        }
        if due.map {
            noise_map(rt, film);
        }
    }
    let share = farm.cfg.analysis_share.clamp(0.01, 1.0);
    let wait = started.elapsed().mul_f64((1.0 - share) / share);
    lock(&rt.state).analysis_after = Some(Instant::now() + wait);
}

/// The haltthreshold test on the display image; its failing fraction (for the error
/// history). A threshold that holds begins the halt.
fn convergence(
    farm: &Farm,
    rt: &JobRt,
    rules: &luxfarm::halt::HaltRules,
    spp: f64,
    display: &RgbImage,
) -> Option<f64> {
    let mut conv = lock(&rt.state).convergence.clone();
    let reason = rules.test_convergence_display(&mut conv, spp, display);
    let failing = conv.last_failing;
    lock(&rt.state).convergence = conv;
    if let Some(reason) = reason {
        begin_halt(farm, rt, reason.to_string());
    }
    failing
}

/// The trade view's own convergence test (jobs without haltthreshold); its failing fraction.
fn own_test(rt: &JobRt, spp: f64, display: &RgbImage) -> Option<f64> {
    let mut trade = lock(&rt.state).trade.clone();
    let failing = trade.own_test(spp, display);
    lock(&rt.state).trade = trade;
    failing
}

/// Gives a test's moment (the tested film's luminance and spp, its failing fraction) to the
/// job's error history, at the job's clock (seconds since its first lease). Done in place
/// under the state lock: one pass over the luminance, where a copy of the trade state (its
/// convergence test holds full-size images) would cost more.
fn observe(rt: &JobRt, y: Vec<f32>, spp: f64, failing: Option<f64>) {
    let mut st = lock(&rt.state);
    let secs = st
        .first_lease_ms
        .map_or(0.0, |t| (now_ms() - t) as f64 / 1000.0);
    st.trade.observe(y, spp, secs.max(0.0), failing);
}

/// A new noise-aware sampling map from the film, handed to workers with their next
/// acknowledgements.
fn noise_map(rt: &JobRt, film: &Film) {
    let step = rt.info.convergence_step;
    let mut builder = lock(&rt.state).noise_map.take_builder(step);
    let built = crate::noisemap::build(&mut builder, film, &rt.info.params.tonemap);
    if built.is_some() {
        tracing::debug!(job = %rt.id, spp = film.spp(), "noise-aware sampling map rebuilt");
    }
    lock(&rt.state).noise_map.put_back(builder, built);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::{leased_job, upload};
    use std::time::Duration;

    /// A round sets when the next may run; before then nothing runs however many
    /// convergencesteps the film grew by, after it the due test runs on the grown film.
    #[test]
    fn a_round_waits_for_the_jobs_share_of_time() {
        let dir = tempfile::tempdir().unwrap();
        let (farm, rt, worker, lease) = leased_job(dir.path(), |c| c.analysis_share = 0.5);
        upload(&farm, &rt, &worker, &lease, 1, 1.0);
        let after = || lock(&rt.state).analysis_after;
        assert_eq!(after(), None);
        // The trade view's own test is due at once (the job has no haltthreshold).
        tick(&farm);
        let first = after().expect("a round ran");
        assert_eq!(lock(&rt.state).trade.own_noise().len(), 48);
        // Held off: 40 spp more (more than a convergencestep) and nothing runs.
        let later = Instant::now() + Duration::from_secs(3600);
        lock(&rt.state).analysis_after = Some(later);
        upload(&farm, &rt, &worker, &lease, 2, 40.0);
        tick(&farm);
        assert_eq!(after(), Some(later));
        assert!(lock(&rt.state).trade.history.points().is_empty());
        // Allowed again: the test runs on the film as it is now.
        let past = Instant::now()
            .checked_sub(Duration::from_millis(1))
            .unwrap_or(first);
        lock(&rt.state).analysis_after = Some(past);
        tick(&farm);
        assert!(after().is_some_and(|t| t > past));
        let points = lock(&rt.state).trade.history.points();
        assert_eq!(points.len(), 1, "{points:?}");
        assert_eq!(points[0].spp, 41.0);
    }
}
