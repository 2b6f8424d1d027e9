//! The merged film's analyses, run on the master's tick instead of on the upload path: the
//! `haltthreshold` convergence test, the trade view's own test for jobs without one
//! (`crate::trade`), and the noise-aware sampling map (`crate::noisemap`), each every
//! `convergencestep` spp.
//!
//! ```text
//! merge (upload path: decode, merge, ledger, haltspp, ack) --> film version bumped
//! tick --due?--> one copy of the film --> convergence / own test / map builder, each on its
//!   state taken out of the job's run state --> results put back; a threshold that holds
//!   begins the halt
//! ```
//!
//! Tonemapping a large film for these tests costs more than merging a delta (a 1080p film:
//! hundreds of milliseconds), so on the upload path it delayed every acknowledgement and,
//! with many workers, ran once per `convergencestep` spp however far behind the master was.
//! On the tick it runs at most once per tick per job, coalescing however many merges arrived,
//! and never holds the job's state lock while it tonemaps: acknowledgements (which read the
//! current sampling map) and views go on meanwhile, reading the state as it was before the
//! test (it is copied out and written back; only the tick changes it, so nothing is lost).

use crate::db::JobRow;
use crate::farm::{lock, now_ms, Farm, JobRt};
use crate::halt::{begin_halt, rules};
use crate::scene::Film;
use std::sync::Arc;

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

/// Runs the analyses due for the job's merged film (none once the job is halting).
fn run(farm: &Farm, row: &JobRow, rt: &JobRt) {
    let spp = lock(&rt.film).spp();
    let rules = rules(row, rt);
    let due = {
        let st = lock(&rt.state);
        if st.halting.is_some() {
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
    let film = lock(&rt.film).clone();
    if due.convergence {
        convergence(farm, rt, &rules, &film);
    } else if due.own {
        own_test(rt, &film);
    }
    if due.map {
        noise_map(rt, &film);
    }
}

/// The haltthreshold test; its failing fraction goes to the error history.
fn convergence(farm: &Farm, rt: &JobRt, rules: &luxfarm::halt::HaltRules, film: &Film) {
    let tonemap = &rt.info.params.tonemap;
    let mut conv = lock(&rt.state).convergence.clone();
    let reason = rules.test_convergence(&mut conv, film, tonemap);
    let failing = conv.last_failing;
    lock(&rt.state).convergence = conv;
    observe(rt, film, failing);
    if let Some(reason) = reason {
        begin_halt(farm, rt, reason.to_string());
    }
}

/// The trade view's own convergence test (jobs without haltthreshold).
fn own_test(rt: &JobRt, film: &Film) {
    let mut trade = lock(&rt.state).trade.clone();
    let failing = trade.own_test(film, &rt.info.params.tonemap);
    lock(&rt.state).trade = trade;
    observe(rt, film, failing);
}

/// Gives a test's moment (the film it tested and its failing fraction) to the job's error
/// history, at the job's clock (seconds since its first lease).
fn observe(rt: &JobRt, film: &Film, failing: Option<f64>) {
    let (first, mut trade) = {
        let st = lock(&rt.state);
        (st.first_lease_ms, st.trade.clone())
    };
    let secs = first.map_or(0.0, |t| (now_ms() - t) as f64 / 1000.0);
    trade.observe(film, &rt.info.params.tonemap, secs.max(0.0), failing);
    lock(&rt.state).trade = trade;
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
