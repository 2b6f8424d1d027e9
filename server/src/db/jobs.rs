//! Jobs in the store: insertion in submission order, lookups in scheduling order, states.

use super::{job_from_row, Db, JobRow, JobState, NewJob, JOB_COLS};
use crate::error::Result;
use rusqlite::{params, OptionalExtension};

impl Db {
    /// Inserts a queued job; its submission order is one past the largest so far.
    pub fn insert_job(&self, j: &NewJob<'_>) -> Result<()> {
        self.conn.execute(
            "INSERT INTO jobs (id, ord, name, state, priority, bundle_hash, scene_path, seed, \
             haltspp, halttime, haltthreshold, width, height, submitted_ms, frame, owner, notes, \
             sequence_id, sequence_frame, tags, min_memory_mb, max_workers, webhook) \
             VALUES (?1, (SELECT COALESCE(MAX(ord), 0) + 1 FROM jobs), ?2, 'queued', ?3, ?4, ?5, \
             ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16, ?17, ?18, ?19, ?20, ?21)",
            params![
                j.id,
                j.name,
                j.priority,
                j.bundle_hash,
                j.scene_path,
                j.seed as i64,
                j.haltspp,
                j.halttime,
                j.haltthreshold,
                j.width,
                j.height,
                j.submitted_ms,
                j.frame,
                j.owner,
                j.notes.join("\n"),
                j.sequence_id,
                j.sequence_frame,
                j.tags.join(","),
                j.min_memory_mb.min(i64::MAX as u64) as i64,
                j.max_workers,
                j.webhook,
            ],
        )?;
        Ok(())
    }

    /// One job.
    pub fn job(&self, id: &str) -> Result<Option<JobRow>> {
        let sql = format!("SELECT {JOB_COLS} FROM jobs WHERE id = ?1");
        Ok(self.conn.query_row(&sql, [id], job_from_row).optional()?)
    }

    /// All jobs in scheduling order: priority (high first), then submission order.
    pub fn jobs(&self) -> Result<Vec<JobRow>> {
        let sql = format!("SELECT {JOB_COLS} FROM jobs ORDER BY priority DESC, ord ASC");
        let mut st = self.conn.prepare(&sql)?;
        let rows = st.query_map([], job_from_row)?;
        Ok(rows.collect::<rusqlite::Result<_>>()?)
    }

    /// Number of jobs stored.
    pub fn job_count(&self) -> Result<u64> {
        Ok(self
            .conn
            .query_row("SELECT COUNT(*) FROM jobs", [], |r| r.get::<_, i64>(0))? as u64)
    }

    /// Sets a job's state, reason and (for final states) finish time. This is the one place a
    /// job's end is written: when the job enters a final state its webhook deliveries are
    /// queued in the same transaction (`outbox`), so a master that stops right after still
    /// sends them when it is back.
    pub fn set_job_state(
        &self,
        id: &str,
        state: JobState,
        reason: &str,
        now_ms: i64,
    ) -> Result<()> {
        let finished = state.is_final().then_some(now_ms);
        let tx = self.conn.unchecked_transaction()?;
        let before: Option<String> = tx
            .query_row("SELECT state FROM jobs WHERE id = ?1", [id], |r| r.get(0))
            .optional()?;
        tx.execute(
            "UPDATE jobs SET state = ?2, reason = ?3, finished_ms = COALESCE(?4, finished_ms) \
             WHERE id = ?1",
            params![id, state.as_str(), reason, finished],
        )?;
        let was_final = before
            .as_deref()
            .and_then(JobState::parse)
            .is_some_and(JobState::is_final);
        let queued = if state.is_final() && !was_final && before.is_some() {
            self.queue_hooks(id, state.as_str(), None, now_ms)?
        } else {
            0
        };
        tx.commit()?;
        if queued > 0 {
            self.hooks.wake.notify_one();
        }
        Ok(())
    }

    /// Sets a job's reason only (a fault being retried, shown while the job goes on).
    pub fn set_job_reason(&self, id: &str, reason: &str) -> Result<()> {
        self.conn.execute(
            "UPDATE jobs SET reason = ?2 WHERE id = ?1",
            params![id, reason],
        )?;
        Ok(())
    }
}
