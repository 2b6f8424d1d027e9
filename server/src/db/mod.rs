//! The master's SQLite store (rusqlite, bundled) in `--data-dir/farm.sqlite`: the farm's
//! identity, jobs, workers (with their hashed credentials), leases, the merge ledger of
//! (lease id, sequence number) pairs already merged, and user tokens (hashed).
//!
//! The ledger rows carry the checkpoint generation that made them durable: rows merged after the
//! last checkpoint are forgotten on restart together with the in-memory film they went into (the
//! workers still hold those deltas and upload them again), so a restarted master never counts a
//! delta twice. Commits are synchronous (`synchronous = FULL`): a checkpoint's commit survives a
//! power loss as its file does.
//!
//! Queries live by subject: [`jobs`] (jobs), [`sequences`] (frame sequences), [`work`]
//! (workers, leases, ledger, checkpoints), [`tokens`] (user tokens), [`outbox`] (webhook
//! deliveries, queued with a job's end in one transaction), [`usermaps`] (user sampling
//! maps); [`migrate`] upgrades a
//! store of an older master (schema versions); this file holds the types, the base schema and
//! opening.

mod blocks;
mod jobs;
pub mod migrate;
mod outbox;
mod sequences;
mod tokens;
mod usermaps;
mod work;

pub use blocks::FailureRow;
pub use outbox::{HookOutcome, HookRow, HookTargets};
pub use sequences::SequenceRow;
pub use usermaps::UserMapRow;

use crate::error::Result;
use rusqlite::{Connection, OptionalExtension, Row};
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
    /// Who submitted the job (a token's name; empty on an open farm).
    pub owner: String,
    /// The master's notes about the job (one per line), e.g. a default halt rule.
    pub notes: Vec<String>,
    /// The frame sequence the job belongs to, and its frame number there.
    pub sequence_id: Option<String>,
    pub sequence_frame: Option<i64>,
    /// Tags a worker must all have to take the job.
    pub tags: Vec<String>,
    /// The memory (MiB) a worker must have to take the job (0: any).
    pub min_memory_mb: u64,
    /// The most workers holding leases of the job at once (0: no limit).
    pub max_workers: u32,
    /// The job's own webhook URL (empty: none).
    pub webhook: String,
}

impl JobRow {
    /// The file name of the job's output: `NAME_0001.EXT` for a frame of a sequence (its job
    /// name, which the master gives it), `image.EXT` otherwise.
    pub fn output_name(&self, ext: &str) -> String {
        match self.sequence_frame {
            Some(_) if self.sequence_id.is_some() => format!("{}.{ext}", self.name),
            _ => format!("image.{ext}"),
        }
    }
}

/// A new job to insert.
#[derive(Default)]
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
    pub owner: &'a str,
    pub notes: &'a [String],
    pub sequence_id: Option<&'a str>,
    pub sequence_frame: Option<i64>,
    pub tags: &'a [String],
    pub min_memory_mb: u64,
    pub max_workers: u32,
    pub webhook: &'a str,
}

/// One lease as stored.
#[derive(Clone, Debug)]
pub struct LeaseRow {
    pub id: String,
    pub job_id: String,
    pub worker_id: String,
    /// The sample budget granted so far (None: unbounded).
    pub budget: Option<f64>,
}

/// One worker as stored.
#[derive(Clone, Debug)]
pub struct WorkerRow {
    pub id: String,
    pub name: String,
    pub threads: u32,
    pub last_seen_ms: i64,
    /// sha256 (hex) of the worker's credential.
    pub token_hash: String,
    /// What the worker declared: its tags, memory (MiB, 0: unknown) and build.
    pub tags: Vec<String>,
    pub memory_mb: u64,
    pub build: String,
}

/// One user token as stored (its hash, never the token).
#[derive(Clone, Debug)]
pub struct TokenRow {
    pub id: String,
    pub name: String,
    pub role: String,
    pub hash: String,
    pub created_ms: i64,
    pub revoked_ms: Option<i64>,
}

/// The store: one connection, used under the caller's lock.
pub struct Db {
    conn: Connection,
    /// Where the outbox sends a job's events, and the wake-up of the delivery task.
    hooks: HookTargets,
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
    frame INTEGER,
    owner TEXT NOT NULL DEFAULT '',
    notes TEXT NOT NULL DEFAULT ''
);
CREATE TABLE IF NOT EXISTS workers (
    id TEXT PRIMARY KEY,
    name TEXT NOT NULL,
    threads INTEGER NOT NULL,
    registered_ms INTEGER NOT NULL,
    last_seen_ms INTEGER NOT NULL,
    token_hash TEXT NOT NULL DEFAULT ''
);
CREATE TABLE IF NOT EXISTS leases (
    id TEXT PRIMARY KEY,
    job_id TEXT NOT NULL,
    worker_id TEXT NOT NULL,
    stream INTEGER NOT NULL,
    started_ms INTEGER NOT NULL,
    ended_ms INTEGER,
    end_reason TEXT,
    budget REAL
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
CREATE TABLE IF NOT EXISTS meta (
    key TEXT PRIMARY KEY,
    value TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS tokens (
    id TEXT PRIMARY KEY,
    name TEXT NOT NULL,
    role TEXT NOT NULL,
    hash TEXT NOT NULL UNIQUE,
    created_ms INTEGER NOT NULL,
    revoked_ms INTEGER
);
";

const JOB_COLS: &str = "id, name, state, reason, priority, bundle_hash, scene_path, seed, \
    haltspp, halttime, haltthreshold, width, height, submitted_ms, first_lease_ms, finished_ms, \
    ckpt_gen, frame, owner, notes, sequence_id, sequence_frame, tags, min_memory_mb, max_workers, \
    webhook";

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
        owner: r.get(18)?,
        notes: r
            .get::<_, String>(19)?
            .lines()
            .map(str::to_string)
            .collect(),
        sequence_id: r.get(20)?,
        sequence_frame: r.get(21)?,
        tags: split_tags(&r.get::<_, String>(22)?),
        min_memory_mb: r.get::<_, i64>(23)?.max(0) as u64,
        max_workers: r.get::<_, i64>(24)?.clamp(0, u32::MAX as i64) as u32,
        webhook: r.get(25)?,
    })
}

/// Tags as stored: one text, comma-separated.
pub fn split_tags(text: &str) -> Vec<String> {
    text.split(',')
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .map(str::to_string)
        .collect()
}

/// The columns [`lease_from_row`] reads, in its order.
const LEASE_COLS: &str = "id, job_id, worker_id, budget";

fn lease_from_row(r: &Row<'_>) -> rusqlite::Result<LeaseRow> {
    Ok(LeaseRow {
        id: r.get(0)?,
        job_id: r.get(1)?,
        worker_id: r.get(2)?,
        budget: r.get(3)?,
    })
}

impl Db {
    /// Opens (creating) the store at `path`, upgrading an older master's schema.
    pub fn open(path: &Path) -> Result<Db> {
        let mut conn = Connection::open(path)?;
        conn.pragma_update(None, "journal_mode", "WAL")?;
        conn.pragma_update(None, "synchronous", "FULL")?;
        if migrate::version(&conn)? <= migrate::CURRENT {
            conn.execute_batch(SCHEMA)?;
        }
        migrate::upgrade(&mut conn)?;
        Ok(Db {
            conn,
            hooks: HookTargets::default(),
        })
    }

    /// The farm's id, set once when the store is created (None for a store without one).
    pub fn farm_id(&self) -> Result<Option<String>> {
        Ok(self
            .conn
            .query_row("SELECT value FROM meta WHERE key = 'farm_id'", [], |r| {
                r.get(0)
            })
            .optional()?)
    }

    /// Records the farm's id.
    pub fn set_farm_id(&self, id: &str) -> Result<()> {
        self.conn.execute(
            "INSERT OR REPLACE INTO meta (key, value) VALUES ('farm_id', ?1)",
            [id],
        )?;
        Ok(())
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
            owner: "",
            notes: &[],
            sequence_id: None,
            sequence_frame: None,
            tags: &[],
            min_memory_mb: 0,
            max_workers: 0,
            webhook: "",
        }
    }

    #[test]
    fn a_store_before_schema_versions_is_upgraded_in_place_keeping_its_jobs() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("farm.sqlite");
        {
            let conn = Connection::open(&path).unwrap();
            conn.execute_batch(SCHEMA).unwrap();
            conn.execute(
                "INSERT INTO jobs (id, ord, name, state, priority, bundle_hash, scene_path, seed, \
                 width, height, submitted_ms) VALUES ('old', 1, 'old', 'queued', 3, 'h', \
                 's.lxs', 1, 8, 6, 1)",
                [],
            )
            .unwrap();
            assert_eq!(migrate::version(&conn).unwrap(), 0);
        }
        let db = Db::open(&path).unwrap();
        assert_eq!(migrate::version(&db.conn).unwrap(), migrate::CURRENT);
        let old = db.job("old").unwrap().unwrap();
        assert_eq!(
            (old.priority, old.sequence_id, old.max_workers),
            (3, None, 0)
        );
        db.insert_sequence("q1", "shot", "spread", "", 5).unwrap();
        let mut j = new_job("f1", 0);
        j.sequence_id = Some("q1");
        j.sequence_frame = Some(7);
        db.insert_job(&j).unwrap();
        drop(db);
        // A second open finds the current version and changes nothing.
        let db = Db::open(&path).unwrap();
        let f1 = db.job("f1").unwrap().unwrap();
        assert_eq!(f1.sequence_id.as_deref(), Some("q1"));
        assert_eq!(f1.sequence_frame, Some(7));
        assert_eq!(db.sequence_jobs("q1").unwrap().len(), 1);
    }

    #[test]
    fn a_store_of_a_newer_master_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("farm.sqlite");
        {
            let conn = Connection::open(&path).unwrap();
            conn.pragma_update(None, "user_version", migrate::CURRENT + 1)
                .unwrap();
        }
        let e = Db::open(&path).err().expect("refused");
        assert!(e.to_string().contains("newer master"), "{e}");
    }

    #[test]
    fn a_store_of_an_older_master_gains_the_new_columns() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("farm.sqlite");
        {
            let conn = Connection::open(&path).unwrap();
            // The tables as masters before the frame option wrote them.
            let old = SCHEMA
                .replace(
                    ",\n    frame INTEGER,\n    owner TEXT NOT NULL DEFAULT '',\n    notes TEXT NOT NULL DEFAULT ''\n",
                    "\n",
                )
                .replace(",\n    token_hash TEXT NOT NULL DEFAULT ''\n", "\n")
                .replace(",\n    budget REAL\n", "\n");
            assert!(!old.contains("frame INTEGER"));
            assert!(!old.contains("token_hash"));
            assert!(!old.contains("budget"));
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
