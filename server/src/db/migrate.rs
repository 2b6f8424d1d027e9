//! Schema versions of the store and the upgrades between them.
//!
//! The version is SQLite's `PRAGMA user_version`. A store is opened in three steps:
//!
//! ```text
//! open --base schema (CREATE TABLE IF NOT EXISTS, version 1's tables)-->
//!      --version 0 (a fresh store, or one written before versions were kept)-->
//!        upgrade to 1: the columns masters before 1 lacked, added when missing
//!      --upgrade to 2: frame sequences (table `sequences`, jobs' sequence_id/sequence_frame)
//!      --upgrade to 3: pools (workers' tags/memory/build, jobs' tags/min_memory/max_workers)
//!                      and failing workers (table `failures`, workers' forgiven_ms)
//!      --upgrade to 4: webhooks (jobs' own hook URL, the outbox table `webhooks`)
//!      --upgrade to 5: user sampling maps (table `sampling_maps`)
//! ```
//!
//! Every upgrade runs in one transaction together with the new version number, so a store is
//! either at the old version or fully at the new one. A store of a newer master than this
//! one (a version above [`CURRENT`]) is refused rather than written to.

use crate::error::{Result, ServerError};
use rusqlite::Connection;

/// The schema version this master writes.
pub const CURRENT: i64 = 5;

/// Columns a store written by a master before versions were kept may lack:
/// (table, column, type).
const VERSION_1_COLUMNS: &[(&str, &str, &str)] = &[
    ("jobs", "frame", "INTEGER"),
    ("jobs", "owner", "TEXT NOT NULL DEFAULT ''"),
    ("jobs", "notes", "TEXT NOT NULL DEFAULT ''"),
    ("workers", "token_hash", "TEXT NOT NULL DEFAULT ''"),
    ("leases", "budget", "REAL"),
];

/// Version 2: frame sequences.
const VERSION_2: &str = "
CREATE TABLE IF NOT EXISTS sequences (
    id TEXT PRIMARY KEY,
    name TEXT NOT NULL,
    policy TEXT NOT NULL,
    owner TEXT NOT NULL DEFAULT '',
    created_ms INTEGER NOT NULL
);
ALTER TABLE jobs ADD COLUMN sequence_id TEXT;
ALTER TABLE jobs ADD COLUMN sequence_frame INTEGER;
CREATE UNIQUE INDEX IF NOT EXISTS jobs_sequence_frame ON jobs (sequence_id, sequence_frame);
";

/// Version 3: worker pools (what workers offer, what jobs ask for) and failing workers (failed
/// leases per worker and job; when an admin last forgave a worker).
const VERSION_3: &str = "
ALTER TABLE workers ADD COLUMN tags TEXT NOT NULL DEFAULT '';
ALTER TABLE workers ADD COLUMN memory_mb INTEGER NOT NULL DEFAULT 0;
ALTER TABLE workers ADD COLUMN build TEXT NOT NULL DEFAULT '';
ALTER TABLE jobs ADD COLUMN tags TEXT NOT NULL DEFAULT '';
ALTER TABLE jobs ADD COLUMN min_memory_mb INTEGER NOT NULL DEFAULT 0;
ALTER TABLE jobs ADD COLUMN max_workers INTEGER NOT NULL DEFAULT 0;
ALTER TABLE workers ADD COLUMN forgiven_ms INTEGER NOT NULL DEFAULT 0;
CREATE TABLE IF NOT EXISTS failures (
    worker_id TEXT NOT NULL,
    job_id TEXT NOT NULL,
    count INTEGER NOT NULL,
    reason TEXT NOT NULL,
    last_ms INTEGER NOT NULL,
    PRIMARY KEY (worker_id, job_id)
);
";

/// Version 4: webhooks. A job's own hook URL, and the outbox of deliveries: one row per
/// (job, event, URL), written in the transaction that records the job's end, kept until it
/// is delivered or given up (`crate::webhooks`).
const VERSION_4: &str = "
ALTER TABLE jobs ADD COLUMN webhook TEXT NOT NULL DEFAULT '';
CREATE TABLE IF NOT EXISTS webhooks (
    id TEXT PRIMARY KEY,
    job_id TEXT NOT NULL,
    event TEXT NOT NULL,
    scope TEXT NOT NULL,
    url TEXT NOT NULL,
    payload TEXT NOT NULL,
    created_ms INTEGER NOT NULL,
    attempts INTEGER NOT NULL DEFAULT 0,
    next_ms INTEGER NOT NULL,
    last_status INTEGER,
    last_error TEXT NOT NULL DEFAULT '',
    delivered_ms INTEGER,
    gave_up_ms INTEGER
);
CREATE UNIQUE INDEX IF NOT EXISTS webhooks_once ON webhooks (job_id, event, url);
CREATE INDEX IF NOT EXISTS webhooks_pending ON webhooks (next_ms)
    WHERE delivered_ms IS NULL AND gave_up_ms IS NULL;
";

/// Version 5: user sampling maps, one row per job that ever had one (`crate::usermap`): the
/// weights as uploaded (f32 little endian, row-major; NULL once cleared) and the map version
/// the master gave the last change.
const VERSION_5: &str = "
CREATE TABLE IF NOT EXISTS sampling_maps (
    job_id TEXT PRIMARY KEY,
    width INTEGER NOT NULL,
    height INTEGER NOT NULL,
    weights BLOB,
    version INTEGER NOT NULL,
    updated_ms INTEGER NOT NULL
);
";

/// The store's schema version.
pub fn version(conn: &Connection) -> Result<i64> {
    Ok(conn.query_row("PRAGMA user_version", [], |r| r.get(0))?)
}

/// Brings a store (whose base tables exist) to [`CURRENT`], one version at a time.
pub fn upgrade(conn: &mut Connection) -> Result<()> {
    let mut v = version(conn)?;
    if v > CURRENT {
        return Err(ServerError::Internal(format!(
            "database farm.sqlite: schema version {v} was written by a newer master (this one \
             knows versions up to {CURRENT}); run that master or restore a backup"
        )));
    }
    while v < CURRENT {
        let next = v + 1;
        let tx = conn.transaction()?;
        match next {
            1 => {
                for (table, column, ty) in VERSION_1_COLUMNS {
                    add_column_if_missing(&tx, table, column, ty)?;
                }
            }
            2 => tx.execute_batch(VERSION_2)?,
            3 => tx.execute_batch(VERSION_3)?,
            4 => tx.execute_batch(VERSION_4)?,
            _ => tx.execute_batch(VERSION_5)?,
        }
        tx.pragma_update(None, "user_version", next)?;
        tx.commit()?;
        tracing::info!(from = v, to = next, "store schema upgraded");
        v = next;
    }
    Ok(())
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
