//! Frame sequences in the store: a sequence is a name and a scheduling policy; its frames are
//! ordinary jobs carrying the sequence's id and their frame number.

use super::{job_from_row, Db, JobRow, JOB_COLS};
use crate::error::Result;
use rusqlite::{params, OptionalExtension, Row};

/// One sequence as stored.
#[derive(Clone, Debug)]
pub struct SequenceRow {
    pub id: String,
    pub name: String,
    /// `spread` or `earliest` (see `crate::sequence::Policy`).
    pub policy: String,
    pub owner: String,
    pub created_ms: i64,
}

const SEQ_COLS: &str = "id, name, policy, owner, created_ms";

fn sequence_from_row(r: &Row<'_>) -> rusqlite::Result<SequenceRow> {
    Ok(SequenceRow {
        id: r.get(0)?,
        name: r.get(1)?,
        policy: r.get(2)?,
        owner: r.get(3)?,
        created_ms: r.get(4)?,
    })
}

impl Db {
    /// Records a new (empty) sequence.
    pub fn insert_sequence(
        &self,
        id: &str,
        name: &str,
        policy: &str,
        owner: &str,
        now_ms: i64,
    ) -> Result<()> {
        self.conn.execute(
            "INSERT INTO sequences (id, name, policy, owner, created_ms) \
             VALUES (?1, ?2, ?3, ?4, ?5)",
            params![id, name, policy, owner, now_ms],
        )?;
        Ok(())
    }

    /// One sequence.
    pub fn sequence(&self, id: &str) -> Result<Option<SequenceRow>> {
        let sql = format!("SELECT {SEQ_COLS} FROM sequences WHERE id = ?1");
        Ok(self
            .conn
            .query_row(&sql, [id], sequence_from_row)
            .optional()?)
    }

    /// Every sequence, oldest first.
    pub fn sequences(&self) -> Result<Vec<SequenceRow>> {
        let sql = format!("SELECT {SEQ_COLS} FROM sequences ORDER BY created_ms, id");
        let mut st = self.conn.prepare(&sql)?;
        let rows = st.query_map([], sequence_from_row)?;
        Ok(rows.collect::<rusqlite::Result<_>>()?)
    }

    /// The frames (jobs) of a sequence by frame number, then submission.
    pub fn sequence_jobs(&self, id: &str) -> Result<Vec<JobRow>> {
        let sql = format!(
            "SELECT {JOB_COLS} FROM jobs WHERE sequence_id = ?1 ORDER BY sequence_frame, ord"
        );
        let mut st = self.conn.prepare(&sql)?;
        let rows = st.query_map([id], job_from_row)?;
        Ok(rows.collect::<rusqlite::Result<_>>()?)
    }

    /// True when the sequence already has a frame with this number.
    pub fn sequence_has_frame(&self, id: &str, frame: i64) -> Result<bool> {
        let n: i64 = self.conn.query_row(
            "SELECT COUNT(*) FROM jobs WHERE sequence_id = ?1 AND sequence_frame = ?2",
            params![id, frame],
            |r| r.get(0),
        )?;
        Ok(n > 0)
    }
}
