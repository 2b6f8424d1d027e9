//! The worker side of the master: jobs loaded for rendering, assignments (leases with their
//! own stream ids and sample budgets), film delta uploads with the (lease, sequence) ledger,
//! heartbeats and failure reports. Every call is made by an authenticated worker and accepted
//! only for leases it holds.
//!
//! ```text
//! NextAssignment --assign--> lease (stream id, budget from the job's haltspp)
//! UploadDelta header --check_upload--> (lease held, job open, size bounded) before any byte
//!   of the body is read; body --upload--> decode into a kept film of the job's layout
//!   (`scratch`), ledger check, merge under the film lock, acknowledgement (durable sequence
//!   number, master instance, budget, stop)
//! Heartbeat --heartbeat--> stop, durable sequence number, budget
//! ```
//!
//! A job that cannot be loaded (a missing or unreadable checkpoint or scene) fails alone, with
//! the file named, and its workers are told their lease is over.

use crate::admission::film_bytes;
use crate::budget;
use crate::db::{JobRow, JobState, LeaseRow};
use crate::error::{Result, ServerError};
use crate::farm::{lock, new_id, now_ms, Farm, JobRt, LeaseRt, RunState};
use crate::metrics::MergeTiming;
use crate::scene;
use crate::schedule;
use luxfarm_proto as pb;
use std::collections::{HashMap, VecDeque};
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// Outcome of an upload.
#[derive(Debug, PartialEq, Eq)]
pub enum UploadStatus {
    Merged,
    Duplicate,
}

impl UploadStatus {
    pub fn as_str(&self) -> &'static str {
        match self {
            UploadStatus::Merged => "merged",
            UploadStatus::Duplicate => "duplicate",
        }
    }
}

/// Largest encoded delta for a film of `film` bytes: its raw size plus what compression can
/// add in the worst case, plus the header (light group names).
fn max_delta(film: u64) -> u64 {
    film.saturating_add(film / 64)
        .saturating_add(8 << 20)
        .min(luxfarm_wire::codec::MAX_DECODED + (8 << 20))
}

impl Farm {
    /// The runtime of a job, loading it (film from its checkpoint, or a new film; its open
    /// leases from the store) on first use. A job that cannot be loaded fails, alone, with the
    /// reason, and the caller gets a Conflict.
    pub fn job_rt(&self, row: &JobRow) -> Result<Arc<JobRt>> {
        if let Some(rt) = lock(&self.jobs).get(&row.id) {
            return Ok(rt.clone());
        }
        if row.state.is_final() {
            return Err(ServerError::Conflict(format!(
                "job {} is {}",
                row.id,
                row.state.as_str()
            )));
        }
        match self.load_job(row) {
            Ok(rt) => Ok(lock(&self.jobs).entry(row.id.clone()).or_insert(rt).clone()),
            Err(e) => {
                let reason = format!("the job cannot be loaded: {e}");
                tracing::error!(job = %row.id, %reason);
                let now = now_ms();
                {
                    let db = lock(&self.db);
                    for l in db.open_leases_of(&row.id)? {
                        db.end_lease(&l.id, "job failed", now)?;
                    }
                    db.set_job_state(&row.id, JobState::Failed, &reason, now)?;
                }
                self.touch();
                Err(ServerError::Conflict(format!(
                    "job {} failed: {reason}",
                    row.id
                )))
            }
        }
    }

    fn load_job(&self, row: &JobRow) -> Result<Arc<JobRt>> {
        let info = scene::inspect(
            &self.scene_dir(&row.bundle_hash),
            row.scene_path.as_ref(),
            row.frame,
        )?;
        let film = match crate::halt::load_checkpoint(self, row)? {
            Some(f) => f,
            None => scene::new_film(&info),
        };
        let samples = film.total_samples();
        // The user sampling map survives restarts: the stored one, at its stored version.
        let mut noise_map = crate::noisemap::NoiseMapState::default();
        if info.map_refusal.is_none() {
            let (user, version) =
                crate::usermap::initial_user_map(self, &row.id, info.width, info.height)?;
            noise_map.set_user(user, version);
        }
        let mut leases = HashMap::new();
        {
            let db = lock(&self.db);
            for l in db.open_leases_of(&row.id)? {
                let mut rt = LeaseRt::new(l.budget);
                rt.samples = db.lease_merged(&l.id)?;
                leases.insert(l.id, rt);
            }
        }
        Ok(Arc::new(JobRt {
            id: row.id.clone(),
            info,
            film: Mutex::new(film),
            version: 0.into(),
            closed: false.into(),
            leases: Mutex::new(leases),
            checkpointing: Mutex::new(()),
            copy: Mutex::new(None),
            state: Mutex::new(RunState {
                halting: None,
                checkpoint_version: 0,
                last_checkpoint: Instant::now(),
                checkpoint_error: None,
                history: VecDeque::from([(Instant::now(), samples)]),
                convergence: Default::default(),
                analysis_after: None,
                noise_map,
                trade: crate::trade::TradeState::with_history(crate::halt::load_trade(
                    self, &row.id,
                )),
                first_lease_ms: row.first_lease_ms,
            }),
        }))
    }

    /// The next assignment for a worker: the first job of the scheduling order
    /// (`schedule::order`: what the worker may take, priority, submission, sequence policies)
    /// that is not halting. None when there is nothing to do (or the master is shutting down).
    pub fn assign(&self, worker_id: &str) -> Result<Option<pb::Assignment>> {
        if !self.seen(worker_id) {
            return Err(ServerError::NotFound(format!(
                "unknown worker {worker_id}: register first"
            )));
        }
        if self.is_draining() {
            return Ok(None);
        }
        if let Some(why) = self.quarantine(worker_id)? {
            tracing::debug!(worker = %worker_id, %why, "quarantined worker asked for work");
            return Ok(None);
        }
        let (tags, memory_mb) = lock(&self.workers)
            .get(worker_id)
            .map(|w| (w.tags.clone(), w.memory_mb))
            .unwrap_or_default();
        let (jobs, open) = {
            let db = lock(&self.db);
            (db.jobs()?, db.open_lease_counts()?)
        };
        let jobs: Vec<JobRow> = jobs.into_iter().filter(|j| !j.state.is_final()).collect();
        let policies = self.sequence_policies()?;
        let blocked = self.blocked_jobs(worker_id)?;
        let offer = schedule::Offer {
            tags: &tags,
            memory_mb,
            blocked: &blocked,
        };
        for row in schedule::order(&jobs, &offer, &open, &policies) {
            let Ok(rt) = self.job_rt(row) else {
                continue;
            };
            if lock(&rt.state).halting.is_some() {
                continue;
            }
            return self.lease_job(worker_id, row, &rt).map(Some);
        }
        Ok(None)
    }

    fn lease_job(&self, worker_id: &str, row: &JobRow, rt: &JobRt) -> Result<pb::Assignment> {
        let lease_id = new_id("l");
        let now = now_ms();
        let stream = {
            let mut db = lock(&self.db);
            let stream = db.create_lease(&lease_id, &row.id, worker_id, now)?;
            if row.state == JobState::Queued {
                db.set_job_state(&row.id, JobState::Rendering, "", now)?;
            }
            stream
        };
        lock(&rt.state).first_lease_ms.get_or_insert(now);
        lock(&rt.leases).insert(lease_id.clone(), LeaseRt::new(None));
        let budget = self.grant(row, rt, &lease_id)?;
        if let Some(w) = lock(&self.workers).get_mut(worker_id) {
            w.lease = Some((row.id.clone(), lease_id.clone()));
        }
        tracing::info!(job = %row.id, lease = %lease_id, worker = %worker_id, stream, ?budget,
            "lease granted");
        self.touch();
        Ok(pb::Assignment {
            lease_id,
            job_id: row.id.clone(),
            bundle_hash: row.bundle_hash.clone(),
            scene_path: row.scene_path.clone(),
            seed: row.seed,
            stream,
            upload_interval: self.cfg.upload_interval,
            haltspp: row.haltspp,
            halttime: row.halttime,
            haltthreshold: row.haltthreshold,
            width: row.width,
            height: row.height,
            frame: row.frame,
            budget,
        })
    }

    /// Grows a lease's budget when due (see `budget`), recording it in the store.
    fn grant(&self, row: &JobRow, rt: &JobRt, lease: &str) -> Result<Option<f64>> {
        let before = lock(&rt.leases).get(lease).and_then(|l| l.budget);
        let target = budget::target(row.haltspp, rt.info.pass_pixels);
        let after = budget::grant_for(rt, lease, target);
        if let Some(b) = after.filter(|b| Some(*b) != before) {
            lock(&self.db).set_lease_budget(lease, b)?;
        }
        Ok(after)
    }

    /// A lease of `worker`, or the reason it cannot be used: unknown (NotFound), another
    /// worker's (Forbidden), or of a finished job (Conflict).
    fn held_lease(&self, worker: &str, lease_id: &str) -> Result<(LeaseRow, JobRow)> {
        let lease = lock(&self.db)
            .lease(lease_id)?
            .ok_or_else(|| ServerError::NotFound(format!("no lease {lease_id}")))?;
        if lease.worker_id != worker {
            return Err(ServerError::Forbidden(format!(
                "lease {lease_id} is held by another worker"
            )));
        }
        let row = self.job_row(&lease.job_id)?;
        if row.state.is_final() {
            return Err(ServerError::Conflict(format!(
                "job {} is {}: lease {lease_id} is over",
                row.id,
                row.state.as_str()
            )));
        }
        Ok((lease, row))
    }

    /// Whether the worker should stop its lease (stopped, ended, job finished or unknown).
    pub fn lease_should_stop(&self, lease_id: &str) -> bool {
        let Ok(Some(lease)) = lock(&self.db).lease(lease_id) else {
            return true;
        };
        let Ok(row) = self.job_row(&lease.job_id) else {
            return true;
        };
        match self.job_rt(&row) {
            Ok(rt) => lock(&rt.leases)
                .get(lease_id)
                .is_none_or(|l| l.stop || l.ended),
            Err(_) => true,
        }
    }

    /// Checks an upload's header before its body is read: the lease is the caller's, its job
    /// is open, the announced size is within what the job's film can take.
    pub fn check_upload(&self, worker: &str, h: &pb::UploadHeader) -> Result<()> {
        if self.is_draining() {
            return Err(ServerError::Unavailable(
                "the master is shutting down: upload again once it is back".into(),
            ));
        }
        if !h.master_instance.is_empty() && h.master_instance != self.instance {
            return Err(ServerError::Restarted(format!(
                "the master restarted (now {}): upload the deltas it has not made durable first",
                self.instance
            )));
        }
        let (_, row) = self.held_lease(worker, &h.lease_id)?;
        let max = max_delta(film_bytes(&self.job_rt(&row)?.info));
        if h.size == 0 || h.size > max {
            return Err(ServerError::TooLarge(format!(
                "a delta of {} bytes announced; a delta of this job's film takes 1 to {max}",
                h.size
            )));
        }
        Ok(())
    }

    /// Merges one film delta of `worker`. A (lease, seq) already merged is acknowledged as a
    /// duplicate and ignored; a delta of the wrong layout is refused and leaves the job
    /// untouched.
    pub fn upload(&self, worker: &str, h: &pb::UploadHeader, data: &[u8]) -> Result<pb::UploadAck> {
        let started = Instant::now();
        self.seen(worker);
        let (_, row) = self.held_lease(worker, &h.lease_id)?;
        let rt = self.job_rt(&row)?;
        if lock(&self.db).ledger_has(&h.lease_id, h.seq)? {
            return self.duplicate(&row, &rt, h);
        }
        let decode_start = Instant::now();
        // Decoded into a film kept for it (`scratch`): no fresh pages per upload.
        let mut delta = self.scratch.take(&rt.info);
        if let Err(e) = luxfarm_wire::codec::decode_as_into(&h.encoding, data, &mut delta) {
            self.scratch.give_back(delta);
            let e = ServerError::from(e);
            self.record_failure(worker, &row.id, &format!("delta refused: {e}"))?;
            return Err(e);
        }
        let decode = decode_start.elapsed();
        let samples = delta.total_samples();
        let merge_start = Instant::now();
        let merged = self.merge_delta(h, data, &row, &rt, &delta);
        self.scratch.give_back(delta);
        if let Err(ServerError::BadRequest(why)) = &merged {
            self.record_failure(worker, &row.id, why)?;
        }
        if merged? == UploadStatus::Duplicate {
            return self.duplicate(&row, &rt, h);
        }
        let merge = merge_start.elapsed();
        rt.version.fetch_add(1, Ordering::Relaxed);
        self.account(worker, &rt, h, samples)?;
        tracing::debug!(job = %row.id, lease = %h.lease_id, seq = h.seq, samples, "delta merged");
        crate::halt::after_merge(self, &row, &rt)?;
        let timing = MergeTiming {
            decode,
            merge,
            total: started.elapsed(),
        };
        self.metrics
            .record_merge(data.len() as u64, samples, timing);
        self.touch();
        let mut ack = self.ack(UploadStatus::Merged, &row, &rt, &h.lease_id)?;
        ack.sampling_map = lock(&rt.state).noise_map.for_worker(h.sampling_map_version);
        Ok(ack)
    }

    /// Merges a decoded delta under the film lock together with its ledger row (never one
    /// without the other; no concurrent duplicate slips between check and insert). A delta of
    /// the wrong layout is refused (BadRequest) and leaves the film untouched.
    fn merge_delta(
        &self,
        h: &pb::UploadHeader,
        data: &[u8],
        row: &JobRow,
        rt: &JobRt,
        delta: &scene::Film,
    ) -> Result<UploadStatus> {
        let mut film = lock(&rt.film);
        film.check_layout(delta)
            .map_err(|e| ServerError::BadRequest(format!("delta refused: {e}")))?;
        if rt.closed.load(Ordering::SeqCst) {
            return Err(ServerError::Conflict(format!(
                "job {} has ended: delta not merged",
                row.id
            )));
        }
        let db = lock(&self.db);
        if db.ledger_has(&h.lease_id, h.seq)? {
            return Ok(UploadStatus::Duplicate);
        }
        film.merge(delta)
            .map_err(|e| ServerError::BadRequest(format!("delta refused: {e}")))?;
        db.ledger_insert(
            &h.lease_id,
            h.seq,
            &row.id,
            delta.total_samples(),
            data.len() as u64,
            now_ms(),
        )?;
        Ok(UploadStatus::Merged)
    }

    /// Books a merged delta to its lease and worker; the last delta ends the lease.
    fn account(&self, worker: &str, rt: &JobRt, h: &pb::UploadHeader, samples: f64) -> Result<()> {
        {
            let mut leases = lock(&rt.leases);
            let l = leases
                .entry(h.lease_id.clone())
                .or_insert_with(|| LeaseRt::new(None));
            l.samples += samples;
            l.rendered = l.rendered.max(l.samples);
            if h.last {
                l.ended = true;
            }
        }
        if h.last {
            lock(&self.db).end_lease(&h.lease_id, "stopped", now_ms())?;
        }
        if let Some(w) = lock(&self.workers).get_mut(worker) {
            w.samples += samples;
            if h.last {
                w.lease = None;
            }
        }
        Ok(())
    }

    fn duplicate(&self, row: &JobRow, rt: &JobRt, h: &pb::UploadHeader) -> Result<pb::UploadAck> {
        self.metrics.duplicates.fetch_add(1, Ordering::Relaxed);
        tracing::info!(lease = %h.lease_id, seq = h.seq, "replayed upload ignored");
        self.ack(UploadStatus::Duplicate, row, rt, &h.lease_id)
    }

    /// The acknowledgement of an upload: status, stop, durable sequence number, budget.
    fn ack(
        &self,
        status: UploadStatus,
        row: &JobRow,
        rt: &JobRt,
        lease: &str,
    ) -> Result<pb::UploadAck> {
        // Each lock is released before the next call takes it again (a guard made inside
        // the struct expression would live to its end, and `grant` locks the store too).
        let stop = self.lease_should_stop(lease);
        let durable_seq = self.durable_seq(lease)?;
        let budget = self.grant(row, rt, lease)?;
        Ok(pb::UploadAck {
            status: status.as_str().into(),
            stop,
            durable_seq,
            master_instance: self.instance.clone(),
            budget,
            sampling_map: None,
        })
    }

    /// The highest sequence number of `lease` a checkpoint holds.
    fn durable_seq(&self, lease: &str) -> Result<u64> {
        let seq = lock(&self.db).durable_seq(lease)?;
        Ok(seq)
    }

    /// A heartbeat of `worker` about its lease (empty: idle).
    pub fn heartbeat(&self, worker: &str, r: &pb::HeartbeatRequest) -> pb::HeartbeatReply {
        let mut reply = pb::HeartbeatReply {
            stop: false,
            unknown_worker: false,
            durable_seq: 0,
            master_instance: self.instance.clone(),
            budget: None,
        };
        if !self.seen(worker) {
            reply.unknown_worker = true;
            reply.stop = true;
            return reply;
        }
        if r.lease_id.is_empty() {
            return reply;
        }
        let lease = match self.held_lease(worker, &r.lease_id) {
            Ok((_, row)) => self.job_rt(&row).map(|rt| (row, rt)),
            Err(e) => Err(e),
        };
        let Ok((row, rt)) = lease else {
            reply.stop = true;
            reply.durable_seq = lock(&self.db).durable_seq(&r.lease_id).unwrap_or(0);
            return reply;
        };
        if let Some(l) = lock(&rt.leases).get_mut(&r.lease_id) {
            if r.samples.is_finite() && r.samples >= 0.0 {
                l.rendered = l.rendered.max(r.samples);
            }
            if r.pass_samples.is_finite() && r.pass_samples > 0.0 {
                l.pass_samples = r.pass_samples;
            }
        }
        reply.durable_seq = lock(&self.db).durable_seq(&r.lease_id).unwrap_or(0);
        reply.budget = self.grant(&row, &rt, &r.lease_id).unwrap_or(None);
        reply.stop = self.lease_should_stop(&r.lease_id);
        reply
    }

    /// A worker could not render its lease (the scene does not build there, the worker ran
    /// out of something): the lease ends and the failure counts against the worker on this
    /// job (`blocks`); the job goes on with other workers, or fails once every live worker is
    /// blocked from it.
    pub fn lease_failed(&self, worker: &str, lease_id: &str, reason: &str) -> Result<()> {
        let (_, row) = match self.held_lease(worker, lease_id) {
            Ok(l) => l,
            Err(ServerError::Conflict(_)) => return Ok(()),
            Err(e) => return Err(e),
        };
        self.end_failed_lease(worker, &row.id, lease_id, "failed")?;
        self.record_failure(worker, &row.id, reason)
    }

    /// Ends a lease that failed (its merged samples stay; its unused budget returns to the
    /// job's pool) and frees its worker.
    fn end_failed_lease(&self, worker: &str, job: &str, lease_id: &str, why: &str) -> Result<()> {
        lock(&self.db).end_lease(lease_id, why, now_ms())?;
        let rt = lock(&self.jobs).get(job).cloned();
        if let Some(rt) = rt {
            if let Some(l) = lock(&rt.leases).get_mut(lease_id) {
                l.ended = true;
                l.stop = true;
            }
        }
        if let Some(w) = lock(&self.workers).get_mut(worker) {
            if w.lease.as_ref().is_some_and(|(_, l)| l == lease_id) {
                w.lease = None;
            }
        }
        self.work_available.notify_waiters();
        Ok(())
    }
}
