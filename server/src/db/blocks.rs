//! Failed leases in the store: per (worker, job) a count, the last reason and when; and when an
//! admin last forgave each worker. `crate::blocks` decides from them who is blocked.

use super::Db;
use crate::error::Result;
use rusqlite::{params, Row};

/// Failed leases of one worker on one job.
#[derive(Clone, Debug)]
pub struct FailureRow {
    pub worker_id: String,
    pub job_id: String,
    pub count: u32,
    pub reason: String,
    pub last_ms: i64,
}

const COLS: &str = "worker_id, job_id, count, reason, last_ms";

fn failure_from_row(r: &Row<'_>) -> rusqlite::Result<FailureRow> {
    Ok(FailureRow {
        worker_id: r.get(0)?,
        job_id: r.get(1)?,
        count: r.get::<_, i64>(2)?.clamp(0, u32::MAX as i64) as u32,
        reason: r.get(3)?,
        last_ms: r.get(4)?,
    })
}

impl Db {
    /// Counts one more failed lease of `worker` on `job`; returns the new count.
    pub fn record_failure(
        &self,
        worker: &str,
        job: &str,
        reason: &str,
        now_ms: i64,
    ) -> Result<u32> {
        self.conn.execute(
            "INSERT INTO failures (worker_id, job_id, count, reason, last_ms) \
             VALUES (?1, ?2, 1, ?3, ?4) ON CONFLICT(worker_id, job_id) DO UPDATE SET \
             count = count + 1, reason = ?3, last_ms = ?4",
            params![worker, job, reason, now_ms],
        )?;
        let n: i64 = self.conn.query_row(
            "SELECT count FROM failures WHERE worker_id = ?1 AND job_id = ?2",
            params![worker, job],
            |r| r.get(0),
        )?;
        Ok(n.clamp(0, u32::MAX as i64) as u32)
    }

    /// The failures of one worker (every job).
    pub fn failures_of_worker(&self, worker: &str) -> Result<Vec<FailureRow>> {
        let mut st = self.conn.prepare(&format!(
            "SELECT {COLS} FROM failures WHERE worker_id = ?1 ORDER BY last_ms"
        ))?;
        let rows = st.query_map([worker], failure_from_row)?;
        Ok(rows.collect::<rusqlite::Result<_>>()?)
    }

    /// The failures on one job (every worker).
    pub fn failures_of_job(&self, job: &str) -> Result<Vec<FailureRow>> {
        let mut st = self.conn.prepare(&format!(
            "SELECT {COLS} FROM failures WHERE job_id = ?1 ORDER BY last_ms"
        ))?;
        let rows = st.query_map([job], failure_from_row)?;
        Ok(rows.collect::<rusqlite::Result<_>>()?)
    }

    /// When an admin last forgave the worker (0: never).
    pub fn forgiven_ms(&self, worker: &str) -> Result<i64> {
        use rusqlite::OptionalExtension;
        Ok(self
            .conn
            .query_row(
                "SELECT forgiven_ms FROM workers WHERE id = ?1",
                [worker],
                |r| r.get(0),
            )
            .optional()?
            .unwrap_or(0))
    }

    /// Forgives a worker's quarantine now; false when there is no such worker.
    pub fn forgive(&self, worker: &str, now_ms: i64) -> Result<bool> {
        Ok(self.conn.execute(
            "UPDATE workers SET forgiven_ms = ?2 WHERE id = ?1",
            params![worker, now_ms],
        )? > 0)
    }
}
