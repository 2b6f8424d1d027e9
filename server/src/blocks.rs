//! Failing workers: a worker whose leases of a job fail (the render fails, the lease times
//! out, a delta is refused) `--block-after` times is blocked from that job; a worker blocked
//! from `--quarantine-after` jobs within `--quarantine-ttl` is quarantined farm-wide (no
//! leases at all) until the TTL passes or an admin forgives it. A job every live worker is
//! blocked from fails with the reason instead of waiting forever.
//!
//! ```text
//! ReportFailure / lease timeout / refused delta --record_failure--> failures (store)
//!   count == block_after --> blocked from the job --stranded?--> job failed with the reason
//! assign --quarantine / blocked_jobs--> nothing, or the jobs the worker may take
//! ```
//!
//! Reasons come from workers and are shown in the API: paths in them are cut to their last
//! component ([`clean_reason`]), so a worker's directories do not leak to users.

use crate::db::{FailureRow, JobState};
use crate::error::Result;
use crate::farm::{lock, now_ms, Farm};
use std::collections::HashSet;

/// Longest reason kept.
const MAX_REASON: usize = 500;

/// A failure reason fit to show: control characters become spaces, every word holding a path
/// separator is cut to its last component (`/home/a/s.lxs:3` -> `s.lxs:3`), at most
/// [`MAX_REASON`] characters.
pub fn clean_reason(reason: &str) -> String {
    let text: String = reason
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    let words: Vec<&str> = text
        .split(' ')
        .map(|w| match w.rfind(['/', '\\']) {
            Some(i) => w.get(i + 1..).unwrap_or(""),
            None => w,
        })
        .collect();
    words.join(" ").chars().take(MAX_REASON).collect()
}

/// A block as the API shows it.
#[derive(Clone, Debug, serde::Serialize, utoipa::ToSchema)]
pub struct FailureView {
    pub worker_id: String,
    pub job_id: String,
    /// Failed leases of the worker on the job.
    pub failures: u32,
    /// True once the failures reached `--block-after`: the worker gets no more leases of it.
    pub blocked: bool,
    pub reason: String,
    pub last_ms: i64,
}

impl Farm {
    fn failure_view(&self, f: FailureRow) -> FailureView {
        FailureView {
            blocked: f.count >= self.cfg.block_after,
            worker_id: f.worker_id,
            job_id: f.job_id,
            failures: f.count,
            reason: f.reason,
            last_ms: f.last_ms,
        }
    }

    /// The failures of a job's workers.
    pub fn job_failures(&self, job: &str) -> Result<Vec<FailureView>> {
        let rows = lock(&self.db).failures_of_job(job)?;
        Ok(rows.into_iter().map(|f| self.failure_view(f)).collect())
    }

    /// Counts a failed lease of `worker` on `job`. Reaching `--block-after` blocks the worker
    /// from the job, and fails the job if every live worker is now blocked from it.
    pub fn record_failure(&self, worker: &str, job: &str, reason: &str) -> Result<()> {
        let reason = clean_reason(reason);
        let count = lock(&self.db).record_failure(worker, job, &reason, now_ms())?;
        tracing::warn!(%worker, %job, count, %reason, "lease failed");
        if count >= self.cfg.block_after {
            if count == self.cfg.block_after {
                tracing::warn!(%worker, %job, "worker blocked from the job");
            }
            self.fail_if_stranded(job)?;
        }
        self.touch();
        Ok(())
    }

    /// Jobs the worker is blocked from.
    pub fn blocked_jobs(&self, worker: &str) -> Result<HashSet<String>> {
        let n = self.cfg.block_after;
        Ok(lock(&self.db)
            .failures_of_worker(worker)?
            .into_iter()
            .filter(|f| f.count >= n)
            .map(|f| f.job_id)
            .collect())
    }

    /// Why the worker is quarantined farm-wide, if it is: blocked from `--quarantine-after`
    /// jobs since the later of its last forgiveness and the TTL's start.
    pub fn quarantine(&self, worker: &str) -> Result<Option<String>> {
        let now = now_ms();
        let ttl_ms = (self.cfg.quarantine_ttl * 1000.0).min(i64::MAX as f64 / 2.0) as i64;
        let (rows, forgiven) = {
            let db = lock(&self.db);
            (db.failures_of_worker(worker)?, db.forgiven_ms(worker)?)
        };
        let since = forgiven.max(now.saturating_sub(ttl_ms));
        let recent = rows
            .iter()
            .filter(|f| f.count >= self.cfg.block_after && f.last_ms >= since)
            .count();
        Ok(
            (recent as u64 >= u64::from(self.cfg.quarantine_after)).then(|| {
                format!(
                    "blocked from {recent} jobs within {} s: quarantined until forgiven",
                    self.cfg.quarantine_ttl
                )
            }),
        )
    }

    /// An admin forgives a worker's quarantine (its blocks on single jobs stay).
    pub fn forgive(&self, worker: &str) -> Result<()> {
        if !lock(&self.db).forgive(worker, now_ms())? {
            return Err(crate::error::ServerError::NotFound(format!(
                "no worker {worker:?}"
            )));
        }
        tracing::info!(%worker, "worker forgiven");
        self.touch();
        self.work_available.notify_waiters();
        Ok(())
    }

    /// Fails `job` when there are live workers that could take it (tags, memory) and every
    /// one of them is blocked from it or quarantined (a job nobody may render would otherwise
    /// wait forever). With no such worker it waits: one may still join.
    pub fn fail_if_stranded(&self, job: &str) -> Result<()> {
        let row = self.job_row(job)?;
        if row.state.is_final() {
            return Ok(());
        }
        let live: Vec<(String, Vec<String>, u64)> = lock(&self.workers)
            .values()
            .filter(|w| !w.lost)
            .map(|w| (w.id.clone(), w.tags.clone(), w.memory_mb))
            .collect();
        let none = HashSet::new();
        let mut capable = 0;
        for (id, tags, memory_mb) in &live {
            let offer = crate::schedule::Offer {
                tags,
                memory_mb: *memory_mb,
                blocked: &none,
            };
            if !crate::schedule::can_take(&row, &offer, 0) {
                continue;
            }
            capable += 1;
            if !self.blocked_jobs(id)?.contains(job) && self.quarantine(id)?.is_none() {
                return Ok(());
            }
        }
        if capable == 0 {
            return Ok(());
        }
        let last = lock(&self.db)
            .failures_of_job(job)?
            .pop()
            .map(|f| f.reason)
            .unwrap_or_default();
        let reason = format!(
            "every worker is blocked from this job after {} failed leases each; last failure: \
             {last}",
            self.cfg.block_after
        );
        tracing::error!(%job, %reason, "job failed");
        let rt = lock(&self.jobs).get(job).cloned();
        match rt {
            Some(rt) => crate::halt::finish(self, &rt, JobState::Failed, &reason),
            None => {
                lock(&self.db).set_job_state(job, JobState::Failed, &reason, now_ms())?;
                self.touch();
                Ok(())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reasons_lose_their_paths() {
        assert_eq!(
            clean_reason("cannot open /home/ann/scenes/a.lxs:3:1: no such\nfile"),
            "cannot open a.lxs:3:1: no such file"
        );
        assert_eq!(clean_reason(r"C:\farm\x.png bad"), "x.png bad");
        assert_eq!(clean_reason(&"x".repeat(900)).len(), MAX_REASON);
    }
}
