//! The master's SQLite store (rusqlite, bundled) in `--data-dir/farm.sqlite`: jobs, workers,
//! leases and the merge ledger of (lease id, sequence number) pairs already merged.
//!
//! The ledger rows carry the checkpoint generation that made them durable: rows merged after the
//! last checkpoint are forgotten on restart together with the in-memory film they went into, so
//! a restarted master never counts a delta twice.

use crate::error::Result;
use rusqlite::{params, Connection, OptionalExtension, Row};
use std::path::Path;

/// Job states. `Rendering` covers the halting phase (waiting for the last deltas).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, utoipa::ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum JobState {
    Queued,
    Rendering,
    Done,
    Cancelled,
    Failed,
}

impl JobState {
    /// The name stored in the database and shown in the API.
    pub fn as_str(self) -> &'static str {
        match self {
            JobState::Queued => "queued",
            JobState::Rendering => "rendering",
            JobState::Done => "done",
            JobState::Cancelled => "cancelled",
            JobState::Failed => "failed",
        }
    }

    /// Parses a stored name.
    pub fn parse(s: &str) -> Option<JobState> {
        Some(match s {
            "queued" => JobState::Queued,
            "rendering" => JobState::Rendering,
            "done" => JobState::Done,
            "cancelled" => JobState::Cancelled,
            "failed" => JobState::Failed,
            _ => return None,
        })
    }

    /// Done, cancelled or failed.
    pub fn is_final(self) -> bool {
        matches!(
            self,
            JobState::Done | JobState::Cancelled | JobState::Failed
        )
    }
}

/// One job as stored.
#[derive(Clone, Debug)]
pub struct JobRow {
    pub id: String,
    pub name: String,
    pub state: JobState,
    pub reason: String,
    pub priority: i32,
    pub bundle_hash: String,
    pub scene_path: String,
    pub seed: u64,
    pub haltspp: Option<f64>,
    pub halttime: Option<f64>,
    pub haltthreshold: Option<f64>,
    pub width: u32,
    pub height: u32,
    pub submitted_ms: i64,
    pub first_lease_ms: Option<i64>,
    pub finished_ms: Option<i64>,
    pub ckpt_gen: i64,
    /// The animation frame the job renders (animated formats), when given.
    pub frame: Option<i64>,
}

/// A new job to insert.
pub struct NewJob<'a> {
    pub id: &'a str,
    pub name: &'a str,
    pub priority: i32,
    pub bundle_hash: &'a str,
    pub scene_path: &'a str,
    pub seed: u64,
    pub haltspp: Option<f64>,
    pub halttime: Option<f64>,
    pub haltthreshold: Option<f64>,
    pub width: u32,
    pub height: u32,
    pub submitted_ms: i64,
    pub frame: Option<i64>,
}

/// One lease as stored.
#[derive(Clone, Debug)]
pub struct LeaseRow {
    pub id: String,
    pub job_id: String,
    pub worker_id: String,
}

/// The store: one connection, used under the caller's lock.
pub struct Db {
    conn: Connection,
}

const SCHEMA: &str = "
CREATE TABLE IF NOT EXISTS jobs (
    id TEXT PRIMARY KEY,
    ord INTEGER NOT NULL,
    name TEXT NOT NULL,
    state TEXT NOT NULL,
    reason TEXT NOT NULL DEFAULT '',
    priority INTEGER NOT NULL,
    bundle_hash TEXT NOT NULL,
    scene_path TEXT NOT NULL,
    seed INTEGER NOT NULL,
    haltspp REAL, halttime REAL, haltthreshold REAL,
    width INTEGER NOT NULL, height INTEGER NOT NULL,
    submitted_ms INTEGER NOT NULL,
    first_lease_ms INTEGER, finished_ms INTEGER,
    next_stream INTEGER NOT NULL DEFAULT 1,
    ckpt_gen INTEGER NOT NULL DEFAULT 0,
    frame INTEGER
);
CREATE TABLE IF NOT EXISTS workers (
    id TEXT PRIMARY KEY,
    name TEXT NOT NULL,
    threads INTEGER NOT NULL,
    registered_ms INTEGER NOT NULL,
    last_seen_ms INTEGER NOT NULL
);
CREATE TABLE IF NOT EXISTS leases (
    id TEXT PRIMARY KEY,
    job_id TEXT NOT NULL,
    worker_id TEXT NOT NULL,
    stream INTEGER NOT NULL,
    started_ms INTEGER NOT NULL,
    ended_ms INTEGER,
    end_reason TEXT
);
CREATE TABLE IF NOT EXISTS ledger (
    lease_id TEXT NOT NULL,
    seq INTEGER NOT NULL,
    job_id TEXT NOT NULL,
    samples REAL NOT NULL,
    bytes INTEGER NOT NULL,
    merged_ms INTEGER NOT NULL,
    ckpt_gen INTEGER,
    PRIMARY KEY (lease_id, seq)
);
CREATE INDEX IF NOT EXISTS ledger_job ON ledger (job_id);
";

const JOB_COLS: &str = "id, name, state, reason, priority, bundle_hash, scene_path, seed, \
    haltspp, halttime, haltthreshold, width, height, submitted_ms, first_lease_ms, finished_ms, \
    ckpt_gen, frame";

fn job_from_row(r: &Row<'_>) -> rusqlite::Result<JobRow> {
    let state: String = r.get(2)?;
    Ok(JobRow {
        id: r.get(0)?,
        name: r.get(1)?,
        state: JobState::parse(&state).unwrap_or(JobState::Failed),
        reason: r.get(3)?,
        priority: r.get(4)?,
        bundle_hash: r.get(5)?,
        scene_path: r.get(6)?,
        seed: r.get::<_, i64>(7)? as u64,
        haltspp: r.get(8)?,
        halttime: r.get(9)?,
        haltthreshold: r.get(10)?,
        width: r.get(11)?,
        height: r.get(12)?,
        submitted_ms: r.get(13)?,
        first_lease_ms: r.get(14)?,
        finished_ms: r.get(15)?,
        ckpt_gen: r.get(16)?,
        frame: r.get(17)?,
    })
}

/// Adds a column that a store written by an older master lacks.
fn add_column_if_missing(conn: &Connection, table: &str, column: &str, ty: &str) -> Result<()> {
    let mut st = conn.prepare(&format!("PRAGMA table_info({table})"))?;
    let names = st.query_map([], |r| r.get::<_, String>(1))?;
    for n in names {
        if n? == column {
            return Ok(());
        }
    }
    conn.execute_batch(&format!("ALTER TABLE {table} ADD COLUMN {column} {ty}"))?;
    Ok(())
}

/// The columns [`lease_from_row`] reads, in its order.
const LEASE_COLS: &str = "id, job_id, worker_id";

fn lease_from_row(r: &Row<'_>) -> rusqlite::Result<LeaseRow> {
    Ok(LeaseRow {
        id: r.get(0)?,
        job_id: r.get(1)?,
        worker_id: r.get(2)?,
    })
}

impl Db {
    /// Opens (creating) the store at `path`.
    pub fn open(path: &Path) -> Result<Db> {
        let conn = Connection::open(path)?;
        conn.pragma_update(None, "journal_mode", "WAL")?;
        conn.pragma_update(None, "synchronous", "NORMAL")?;
        conn.execute_batch(SCHEMA)?;
        add_column_if_missing(&conn, "jobs", "frame", "INTEGER")?;
        Ok(Db { conn })
    }

    /// Inserts a queued job; its submission order is one past the largest so far.
    pub fn insert_job(&self, j: &NewJob<'_>) -> Result<()> {
        self.conn.execute(
            "INSERT INTO jobs (id, ord, name, state, priority, bundle_hash, scene_path, seed, \
             haltspp, halttime, haltthreshold, width, height, submitted_ms, frame) \
             VALUES (?1, (SELECT COALESCE(MAX(ord), 0) + 1 FROM jobs), ?2, 'queued', ?3, ?4, ?5, \
             ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13)",
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
                j.frame
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

    /// Sets a job's state, reason and (for final states) finish time.
    pub fn set_job_state(
        &self,
        id: &str,
        state: JobState,
        reason: &str,
        now_ms: i64,
    ) -> Result<()> {
        let finished = state.is_final().then_some(now_ms);
        self.conn.execute(
            "UPDATE jobs SET state = ?2, reason = ?3, finished_ms = COALESCE(?4, finished_ms) \
             WHERE id = ?1",
            params![id, state.as_str(), reason, finished],
        )?;
        Ok(())
    }

    /// Registers or refreshes a worker.
    pub fn upsert_worker(&self, id: &str, name: &str, threads: u32, now_ms: i64) -> Result<()> {
        self.conn.execute(
            "INSERT INTO workers (id, name, threads, registered_ms, last_seen_ms) \
             VALUES (?1, ?2, ?3, ?4, ?4) ON CONFLICT(id) DO UPDATE SET name = ?2, threads = ?3, \
             last_seen_ms = ?4",
            params![id, name, threads, now_ms],
        )?;
        Ok(())
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
}

#[cfg(test)]
mod tests {
    use super::*;

    fn new_job<'a>(id: &'a str, priority: i32) -> NewJob<'a> {
        NewJob {
            id,
            name: id,
            priority,
            bundle_hash: "h",
            scene_path: "s.lxs",
            seed: 7,
            haltspp: Some(4.0),
            halttime: None,
            haltthreshold: None,
            width: 8,
            height: 6,
            submitted_ms: 1,
            frame: None,
        }
    }

    #[test]
    fn a_store_of_an_older_master_gains_the_frame_column() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("farm.sqlite");
        {
            let conn = Connection::open(&path).unwrap();
            // The jobs table as masters before the frame option wrote it.
            let old = SCHEMA.replace(",\n    frame INTEGER\n", "\n");
            assert!(!old.contains("frame INTEGER"));
            conn.execute_batch(&old).unwrap();
        }
        let db = Db::open(&path).unwrap();
        let mut j = new_job("a", 0);
        j.frame = Some(12);
        db.insert_job(&j).unwrap();
        assert_eq!(db.job("a").unwrap().unwrap().frame, Some(12));
        drop(db);
        // Opening again finds the column and leaves it.
        let db = Db::open(&path).unwrap();
        assert_eq!(db.job("a").unwrap().unwrap().frame, Some(12));
    }

    #[test]
    fn jobs_order_by_priority_then_submission() {
        let dir = tempfile::tempdir().unwrap();
        let db = Db::open(&dir.path().join("db")).unwrap();
        db.insert_job(&new_job("a", 0)).unwrap();
        db.insert_job(&new_job("b", 5)).unwrap();
        db.insert_job(&new_job("c", 0)).unwrap();
        let ids: Vec<_> = db.jobs().unwrap().into_iter().map(|j| j.id).collect();
        assert_eq!(ids, ["b", "a", "c"]);
    }

    #[test]
    fn leases_get_distinct_streams_and_ledger_checkpoints() {
        let dir = tempfile::tempdir().unwrap();
        let mut db = Db::open(&dir.path().join("db")).unwrap();
        db.insert_job(&new_job("a", 0)).unwrap();
        let s1 = db.create_lease("l1", "a", "w", 10).unwrap();
        let s2 = db.create_lease("l2", "a", "w", 11).unwrap();
        assert_ne!(s1, s2);
        assert_eq!(db.job("a").unwrap().unwrap().first_lease_ms, Some(10));
        db.ledger_insert("l1", 1, "a", 48.0, 10, 12).unwrap();
        let max = db.ledger_max_rowid().unwrap();
        db.commit_checkpoint("a", 1, max).unwrap();
        db.ledger_insert("l1", 2, "a", 48.0, 10, 13).unwrap();
        assert!(db.ledger_has("l1", 2).unwrap());
        assert_eq!(db.drop_uncheckpointed("a").unwrap(), 1);
        assert!(db.ledger_has("l1", 1).unwrap());
        assert!(!db.ledger_has("l1", 2).unwrap());
    }
}
