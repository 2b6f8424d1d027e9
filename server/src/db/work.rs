//! Workers, leases and the merge ledger in the store: registration with a hashed credential,
//! leases with their stream ids and sample budgets, the (lease, sequence) ledger and the
//! checkpoints that make its rows durable.

use super::{lease_from_row, split_tags, Db, LeaseRow, WorkerRow, LEASE_COLS};
use crate::error::Result;
use rusqlite::{params, OptionalExtension, Row};

const WORKER_COLS: &str = "id, name, threads, last_seen_ms, token_hash, tags, memory_mb, build";

fn worker_from_row(r: &Row<'_>) -> rusqlite::Result<WorkerRow> {
    Ok(WorkerRow {
        id: r.get(0)?,
        name: r.get(1)?,
        threads: r.get(2)?,
        last_seen_ms: r.get(3)?,
        token_hash: r.get(4)?,
        tags: split_tags(&r.get::<_, String>(5)?),
        memory_mb: r.get::<_, i64>(6)?.max(0) as u64,
        build: r.get(7)?,
    })
}

impl Db {
    /// Registers or refreshes a worker (what it declared, the hash of its credential).
    pub fn upsert_worker(&self, w: &WorkerRow) -> Result<()> {
        self.conn.execute(
            "INSERT INTO workers (id, name, threads, registered_ms, last_seen_ms, token_hash, \
             tags, memory_mb, build) VALUES (?1, ?2, ?3, ?4, ?4, ?5, ?6, ?7, ?8) \
             ON CONFLICT(id) DO UPDATE SET name = ?2, threads = ?3, last_seen_ms = ?4, \
             token_hash = ?5, tags = ?6, memory_mb = ?7, build = ?8",
            params![
                w.id,
                w.name,
                w.threads,
                w.last_seen_ms,
                w.token_hash,
                w.tags.join(","),
                w.memory_mb.min(i64::MAX as u64) as i64,
                w.build
            ],
        )?;
        Ok(())
    }

    /// One worker.
    pub fn worker(&self, id: &str) -> Result<Option<WorkerRow>> {
        let sql = format!("SELECT {WORKER_COLS} FROM workers WHERE id = ?1");
        Ok(self
            .conn
            .query_row(&sql, [id], worker_from_row)
            .optional()?)
    }

    /// The worker whose credential has this hash.
    pub fn worker_by_token(&self, token_hash: &str) -> Result<Option<WorkerRow>> {
        if token_hash.is_empty() {
            return Ok(None);
        }
        let sql = format!("SELECT {WORKER_COLS} FROM workers WHERE token_hash = ?1");
        Ok(self
            .conn
            .query_row(&sql, [token_hash], worker_from_row)
            .optional()?)
    }

    /// Creates a lease with the job's next stream id (stream ids never repeat within a job).
    pub fn create_lease(&mut self, id: &str, job: &str, worker: &str, now_ms: i64) -> Result<u64> {
        let tx = self.conn.transaction()?;
        let stream: i64 =
            tx.query_row("SELECT next_stream FROM jobs WHERE id = ?1", [job], |r| {
                r.get(0)
            })?;
        tx.execute(
            "UPDATE jobs SET next_stream = next_stream + 1, \
             first_lease_ms = COALESCE(first_lease_ms, ?2) WHERE id = ?1",
            params![job, now_ms],
        )?;
        tx.execute(
            "INSERT INTO leases (id, job_id, worker_id, stream, started_ms) \
             VALUES (?1, ?2, ?3, ?4, ?5)",
            params![id, job, worker, stream, now_ms],
        )?;
        tx.commit()?;
        Ok(stream as u64)
    }

    /// One lease.
    pub fn lease(&self, id: &str) -> Result<Option<LeaseRow>> {
        Ok(self
            .conn
            .query_row(
                &format!("SELECT {LEASE_COLS} FROM leases WHERE id = ?1"),
                [id],
                lease_from_row,
            )
            .optional()?)
    }

    /// Leases still open (not ended).
    pub fn open_leases(&self) -> Result<Vec<LeaseRow>> {
        let mut st = self.conn.prepare(&format!(
            "SELECT {LEASE_COLS} FROM leases WHERE ended_ms IS NULL"
        ))?;
        let rows = st.query_map([], lease_from_row)?;
        Ok(rows.collect::<rusqlite::Result<_>>()?)
    }

    /// Ends a lease with a reason (stopped, lost, cancelled, restart).
    pub fn end_lease(&self, id: &str, reason: &str, now_ms: i64) -> Result<()> {
        self.conn.execute(
            "UPDATE leases SET ended_ms = ?2, end_reason = ?3 WHERE id = ?1 AND ended_ms IS NULL",
            params![id, now_ms, reason],
        )?;
        Ok(())
    }

    /// True when (lease, seq) was already merged.
    pub fn ledger_has(&self, lease: &str, seq: u64) -> Result<bool> {
        let n: i64 = self.conn.query_row(
            "SELECT COUNT(*) FROM ledger WHERE lease_id = ?1 AND seq = ?2",
            params![lease, seq as i64],
            |r| r.get(0),
        )?;
        Ok(n > 0)
    }

    /// Records a merged delta (not yet durable: `ckpt_gen` NULL until the next checkpoint).
    pub fn ledger_insert(
        &self,
        lease: &str,
        seq: u64,
        job: &str,
        samples: f64,
        bytes: u64,
        now_ms: i64,
    ) -> Result<i64> {
        self.conn.execute(
            "INSERT INTO ledger (lease_id, seq, job_id, samples, bytes, merged_ms) \
             VALUES (?1, ?2, ?3, ?4, ?5, ?6)",
            params![lease, seq as i64, job, samples, bytes as i64, now_ms],
        )?;
        Ok(self.conn.last_insert_rowid())
    }

    /// Largest ledger row id (0 when empty): taken with a film snapshot for a checkpoint.
    pub fn ledger_max_rowid(&self) -> Result<i64> {
        Ok(self
            .conn
            .query_row("SELECT COALESCE(MAX(rowid), 0) FROM ledger", [], |r| {
                r.get(0)
            })?)
    }

    /// Commits a checkpoint: the job's ledger rows up to `max_rowid` become durable in
    /// generation `generation`, which becomes the job's checkpoint.
    pub fn commit_checkpoint(&mut self, job: &str, generation: i64, max_rowid: i64) -> Result<()> {
        let tx = self.conn.transaction()?;
        tx.execute(
            "UPDATE ledger SET ckpt_gen = ?2 WHERE job_id = ?1 AND ckpt_gen IS NULL \
             AND rowid <= ?3",
            params![job, generation, max_rowid],
        )?;
        tx.execute(
            "UPDATE jobs SET ckpt_gen = ?2 WHERE id = ?1",
            params![job, generation],
        )?;
        tx.commit()?;
        Ok(())
    }

    /// Forgets ledger rows never made durable (after a restart their samples are gone).
    pub fn drop_uncheckpointed(&self, job: &str) -> Result<usize> {
        Ok(self.conn.execute(
            "DELETE FROM ledger WHERE job_id = ?1 AND ckpt_gen IS NULL",
            [job],
        )?)
    }

    /// Merged samples and number of merged deltas of a job (ledger sums).
    pub fn job_totals(&self, job: &str) -> Result<(f64, u64)> {
        Ok(self.conn.query_row(
            "SELECT COALESCE(SUM(samples), 0), COUNT(*) FROM ledger WHERE job_id = ?1",
            [job],
            |r| Ok((r.get(0)?, r.get::<_, i64>(1)? as u64)),
        )?)
    }

    /// Samples merged per lease of a job (ledger sums), with the lease's worker.
    pub fn lease_samples(&self, job: &str) -> Result<Vec<(String, String, f64)>> {
        let mut st = self.conn.prepare(
            "SELECT l.id, l.worker_id, COALESCE(SUM(g.samples), 0) FROM leases l \
             LEFT JOIN ledger g ON g.lease_id = l.id WHERE l.job_id = ?1 GROUP BY l.id",
        )?;
        let rows = st.query_map([job], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)))?;
        Ok(rows.collect::<rusqlite::Result<_>>()?)
    }

    /// The open leases of one job.
    pub fn open_leases_of(&self, job: &str) -> Result<Vec<LeaseRow>> {
        let mut st = self.conn.prepare(&format!(
            "SELECT {LEASE_COLS} FROM leases WHERE job_id = ?1 AND ended_ms IS NULL"
        ))?;
        let rows = st.query_map([job], lease_from_row)?;
        Ok(rows.collect::<rusqlite::Result<_>>()?)
    }

    /// Open leases per job (jobs without one are absent).
    pub fn open_lease_counts(&self) -> Result<std::collections::HashMap<String, u32>> {
        let mut st = self.conn.prepare(
            "SELECT job_id, COUNT(*) FROM leases WHERE ended_ms IS NULL GROUP BY job_id",
        )?;
        let rows = st.query_map([], |r| Ok((r.get(0)?, r.get::<_, i64>(1)? as u32)))?;
        Ok(rows.collect::<rusqlite::Result<_>>()?)
    }

    /// Records the sample budget granted to a lease so far.
    pub fn set_lease_budget(&self, id: &str, budget: f64) -> Result<()> {
        self.conn.execute(
            "UPDATE leases SET budget = ?2 WHERE id = ?1",
            params![id, budget],
        )?;
        Ok(())
    }

    /// The highest sequence number of the lease held by a committed checkpoint (0: none).
    pub fn durable_seq(&self, lease: &str) -> Result<u64> {
        let n: i64 = self.conn.query_row(
            "SELECT COALESCE(MAX(seq), 0) FROM ledger WHERE lease_id = ?1 AND ckpt_gen IS NOT NULL",
            [lease],
            |r| r.get(0),
        )?;
        Ok(n.max(0) as u64)
    }

    /// Samples merged from one lease (ledger sum).
    pub fn lease_merged(&self, lease: &str) -> Result<f64> {
        Ok(self.conn.query_row(
            "SELECT COALESCE(SUM(samples), 0) FROM ledger WHERE lease_id = ?1",
            [lease],
            |r| r.get(0),
        )?)
    }
}
