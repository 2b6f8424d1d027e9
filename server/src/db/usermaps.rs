//! User sampling maps in the store (table `sampling_maps`, schema version 5): per job the
//! weights as the user uploaded them (f32 little endian, row-major, the film buffer's size)
//! or NULL once cleared, and the map version the master gave the last change, so that a
//! restarted master hands the workers the same map at the same version (`crate::usermap`).

use super::Db;
use crate::error::{Result, ServerError};
use rusqlite::{params, OptionalExtension};

/// A job's user sampling map as stored.
#[derive(Clone, Debug, PartialEq)]
pub struct UserMapRow {
    pub job_id: String,
    pub width: u32,
    pub height: u32,
    /// The weights, row-major (None: cleared).
    pub weights: Option<Vec<f32>>,
    pub version: u64,
    pub updated_ms: i64,
}

fn to_bytes(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

impl Db {
    /// Stores (or with `weights` None, clears) the user sampling map of a job at `version`.
    pub fn set_user_map(
        &self,
        job_id: &str,
        (width, height): (u32, u32),
        weights: Option<&[f32]>,
        version: u64,
        now_ms: i64,
    ) -> Result<()> {
        self.conn.execute(
            "INSERT OR REPLACE INTO sampling_maps (job_id, width, height, weights, version, \
             updated_ms) VALUES (?1, ?2, ?3, ?4, ?5, ?6)",
            params![
                job_id,
                width,
                height,
                weights.map(to_bytes),
                version.min(i64::MAX as u64) as i64,
                now_ms
            ],
        )?;
        Ok(())
    }

    /// The job's user sampling map row (None: it never had one). A row whose weights do not
    /// fill its size is an error naming the job.
    pub fn user_map(&self, job_id: &str) -> Result<Option<UserMapRow>> {
        let row = self
            .conn
            .query_row(
                "SELECT width, height, weights, version, updated_ms FROM sampling_maps \
                 WHERE job_id = ?1",
                [job_id],
                |r| {
                    Ok((
                        r.get::<_, u32>(0)?,
                        r.get::<_, u32>(1)?,
                        r.get::<_, Option<Vec<u8>>>(2)?,
                        r.get::<_, i64>(3)?,
                        r.get::<_, i64>(4)?,
                    ))
                },
            )
            .optional()?;
        let Some((width, height, bytes, version, updated_ms)) = row else {
            return Ok(None);
        };
        let weights = match bytes {
            None => None,
            Some(b) => {
                let want = u64::from(width) * u64::from(height) * 4;
                if b.len() as u64 != want {
                    return Err(ServerError::Internal(format!(
                        "database farm.sqlite: the sampling map of job {job_id} has {} bytes \
                         for {width}x{height} weights",
                        b.len()
                    )));
                }
                Some(
                    b.chunks_exact(4)
                        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                        .collect(),
                )
            }
        };
        Ok(Some(UserMapRow {
            job_id: job_id.to_string(),
            width,
            height,
            weights,
            version: version.max(0) as u64,
            updated_ms,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maps_are_stored_cleared_and_read_back() {
        let dir = tempfile::tempdir().unwrap();
        let db = Db::open(&dir.path().join("farm.sqlite")).unwrap();
        assert_eq!(db.user_map("j1").unwrap(), None);
        db.set_user_map("j1", (2, 1), Some(&[9.0, 1.0]), 3, 10)
            .unwrap();
        let r = db.user_map("j1").unwrap().unwrap();
        assert_eq!(
            (r.width, r.height, r.weights.as_deref(), r.version),
            (2, 1, Some(&[9.0f32, 1.0][..]), 3)
        );
        db.set_user_map("j1", (2, 1), None, 4, 11).unwrap();
        let r = db.user_map("j1").unwrap().unwrap();
        assert_eq!((r.weights, r.version, r.updated_ms), (None, 4, 11));
        // reopened: still there
        drop(db);
        let db = Db::open(&dir.path().join("farm.sqlite")).unwrap();
        assert_eq!(db.user_map("j1").unwrap().unwrap().version, 4);
        // a row that does not fill its size is refused, not misread
        db.set_user_map("j2", (3, 1), Some(&[1.0]), 1, 1).unwrap();
        assert!(db.user_map("j2").is_err());
    }
}
