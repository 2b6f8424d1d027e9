//! Halt rules, checkpoints and the end of a job.
//!
//! The halt rules themselves are the core's (`luxfarm::halt`, shared with `luxfarm render`);
//! this module asks them at the master's moments, on the merged film: haltspp and haltthreshold
//! (the convergence test every convergencestep spp) after each merge, halttime (seconds since
//! the first lease) on every tick. When one holds the job enters its halting phase: every lease
//! is told to stop and the master waits for the last deltas (at most two upload intervals plus
//! a margin), then writes the outputs the Film asks for (`luxfarm::output`) and marks the job
//! done.

use crate::db::{JobRow, JobState};
use crate::error::{Result, ServerError};
use crate::farm::{lock, now_ms, Farm, JobRt};
use crate::scene;
use crate::scene::Film;
use luxfarm::halt::HaltRules;
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// The job's halt rules: its haltspp, halttime and haltthreshold (the scene's, or the
/// submission's overrides) and the scene's convergencestep.
fn rules(row: &JobRow, rt: &JobRt) -> HaltRules {
    HaltRules {
        spp: row.haltspp,
        time: row.halttime,
        threshold: row.haltthreshold,
        step: rt.info.convergence_step,
    }
}

/// Checks the halt rules that depend on merged samples.
pub fn after_merge(farm: &Farm, row: &JobRow, rt: &Arc<JobRt>) -> Result<()> {
    let (samples, spp) = {
        let film = lock(&rt.film);
        (film.total_samples(), film.spp())
    };
    {
        let mut st = lock(&rt.state);
        st.history.push_back((Instant::now(), samples));
        while st.history.len() > 2
            && st
                .history
                .front()
                .is_some_and(|(t, _)| t.elapsed() > Duration::from_secs(60))
        {
            st.history.pop_front();
        }
    }
    let rules = rules(row, rt);
    if let Some(reason) = rules.spp_reached(samples, rt.info.pixels as f64) {
        begin_halt(farm, rt, reason.to_string());
        return Ok(());
    }
    let due = rules.convergence_due(&lock(&rt.state).convergence, spp);
    if due {
        // The test tonemaps a copy: merges into the live film go on meanwhile.
        let film = lock(&rt.film).clone();
        let reason = {
            let mut st = lock(&rt.state);
            rules.test_convergence(&mut st.convergence, &film, &rt.info.params.tonemap)
        };
        if let Some(reason) = reason {
            begin_halt(farm, rt, reason.to_string());
        }
    }
    Ok(())
}

/// Starts the halting phase (idempotent): every lease is told to stop.
pub fn begin_halt(farm: &Farm, rt: &JobRt, reason: String) {
    {
        let mut st = lock(&rt.state);
        if st.halting.is_some() {
            return;
        }
        tracing::info!(job = %rt.id, %reason, "halt condition holds; stopping workers");
        st.halting = Some((JobState::Done, reason, Instant::now()));
    }
    for l in lock(&rt.leases).values_mut() {
        l.stop = true;
    }
    farm.touch();
}

/// Periodic work: halttime, halting deadlines, worker timeouts and checkpoints.
pub fn tick(farm: &Farm) -> Result<()> {
    expire_workers(farm)?;
    let jobs: Vec<Arc<JobRt>> = lock(&farm.jobs).values().cloned().collect();
    for rt in jobs {
        let row = farm.job_row(&rt.id)?;
        let first_lease = lock(&rt.state).first_lease_ms;
        if let Some(first) = first_lease {
            let elapsed = (now_ms() - first) as f64 / 1000.0;
            let rules = rules(&row, &rt);
            if let Some(reason) = rules.time_reached(elapsed) {
                begin_halt(farm, &rt, reason.to_string());
            }
        }
        let halting = lock(&rt.state).halting.clone();
        if let Some((state, reason, since)) = halting {
            let all_in = lock(&rt.leases).values().all(|l| l.ended);
            let deadline = Duration::from_secs_f64(farm.cfg.upload_interval * 2.0 + 5.0);
            if all_in || since.elapsed() > deadline {
                finish(farm, &rt, state, &reason)?;
                continue;
            }
        }
        let due = {
            let st = lock(&rt.state);
            st.last_checkpoint.elapsed().as_secs_f64() >= farm.cfg.checkpoint_interval
                && rt.version.load(Ordering::Relaxed) != st.checkpoint_version
        };
        if due {
            checkpoint(farm, &rt, &row)?;
        }
    }
    Ok(())
}

/// Ends the leases of workers silent for longer than the timeout (their merged samples stay).
fn expire_workers(farm: &Farm) -> Result<()> {
    let timeout = Duration::from_secs_f64(farm.cfg.worker_timeout);
    let mut lost = Vec::new();
    for w in lock(&farm.workers).values_mut() {
        if !w.lost && w.last_seen.elapsed() > timeout {
            w.lost = true;
            if let Some((job, lease)) = w.lease.take() {
                lost.push((w.id.clone(), job, lease));
            }
            tracing::warn!(worker = %w.id, "worker timed out");
        }
    }
    for (worker, job, lease) in lost {
        lock(&farm.db).end_lease(&lease, "worker timeout", now_ms())?;
        let rt = lock(&farm.jobs).get(&job).cloned();
        if let Some(rt) = rt {
            if let Some(l) = lock(&rt.leases).get_mut(&lease) {
                l.ended = true;
                l.stop = true;
            }
        }
        tracing::warn!(%worker, %job, %lease, "lease lost");
        farm.touch();
    }
    Ok(())
}

/// Writes the job's merged film atomically as the next checkpoint generation and commits the
/// ledger rows it contains.
pub fn checkpoint(farm: &Farm, rt: &JobRt, row: &JobRow) -> Result<()> {
    let (film, version, max_rowid) = {
        let film = lock(&rt.film);
        let max_rowid = lock(&farm.db).ledger_max_rowid()?;
        (film.clone(), rt.version.load(Ordering::Relaxed), max_rowid)
    };
    let dir = farm.job_dir(&rt.id);
    std::fs::create_dir_all(&dir)?;
    let generation = row.ckpt_gen + 1;
    let path = dir.join(format!("checkpoint-{generation}.lxd"));
    scene::write_checkpoint(&film, &path)?;
    lock(&farm.db).commit_checkpoint(&rt.id, generation, max_rowid)?;
    let old = dir.join(format!("checkpoint-{}.lxd", row.ckpt_gen));
    if old.exists() {
        let _ = std::fs::remove_file(old);
    }
    let mut st = lock(&rt.state);
    st.checkpoint_version = version;
    st.last_checkpoint = Instant::now();
    tracing::debug!(job = %rt.id, generation, "checkpoint written");
    Ok(())
}

/// The job's latest checkpoint film, if any.
pub fn load_checkpoint(farm: &Farm, row: &JobRow) -> Result<Option<Film>> {
    if row.ckpt_gen == 0 {
        return Ok(None);
    }
    let path = farm
        .job_dir(&row.id)
        .join(format!("checkpoint-{}.lxd", row.ckpt_gen));
    scene::read_checkpoint(&path).map(Some)
}

/// Path of the job's final (or latest) checkpoint.
pub fn latest_checkpoint(farm: &Farm, row: &JobRow) -> Option<std::path::PathBuf> {
    let p = farm
        .job_dir(&row.id)
        .join(format!("checkpoint-{}.lxd", row.ckpt_gen));
    (row.ckpt_gen > 0 && p.exists()).then_some(p)
}

/// Ends a job: stops its leases, writes the final checkpoint (and the outputs when done), sets
/// the final state and drops the job from memory.
pub fn finish(farm: &Farm, rt: &Arc<JobRt>, state: JobState, reason: &str) -> Result<()> {
    if rt.closed.swap(true, Ordering::SeqCst) {
        return Ok(());
    }
    let row = farm.job_row(&rt.id)?;
    let now = now_ms();
    for (id, l) in lock(&rt.leases).iter_mut() {
        l.stop = true;
        if !l.ended {
            l.ended = true;
            lock(&farm.db).end_lease(id, state.as_str(), now)?;
        }
    }
    checkpoint(farm, rt, &row)?;
    if state == JobState::Done {
        let film = lock(&rt.film).clone();
        let dir = farm.job_dir(&rt.id).join("out");
        if let Err(e) = scene::write_outputs(&film, &rt.info, &dir) {
            tracing::error!(job = %rt.id, error = %e, "writing outputs failed");
            lock(&farm.db).set_job_state(&rt.id, JobState::Failed, &e.to_string(), now)?;
            lock(&farm.jobs).remove(&rt.id);
            return Ok(());
        }
    }
    lock(&farm.db).set_job_state(&rt.id, state, reason, now)?;
    lock(&farm.jobs).remove(&rt.id);
    for w in lock(&farm.workers).values_mut() {
        if w.lease.as_ref().is_some_and(|(j, _)| *j == rt.id) {
            w.lease = None;
        }
    }
    tracing::info!(job = %rt.id, state = state.as_str(), reason, "job finished");
    farm.metrics.jobs_finished.fetch_add(1, Ordering::Relaxed);
    farm.touch();
    farm.work_available.notify_waiters();
    Ok(())
}

/// Cancels a queued or rendering job. Workers on it are told to stop; what was merged is
/// kept (film.flm stays downloadable).
pub fn cancel(farm: &Farm, id: &str) -> Result<JobRow> {
    let row = farm.job_row(id)?;
    if row.state.is_final() {
        return Err(ServerError::Conflict(format!(
            "job {id} is already {}",
            row.state.as_str()
        )));
    }
    let rt = lock(&farm.jobs).get(id).cloned();
    match rt {
        Some(rt) => finish(farm, &rt, JobState::Cancelled, "cancelled by user")?,
        None => {
            lock(&farm.db).set_job_state(id, JobState::Cancelled, "cancelled by user", now_ms())?
        }
    }
    tracing::info!(job = %id, "job cancelled");
    farm.touch();
    farm.job_row(id)
}
