//! Halt rules, checkpoints, the end of a job, cancel and the drain at shutdown.
//!
//! The halt rules themselves are the core's (`luxfarm::halt`, shared with `luxfarm render`);
//! this module asks them at the master's moments, on the merged film: haltspp after each
//! merge; halttime (seconds since the first lease) and haltthreshold (the convergence test
//! every convergencestep spp, `crate::analysis`, which also rebuilds a noise-aware job's
//! sampling map on its own doubling schedule and feeds the job's error history) on every tick.
//! When a halt rule holds the job enters its halting phase (its `halted` webhook queued,
//! `crate::webhooks`): every lease is told to stop and
//! the master waits for the last deltas (at most two upload intervals plus
//! a margin), then writes the outputs the Film asks for (`luxfarm::output`) and marks the job
//! done.
//!
//! Checkpoints make acknowledged deltas durable: the film is written atomically (file and
//! directory synced), then the ledger rows it holds are committed with its generation; the
//! job's error history is saved beside it (`crate::trade`, best effort). Faults
//! stay with their job: a checkpoint that cannot be written is named (file and reason) on the
//! job and retried every checkpoint interval while the job renders on (its workers keep the
//! deltas not yet durable); a final checkpoint that fails keeps the job halting and retried; a
//! cancel ends the job even then, saying what its film holds. One job's fault never stops the
//! others' halting or checkpoints.

use crate::auth::Identity;
use crate::datadir::checkpoint_rel;
use crate::db::{JobRow, JobState};
use crate::error::{Result, ServerError};
use crate::farm::{lock, now_ms, CheckpointStep, Farm, JobRt};
use crate::scene;
use crate::scene::Film;
use luxfarm::halt::HaltRules;
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// The job's halt rules: its haltspp, halttime and haltthreshold (the scene's, or the
/// submission's overrides) and the scene's convergencestep.
pub(crate) fn rules(row: &JobRow, rt: &JobRt) -> HaltRules {
    HaltRules {
        spp: row.haltspp,
        time: row.halttime,
        threshold: row.haltthreshold,
        step: rt.info.convergence_step,
    }
}

/// The cheap checks after a merge, on the upload path: the samples-per-second history and
/// haltspp. The tests that tonemap the film run on the tick (`crate::analysis`).
pub fn after_merge(farm: &Farm, row: &JobRow, rt: &Arc<JobRt>) -> Result<()> {
    let samples = lock(&rt.film).total_samples();
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
    if let Some(reason) = rules(row, rt).spp_reached(samples, rt.info.pass_pixels as f64) {
        begin_halt(farm, rt, reason.to_string());
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
        st.halting = Some((JobState::Done, reason.clone(), Instant::now()));
    }
    for l in lock(&rt.leases).values_mut() {
        l.stop = true;
    }
    farm.touch();
    if let Err(e) = lock(&farm.db).queue_halted(&rt.id, &reason, now_ms()) {
        tracing::error!(job = %rt.id, error = %e, "the halted webhook could not be queued");
    }
}

/// Periodic work: worker timeouts, then for every loaded job on its own (one job's fault
/// never stops another's): halttime, halting deadlines and checkpoints.
pub fn tick(farm: &Farm) -> Result<()> {
    expire_workers(farm)?;
    let jobs: Vec<Arc<JobRt>> = lock(&farm.jobs).values().cloned().collect();
    for rt in jobs {
        if let Err(e) = tick_job(farm, &rt) {
            tracing::error!(job = %rt.id, error = %e, "job upkeep failed");
        }
    }
    Ok(())
}

fn tick_job(farm: &Farm, rt: &Arc<JobRt>) -> Result<()> {
    let row = farm.job_row(&rt.id)?;
    let first_lease = lock(&rt.state).first_lease_ms;
    if let Some(first) = first_lease {
        let elapsed = (now_ms() - first) as f64 / 1000.0;
        if let Some(reason) = rules(&row, rt).time_reached(elapsed) {
            begin_halt(farm, rt, reason.to_string());
        }
    }
    let halting = lock(&rt.state).halting.clone();
    if let Some((state, reason, since)) = halting {
        let all_in = lock(&rt.leases).values().all(|l| l.ended);
        let deadline = Duration::from_secs_f64(farm.cfg.upload_interval * 2.0 + 5.0);
        if all_in || since.elapsed() > deadline {
            return finish(farm, rt, state, &reason);
        }
    }
    let due = {
        let st = lock(&rt.state);
        st.last_checkpoint.elapsed().as_secs_f64() >= farm.cfg.checkpoint_interval
            && rt.version.load(Ordering::Relaxed) != st.checkpoint_version
    };
    if due {
        checkpoint(farm, rt)?;
    }
    Ok(())
}

/// Ends the leases of workers silent for longer than the timeout (their merged samples stay;
/// their unused budget returns to the job's pool); each counts as a failed lease of the worker
/// (`blocks`).
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
        let timeout = farm.cfg.worker_timeout;
        farm.record_failure(
            &worker,
            &job,
            &format!("lease timed out: no heartbeat for {timeout} s"),
        )?;
        farm.touch();
    }
    Ok(())
}

/// Writes the job's merged film atomically as the next checkpoint generation and commits the
/// ledger rows it contains. A failure is recorded on the job (file and reason), to be retried
/// after the checkpoint interval, and returned.
pub fn checkpoint(farm: &Farm, rt: &JobRt) -> Result<()> {
    let result = write_checkpoint(farm, rt);
    let mut st = lock(&rt.state);
    st.last_checkpoint = Instant::now();
    match &result {
        Ok(version) => {
            st.checkpoint_version = *version;
            if st.checkpoint_error.take().is_some() {
                drop(st);
                lock(&farm.db).set_job_reason(&rt.id, "")?;
                farm.touch();
            }
        }
        Err(e) => {
            let reason = format!("checkpoint failed: {e} (retrying)");
            tracing::error!(job = %rt.id, %reason);
            st.checkpoint_error = Some(reason.clone());
            drop(st);
            let _ = lock(&farm.db).set_job_reason(&rt.id, &reason);
            farm.touch();
        }
    }
    result.map(|_| ())
}

/// The checkpoint itself; returns the film version it holds. Checkpoints of one job are
/// written one at a time, each reading the job's generation under that lock: two writing the
/// same generation raced on its file, and the older film could replace the newer one after the
/// store had counted the newer one's deltas as durable.
///
/// The film is copied into the job's kept copy (`JobRt::copy`, held until the checkpoint is
/// written) with the ledger's last row read under the same film lock. A probe
/// (`Farm::checkpoint_probe`) is told when this checkpoint waits for another and when it has
/// copied the film and chosen its generation (tests drive interleavings with it).
fn write_checkpoint(farm: &Farm, rt: &JobRt) -> Result<u64> {
    let _one = farm.wait_lock(&rt.id, &rt.checkpointing);
    let row = farm.job_row(&rt.id)?;
    let mut slot = farm.wait_lock(&rt.id, &rt.copy);
    let (film, read) = rt.copy_film(&mut slot, |_| {
        let max_rowid = lock(&farm.db).ledger_max_rowid();
        (rt.version.load(Ordering::Relaxed), max_rowid)
    });
    let (version, max_rowid) = (read.0, read.1?);
    let generation = row.ckpt_gen + 1;
    farm.probe(&rt.id, CheckpointStep::Copied { generation });
    let dir = farm.job_dir(&rt.id);
    let dir_rel = format!("jobs/{}", rt.id);
    std::fs::create_dir_all(&dir).map_err(ServerError::file(dir_rel.clone()))?;
    let rel = checkpoint_rel(&rt.id, generation);
    let path = farm.cfg.data_dir.join(&rel);
    scene::write_checkpoint(film, &path)
        .map_err(|e| ServerError::Internal(format!("{rel}: {e}")))?;
    // The rename is made durable before the database points at the new file.
    std::fs::File::open(&dir)
        .and_then(|d| d.sync_all())
        .map_err(ServerError::file(dir_rel))?;
    lock(&farm.db).commit_checkpoint(&rt.id, generation, max_rowid)?;
    let history = lock(&rt.state).trade.history.clone();
    if let Err(e) = crate::trade::save(&history, &dir.join(crate::trade::SAVED_FILE)) {
        tracing::warn!(job = %rt.id, error = %e, "the error history could not be saved");
    }
    for old in crate::datadir::other_checkpoints(&dir, generation) {
        let _ = std::fs::remove_file(old);
    }
    tracing::debug!(job = %rt.id, generation, "checkpoint written");
    Ok(version)
}

/// The job's latest checkpoint film, if any. A missing or unreadable checkpoint is an error
/// naming the file.
pub fn load_checkpoint(farm: &Farm, row: &JobRow) -> Result<Option<Film>> {
    if row.ckpt_gen == 0 {
        return Ok(None);
    }
    let rel = checkpoint_rel(&row.id, row.ckpt_gen);
    scene::read_checkpoint(&farm.cfg.data_dir.join(&rel))
        .map(Some)
        .map_err(|e| match e {
            ServerError::Io(source) => ServerError::File { path: rel, source },
            ServerError::Internal(m) => ServerError::Internal(format!("{rel}: {m}")),
            other => other,
        })
}

/// The job's error history saved with its last checkpoint (`crate::trade`); empty when
/// there is none or it cannot be read (logged).
pub fn load_trade(farm: &Farm, id: &str) -> crate::trade::ErrorHistory {
    let path = farm.job_dir(id).join(crate::trade::SAVED_FILE);
    crate::trade::load(&path).unwrap_or_else(|e| {
        tracing::warn!(job = %id, error = %e, "the saved error history is left out");
        Default::default()
    })
}

/// Path of the job's final (or latest) checkpoint.
pub fn latest_checkpoint(farm: &Farm, row: &JobRow) -> Option<std::path::PathBuf> {
    let p = farm
        .cfg
        .data_dir
        .join(checkpoint_rel(&row.id, row.ckpt_gen));
    (row.ckpt_gen > 0 && p.exists()).then_some(p)
}

/// Ends a job: stops its leases, writes the final checkpoint (and the outputs when done), sets
/// the final state and drops the job from memory.
///
/// When the final checkpoint cannot be written the job stays halting, with the fault named,
/// and the end is tried again at the next tick; `force` (a cancel) ends it anyway, saying so.
pub fn finish(farm: &Farm, rt: &Arc<JobRt>, state: JobState, reason: &str) -> Result<()> {
    finish_with(farm, rt, state, reason, false)
}

fn finish_with(
    farm: &Farm,
    rt: &Arc<JobRt>,
    state: JobState,
    reason: &str,
    force: bool,
) -> Result<()> {
    if rt.closed.swap(true, Ordering::SeqCst) {
        return Ok(());
    }
    {
        let mut st = lock(&rt.state);
        if st.halting.is_none() || force {
            st.halting = Some((state, reason.to_string(), Instant::now()));
        }
    }
    let now = now_ms();
    for (id, l) in lock(&rt.leases).iter_mut() {
        l.stop = true;
        if !l.ended {
            l.ended = true;
            lock(&farm.db).end_lease(id, state.as_str(), now)?;
        }
    }
    let mut reason = reason.to_string();
    if let Err(e) = checkpoint(farm, rt) {
        if !force {
            // Merges stay closed off (every lease has ended); the next tick tries again.
            rt.closed.store(false, Ordering::SeqCst);
            return Err(e);
        }
        reason = format!(
            "{reason}; the final checkpoint could not be written ({e}): the film holds the \
             samples of the last checkpoint"
        );
    }
    if state == JobState::Done {
        let film = lock(&rt.film).clone();
        let dir = farm.job_dir(&rt.id).join("out");
        if let Err(e) = scene::write_outputs(&film, &rt.info, &dir) {
            tracing::error!(job = %rt.id, error = %e, "writing outputs failed");
            let why = format!("writing the outputs failed: {e}");
            lock(&farm.db).set_job_state(&rt.id, JobState::Failed, &why, now)?;
            forget(farm, rt);
            return Ok(());
        }
    }
    lock(&farm.db).set_job_state(&rt.id, state, &reason, now)?;
    forget(farm, rt);
    tracing::info!(job = %rt.id, state = state.as_str(), %reason, "job finished");
    Ok(())
}

/// Drops an ended job from memory (and the decoding films only it could use) and frees its
/// workers.
fn forget(farm: &Farm, rt: &JobRt) {
    let loaded: Vec<Arc<JobRt>> = {
        let mut jobs = lock(&farm.jobs);
        jobs.remove(&rt.id);
        jobs.values().cloned().collect()
    };
    let layouts: Vec<&scene::SceneInfo> = loaded.iter().map(|j| &j.info).collect();
    farm.scratch.retain(&layouts);
    if loaded.is_empty() {
        farm.received.clear();
    }
    for w in lock(&farm.workers).values_mut() {
        if w.lease.as_ref().is_some_and(|(j, _)| *j == rt.id) {
            w.lease = None;
        }
    }
    farm.metrics.jobs_finished.fetch_add(1, Ordering::Relaxed);
    farm.touch();
    farm.work_available.notify_waiters();
}

/// Cancels a queued or rendering job for `who` (its submitter or an admin). Workers on it are
/// told to stop; what was merged is kept (film.flm stays downloadable). A cancel always ends
/// the job, even when its final checkpoint cannot be written.
pub fn cancel(farm: &Farm, id: &str, who: &Identity) -> Result<JobRow> {
    let row = farm.job_row(id)?;
    who.check_manage(&row.owner)?;
    if row.state.is_final() {
        return Err(ServerError::Conflict(format!(
            "job {id} is already {}",
            row.state.as_str()
        )));
    }
    let rt = lock(&farm.jobs).get(id).cloned();
    match rt {
        Some(rt) => finish_with(farm, &rt, JobState::Cancelled, "cancelled by user", true)?,
        None => {
            lock(&farm.db).set_job_state(id, JobState::Cancelled, "cancelled by user", now_ms())?
        }
    }
    tracing::info!(job = %id, "job cancelled");
    farm.touch();
    farm.job_row(id)
}

/// The shutdown drain's last step, once no upload is in flight: a checkpoint of every loaded
/// job whose film changed since its last one. Returns how many failed.
pub fn checkpoint_all(farm: &Farm) -> usize {
    let jobs: Vec<Arc<JobRt>> = lock(&farm.jobs).values().cloned().collect();
    let mut failed = 0;
    for rt in jobs {
        let changed = rt.version.load(Ordering::Relaxed) != lock(&rt.state).checkpoint_version;
        if !changed {
            continue;
        }
        let result = checkpoint(farm, &rt);
        if let Err(e) = result {
            tracing::error!(job = %rt.id, error = %e, "final checkpoint at shutdown failed");
            failed += 1;
        }
    }
    failed
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::farm::CheckpointProbe;
    use crate::test_util::{leased_job, upload};
    use std::sync::{mpsc, Mutex};

    /// Two checkpoints of one job racing, driven step by step through the probe: "a" copies
    /// the film and is held there; a delta is merged; "b" starts. "b" must wait for "a" and
    /// then write the next generation, so the newest checkpoint holds every delta the store
    /// counts as durable. (Without the per-job lock, or with the generation read before it,
    /// "b" reuses "a"'s generation, and "a" finishing last leaves its older film under the
    /// store's claim that the second delta is durable: the asserts below fail.)
    #[test]
    fn a_racing_checkpoint_waits_and_takes_the_next_generation() {
        let dir = tempfile::tempdir().unwrap();
        let (farm, rt, worker, lease) = leased_job(dir.path(), |_| {});
        upload(&farm, &rt, &worker, &lease, 1, 1.0);
        let (events, seen) = mpsc::channel::<(String, CheckpointStep)>();
        let (release, held) = mpsc::channel::<()>();
        let (events, held) = (Mutex::new(events), Mutex::new(held));
        let probe: CheckpointProbe = Arc::new(move |_job: &str, step| {
            let who = std::thread::current().name().unwrap_or("").to_string();
            let _ = lock(&events).send((who.clone(), step));
            if who == "a" && matches!(step, CheckpointStep::Copied { .. }) {
                let _ = lock(&held).recv();
            }
        });
        *lock(&farm.checkpoint_probe) = Some(probe);
        let spawn = |name: &str| {
            let (f, r) = (farm.clone(), rt.clone());
            std::thread::Builder::new()
                .name(name.into())
                .spawn(move || checkpoint(&f, &r))
                .unwrap()
        };
        let a = spawn("a");
        let first = seen.recv().unwrap();
        assert_eq!(
            first,
            ("a".into(), CheckpointStep::Copied { generation: 1 })
        );
        upload(&farm, &rt, &worker, &lease, 2, 1.0);
        let b = spawn("b");
        // "b" either waits for "a" (its first step) or, were the race back, runs through.
        let (who, b_first) = seen.recv().unwrap();
        assert_eq!(who, "b");
        let waiting_b = if b_first == CheckpointStep::Waiting {
            Some(b)
        } else {
            b.join().unwrap().unwrap();
            None
        };
        release.send(()).unwrap();
        a.join().unwrap().unwrap();
        if let Some(b) = waiting_b {
            b.join().unwrap().unwrap();
        }
        let rest: Vec<(String, CheckpointStep)> = seen.try_iter().collect();
        let row = farm.job_row(&rt.id).unwrap();
        let on_disk = load_checkpoint(&farm, &row).unwrap().unwrap();
        let merged = lock(&rt.film).clone();
        assert_eq!(merged.total_samples(), 2.0 * rt.info.pixels as f64);
        assert_eq!(lock(&farm.db).durable_seq(&lease).unwrap(), 2);
        assert_eq!(
            on_disk, merged,
            "the newest checkpoint lacks a durable delta"
        );
        assert_eq!(row.ckpt_gen, 2, "two checkpoints wrote one generation");
        assert_eq!(b_first, CheckpointStep::Waiting);
        assert_eq!(
            rest,
            [("b".into(), CheckpointStep::Copied { generation: 2 })]
        );
    }
}
