//! The data directory at startup: its layout, its identity, and the check that the database
//! matches what the directory holds, before the master serves anything.
//!
//! ```text
//! data dir: farm-id  farm.sqlite  bundles/HASH.tar  scenes/HASH/  jobs/ID/checkpoint-N.lxd  tmp/
//! ```
//!
//! - The farm's id is written both in `farm-id` and in the database when the farm is created.
//!   A database that lacks it while the directory has one (emptied or replaced), or holds
//!   another, is refused: the master will not start a new, empty farm over an old one's files.
//!   So is an empty database beside job directories or bundles.
//! - A job that cannot resume (its checkpoint or bundle is missing) fails alone, with the file
//!   named; the other jobs resume.
//! - Ledger rows that no checkpoint holds are forgotten (their workers upload those deltas
//!   again); open leases of unfinished jobs stay open, so their workers carry on.

use crate::db::{Db, JobRow, JobState, WorkerRow};
use crate::error::{Result, ServerError};
use std::path::{Path, PathBuf};

/// Name of the file holding the farm's id.
const FARM_ID: &str = "farm-id";

/// Creates the directory's layout and empties `tmp/`.
pub fn prepare_layout(dir: &Path) -> Result<()> {
    for sub in ["bundles", "scenes", "jobs", "tmp"] {
        let p = dir.join(sub);
        std::fs::create_dir_all(&p).map_err(ServerError::file(p.display().to_string()))?;
    }
    let tmp = dir.join("tmp");
    for entry in std::fs::read_dir(&tmp)? {
        let path = entry?.path();
        if path.is_dir() {
            std::fs::remove_dir_all(&path)?;
        } else {
            std::fs::remove_file(&path)?;
        }
    }
    Ok(())
}

/// A new farm's id: 16 random bytes in hex.
fn new_farm_id() -> Result<String> {
    let mut b = [0u8; 16];
    getrandom::getrandom(&mut b)
        .map_err(|e| ServerError::Internal(format!("no random numbers: {e}")))?;
    Ok(format!("farm-{}", luxfarm_wire::bundle::hex(&b)))
}

/// True when `dir` holds at least one entry.
fn has_entries(dir: &Path) -> bool {
    std::fs::read_dir(dir).is_ok_and(|mut rd| rd.next().is_some())
}

/// Checks that the database belongs to this data directory (creating the farm's id for a new
/// farm, or for a store written before ids existed).
pub fn check_identity(db: &Db, dir: &Path) -> Result<()> {
    let file = dir.join(FARM_ID);
    let on_disk = match std::fs::read_to_string(&file) {
        Ok(s) => Some(s.trim().to_string()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => return Err(ServerError::file(FARM_ID)(e)),
    };
    let in_db = db.farm_id()?;
    let refuse = |why: String| {
        Err(ServerError::Internal(format!(
            "data directory {}: {why}; restore the database, or start the master with an empty \
             data directory",
            dir.display()
        )))
    };
    match (on_disk, in_db) {
        (Some(a), Some(b)) if a == b => Ok(()),
        (Some(a), Some(b)) => refuse(format!(
            "farm.sqlite belongs to farm {b}, the directory to farm {a} ({FARM_ID})"
        )),
        (Some(a), None) => refuse(format!(
            "farm.sqlite is empty or was replaced: it does not hold the id of farm {a} \
             ({FARM_ID})"
        )),
        (None, found) => {
            let jobs = db.job_count()?;
            if jobs == 0 && (has_entries(&dir.join("jobs")) || has_entries(&dir.join("bundles"))) {
                return refuse(
                    "farm.sqlite holds no jobs, but jobs/ or bundles/ hold a farm's files".into(),
                );
            }
            let id = match found {
                Some(id) => id,
                None => {
                    let id = new_farm_id()?;
                    db.set_farm_id(&id)?;
                    id
                }
            };
            luxfarm::atomic_write::write_bytes_atomic(&file, format!("{id}\n").as_bytes())
                .map_err(|e| ServerError::Internal(format!("{FARM_ID}: {e}")))?;
            Ok(())
        }
    }
}

/// Prepares unfinished jobs for resumption: forgets ledger rows no checkpoint holds, ends the
/// leases of finished jobs, and fails (alone) a job whose checkpoint or bundle is missing.
pub fn check_jobs(db: &Db, dir: &Path, now: i64) -> Result<()> {
    for job in db.jobs()? {
        if job.state.is_final() {
            for lease in db.open_leases_of(&job.id)? {
                db.end_lease(&lease.id, job.state.as_str(), now)?;
            }
            continue;
        }
        if let Some(fault) = missing_file(&job, dir) {
            tracing::error!(job = %job.id, %fault, "job cannot resume");
            for lease in db.open_leases_of(&job.id)? {
                db.end_lease(&lease.id, "job failed", now)?;
            }
            db.set_job_state(&job.id, JobState::Failed, &fault, now)?;
            continue;
        }
        let dropped = db.drop_uncheckpointed(&job.id)?;
        if job.state == JobState::Rendering {
            tracing::info!(job = %job.id, dropped, "resuming job from its checkpoint");
        }
    }
    Ok(())
}

/// The file a job needs that is missing, described.
fn missing_file(job: &JobRow, dir: &Path) -> Option<String> {
    let bundle = format!("bundles/{}.tar", job.bundle_hash);
    if !dir.join(&bundle).is_file() || !dir.join("scenes").join(&job.bundle_hash).is_dir() {
        return Some(format!(
            "{bundle} (or its unpacked scenes/{}) is missing: the job cannot resume",
            job.bundle_hash
        ));
    }
    if job.ckpt_gen > 0 {
        let ckpt = checkpoint_rel(&job.id, job.ckpt_gen);
        if !dir.join(&ckpt).is_file() {
            return Some(format!(
                "{ckpt} is missing: the job cannot resume (its merged samples are gone)"
            ));
        }
    }
    None
}

/// A job's checkpoint file of generation `generation`, relative to the data directory.
pub fn checkpoint_rel(job: &str, generation: i64) -> String {
    format!("jobs/{job}/checkpoint-{generation}.lxd")
}

/// The checkpoint files in a job's directory `dir` of any generation but `keep`: the one
/// before the last commit, and any a master killed between writing or committing a
/// checkpoint and removing its predecessor left behind.
pub fn other_checkpoints(dir: &Path, keep: i64) -> Vec<PathBuf> {
    let keep = format!("checkpoint-{keep}.lxd");
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    entries
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| {
            p.file_name().and_then(|n| n.to_str()).is_some_and(|n| {
                n != keep
                    && n.strip_prefix("checkpoint-")
                        .and_then(|r| r.strip_suffix(".lxd"))
                        .is_some_and(|g| g.parse::<i64>().is_ok())
            })
        })
        .collect()
}

/// A worker to resume, with the lease it holds as (job id, lease id).
pub type ResumedWorker = (WorkerRow, Option<(String, String)>);

/// The workers holding open leases, each with its lease (job, lease), to resume.
pub fn resume_workers(db: &Db) -> Result<Vec<ResumedWorker>> {
    let mut out = Vec::new();
    for lease in db.open_leases()? {
        if let Some(w) = db.worker(&lease.worker_id)? {
            out.push((w, Some((lease.job_id, lease.id))));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn other_checkpoints_are_every_generation_but_the_kept_one() {
        let dir = tempfile::tempdir().unwrap();
        for name in [
            "checkpoint-2.lxd",
            "checkpoint-5.lxd",
            "checkpoint-6.lxd",
            "checkpoint-6.lxd.tmp",
            "checkpoint-x.lxd",
            "history.json",
        ] {
            std::fs::write(dir.path().join(name), b"").unwrap();
        }
        let mut names: Vec<String> = other_checkpoints(dir.path(), 5)
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(names, ["checkpoint-2.lxd", "checkpoint-6.lxd"]);
        assert!(other_checkpoints(&dir.path().join("missing"), 1).is_empty());
    }
}
