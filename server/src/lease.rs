//! The worker side of the master: registration, assignments (leases with their own stream
//! ids), film delta uploads with the (lease, sequence) ledger, and heartbeats.

use crate::db::{JobRow, JobState};
use crate::error::{Result, ServerError};
use crate::farm::{lock, new_id, now_ms, Farm, JobRt, LeaseRt, RunState, WorkerRt};
use crate::metrics::MergeTiming;
use crate::scene;
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

impl Farm {
    /// Registers a worker (a known id re-registers after a master restart).
    pub fn register(&self, name: &str, threads: u32, old_id: &str) -> Result<String> {
        let id = if old_id.is_empty() || old_id.len() > 64 {
            new_id("w")
        } else {
            old_id.to_string()
        };
        let now = now_ms();
        lock(&self.db).upsert_worker(&id, name, threads, now)?;
        lock(&self.workers).insert(
            id.clone(),
            WorkerRt {
                id: id.clone(),
                name: name.to_string(),
                threads,
                last_seen: Instant::now(),
                last_seen_ms: now,
                lease: None,
                lost: false,
                samples: 0.0,
            },
        );
        tracing::info!(worker = %id, %name, threads, "worker registered");
        self.touch();
        Ok(id)
    }

    /// Marks a worker as seen; false when unknown (it must register again).
    pub fn seen(&self, worker_id: &str) -> bool {
        let mut workers = lock(&self.workers);
        match workers.get_mut(worker_id) {
            Some(w) => {
                w.last_seen = Instant::now();
                w.last_seen_ms = now_ms();
                w.lost = false;
                true
            }
            None => false,
        }
    }

    /// The runtime of a job, loading it (film from its checkpoint, or a new film) on first use.
    pub fn job_rt(&self, row: &JobRow) -> Result<Arc<JobRt>> {
        if let Some(rt) = lock(&self.jobs).get(&row.id) {
            return Ok(rt.clone());
        }
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
        let rt = Arc::new(JobRt {
            id: row.id.clone(),
            info,
            film: Mutex::new(film),
            version: 0.into(),
            closed: false.into(),
            leases: Mutex::new(HashMap::new()),
            state: Mutex::new(RunState {
                halting: None,
                checkpoint_version: 0,
                last_checkpoint: Instant::now(),
                history: VecDeque::from([(Instant::now(), samples)]),
                convergence: Default::default(),
                first_lease_ms: row.first_lease_ms,
            }),
        });
        Ok(lock(&self.jobs).entry(row.id.clone()).or_insert(rt).clone())
    }

    /// The next assignment for a worker: the first unfinished job by priority then submission
    /// order that is not halting. None when there is nothing to do.
    pub fn assign(&self, worker_id: &str) -> Result<Option<pb::Assignment>> {
        if !self.seen(worker_id) {
            return Err(ServerError::NotFound(format!(
                "unknown worker {worker_id}: register first"
            )));
        }
        let jobs = lock(&self.db).jobs()?;
        for row in jobs.into_iter().filter(|j| !j.state.is_final()) {
            let rt = match self.job_rt(&row) {
                Ok(rt) => rt,
                Err(e) => {
                    tracing::error!(job = %row.id, error = %e, "job cannot be loaded");
                    let now = now_ms();
                    lock(&self.db).set_job_state(&row.id, JobState::Failed, &e.to_string(), now)?;
                    self.touch();
                    continue;
                }
            };
            if lock(&rt.state).halting.is_some() {
                continue;
            }
            return self.lease_job(worker_id, &row, &rt).map(Some);
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
        lock(&rt.leases).insert(
            lease_id.clone(),
            LeaseRt {
                stop: false,
                ended: false,
                samples: 0.0,
            },
        );
        if let Some(w) = lock(&self.workers).get_mut(worker_id) {
            w.lease = Some((row.id.clone(), lease_id.clone()));
        }
        tracing::info!(job = %row.id, lease = %lease_id, worker = %worker_id, stream, "lease granted");
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
        })
    }

    /// Whether the worker should stop its lease (stopped, ended, job finished or unknown).
    pub fn lease_should_stop(&self, lease_id: &str) -> bool {
        let Ok(Some(lease)) = lock(&self.db).lease(lease_id) else {
            return true;
        };
        let rt = lock(&self.jobs).get(&lease.job_id).cloned();
        match rt {
            Some(rt) => lock(&rt.leases)
                .get(lease_id)
                .is_none_or(|l| l.stop || l.ended),
            None => true,
        }
    }

    /// Merges one film delta. A (lease, seq) already merged is acknowledged as a duplicate and
    /// ignored; a delta of the wrong layout is refused and leaves the job untouched.
    pub fn upload(&self, h: &pb::UploadHeader, data: &[u8]) -> Result<(UploadStatus, bool)> {
        let started = Instant::now();
        self.seen(&h.worker_id);
        let lease = lock(&self.db)
            .lease(&h.lease_id)?
            .ok_or_else(|| ServerError::NotFound(format!("no lease {}", h.lease_id)))?;
        if lease.worker_id != h.worker_id {
            return Err(ServerError::BadRequest(
                "lease belongs to another worker".into(),
            ));
        }
        if lock(&self.db).ledger_has(&h.lease_id, h.seq)? {
            self.metrics.duplicates.fetch_add(1, Ordering::Relaxed);
            tracing::info!(lease = %h.lease_id, seq = h.seq, "replayed upload ignored");
            return Ok((UploadStatus::Duplicate, self.lease_should_stop(&h.lease_id)));
        }
        let row = self.job_row(&lease.job_id)?;
        if row.state.is_final() {
            return Err(ServerError::Conflict(format!(
                "job {} is {}: delta not merged",
                row.id,
                row.state.as_str()
            )));
        }
        let rt = self.job_rt(&row)?;
        let decode_start = Instant::now();
        let delta = luxfarm_wire::codec::decode_as(&h.encoding, data)?;
        let decode = decode_start.elapsed();
        let samples = delta.total_samples();
        let merge_start = Instant::now();
        {
            let mut film = lock(&rt.film);
            film.check_layout(&delta)
                .map_err(|e| ServerError::BadRequest(format!("delta refused: {e}")))?;
            // The ledger row and the merge happen under the film lock: never one without the
            // other, and no concurrent duplicate can slip between check and insert.
            if rt.closed.load(Ordering::SeqCst) {
                return Err(ServerError::Conflict(format!(
                    "job {} has ended: delta not merged",
                    row.id
                )));
            }
            let db = lock(&self.db);
            let duplicate = db.ledger_has(&h.lease_id, h.seq)?;
            if !duplicate {
                film.merge(&delta)
                    .map_err(|e| ServerError::BadRequest(format!("delta refused: {e}")))?;
                db.ledger_insert(
                    &h.lease_id,
                    h.seq,
                    &row.id,
                    samples,
                    data.len() as u64,
                    now_ms(),
                )?;
            }
            drop(db);
            drop(film);
            if duplicate {
                self.metrics.duplicates.fetch_add(1, Ordering::Relaxed);
                return Ok((UploadStatus::Duplicate, self.lease_should_stop(&h.lease_id)));
            }
        }
        let merge = merge_start.elapsed();
        rt.version.fetch_add(1, Ordering::Relaxed);
        let stop = {
            let mut leases = lock(&rt.leases);
            let l = leases.entry(h.lease_id.clone()).or_insert(LeaseRt {
                stop: true,
                ended: false,
                samples: 0.0,
            });
            l.samples += samples;
            if h.last {
                l.ended = true;
            }
            l.stop || l.ended
        };
        if h.last {
            lock(&self.db).end_lease(&h.lease_id, "stopped", now_ms())?;
            if let Some(w) = lock(&self.workers).get_mut(&h.worker_id) {
                w.lease = None;
            }
        }
        if let Some(w) = lock(&self.workers).get_mut(&h.worker_id) {
            w.samples += samples;
        }
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
        Ok((
            UploadStatus::Merged,
            stop || self.lease_should_stop(&h.lease_id),
        ))
    }

    /// A heartbeat: (stop, unknown worker).
    pub fn heartbeat(&self, worker_id: &str, lease_id: &str) -> (bool, bool) {
        if !self.seen(worker_id) {
            return (true, true);
        }
        if lease_id.is_empty() {
            return (false, false);
        }
        (self.lease_should_stop(lease_id), false)
    }

    /// A worker could not render its lease (the scene does not build): the job fails.
    pub fn lease_failed(&self, worker_id: &str, lease_id: &str, reason: &str) -> Result<()> {
        let lease = lock(&self.db)
            .lease(lease_id)?
            .ok_or_else(|| ServerError::NotFound(format!("no lease {lease_id}")))?;
        if lease.worker_id != worker_id {
            return Err(ServerError::BadRequest(
                "lease belongs to another worker".into(),
            ));
        }
        let row = self.job_row(&lease.job_id)?;
        if row.state.is_final() {
            return Ok(());
        }
        tracing::error!(job = %row.id, lease = %lease_id, %reason, "worker could not render the job");
        let reason = format!("worker {worker_id}: {reason}");
        let rt = lock(&self.jobs).get(&row.id).cloned();
        match rt {
            Some(rt) => crate::halt::finish(self, &rt, JobState::Failed, &reason),
            None => {
                lock(&self.db).set_job_state(&row.id, JobState::Failed, &reason, now_ms())?;
                self.touch();
                Ok(())
            }
        }
    }
}
