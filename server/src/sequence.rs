//! Frame sequences: an animation submitted as one sequence whose frames are ordinary
//! progressive jobs (each with its own halt rule), named and numbered after the sequence.
//!
//! ```text
//! CreateSequence / POST /api/v1/sequences (name, policy) --create--> SequenceRow
//! submit(sequence, sequence_frame) --frame_name--> job NAME_0001 in the sequence
//! GET /api/v1/sequences/{id} --view--> per-frame state, spp, output NAME_0001.png
//! ```
//!
//! The policy (`schedule::Policy`) decides how workers are given frames; each frame's output
//! is named `NAME_0001.png` (four digits at least, as LuxRender exporters number files).

use crate::admission;
use crate::db::{JobState, SequenceRow};
use crate::error::{Result, ServerError};
use crate::farm::{lock, new_id, now_ms, Farm};
use crate::schedule::Policy;
use crate::views;

/// Most frames one sequence may hold.
pub const MAX_FRAMES: usize = 100_000;

/// A job (or output) name for one frame: `base_0012` (at least four digits).
pub fn frame_name(base: &str, frame: i64) -> String {
    format!("{base}_{frame:04}")
}

/// A sequence as the API shows it.
#[derive(Clone, Debug, serde::Serialize, utoipa::ToSchema)]
pub struct SequenceView {
    pub id: String,
    pub name: String,
    /// `spread` or `earliest`.
    pub policy: String,
    pub owner: String,
    pub created_ms: i64,
    /// queued (no frame started), rendering, done (every frame done), failed (a frame failed
    /// or was cancelled and the others are over).
    pub state: String,
    pub frames_done: usize,
    pub frames: Vec<FrameView>,
}

/// One frame of a sequence.
#[derive(Clone, Debug, serde::Serialize, utoipa::ToSchema)]
pub struct FrameView {
    pub number: i64,
    pub job_id: String,
    pub state: JobState,
    pub halting: bool,
    pub spp: f64,
    pub haltspp: Option<f64>,
    pub active_leases: u32,
    pub reason: String,
    /// The output's file name (`NAME_0001.png`).
    pub output: String,
}

/// The state of a whole sequence from its frames' states.
fn sequence_state(frames: &[FrameView]) -> &'static str {
    let all = |f: fn(JobState) -> bool| frames.iter().all(|x| f(x.state));
    if frames.is_empty() || all(|s| s == JobState::Queued) {
        "queued"
    } else if all(|s| s == JobState::Done) {
        "done"
    } else if all(JobState::is_final) {
        "failed"
    } else {
        "rendering"
    }
}

impl Farm {
    /// Creates an empty sequence owned by `owner`.
    pub fn create_sequence(&self, name: &str, policy: &str, owner: &str) -> Result<SequenceRow> {
        let policy = match policy.trim() {
            "" => Policy::default(),
            p => Policy::parse(p).ok_or_else(|| {
                ServerError::BadRequest(format!(
                    "policy {:?}: spread or earliest",
                    p.chars().take(40).collect::<String>()
                ))
            })?,
        };
        let name = admission::clean_name(name);
        let name = if name.is_empty() {
            "sequence".to_string()
        } else {
            name
        };
        let id = new_id("q");
        let db = lock(&self.db);
        db.insert_sequence(&id, &name, policy.as_str(), owner, now_ms())?;
        tracing::info!(sequence = %id, %name, policy = policy.as_str(), "sequence created");
        let row = db
            .sequence(&id)?
            .ok_or_else(|| ServerError::Internal("the new sequence was not stored".into()))?;
        drop(db);
        self.touch();
        Ok(row)
    }

    /// The sequence a frame joins, checked: it exists, it is the submitter's (an open farm
    /// has no owners), it has room and no frame of this number yet. Returns the frame's job
    /// name.
    pub fn check_frame(&self, sequence: &str, frame: Option<i64>, owner: &str) -> Result<String> {
        let frame = frame.ok_or_else(|| {
            ServerError::BadRequest(format!(
                "a frame of sequence {sequence} needs its frame number (sequence_frame)"
            ))
        })?;
        let db = lock(&self.db);
        let seq = db
            .sequence(sequence)?
            .ok_or_else(|| ServerError::NotFound(format!("no sequence {sequence:?}")))?;
        if seq.owner != owner {
            return Err(ServerError::Forbidden(format!(
                "sequence {sequence} is another user's"
            )));
        }
        if db.sequence_has_frame(sequence, frame)? {
            return Err(ServerError::Conflict(format!(
                "sequence {sequence} already has frame {frame}"
            )));
        }
        if db.sequence_jobs(sequence)?.len() >= MAX_FRAMES {
            return Err(ServerError::BadRequest(format!(
                "sequence {sequence} has {MAX_FRAMES} frames: no more"
            )));
        }
        Ok(frame_name(&seq.name, frame))
    }

    /// The view of one sequence.
    pub fn sequence_view(&self, id: &str) -> Result<SequenceView> {
        let (seq, rows) = {
            let db = lock(&self.db);
            let seq = db
                .sequence(id)?
                .ok_or_else(|| ServerError::NotFound(format!("no sequence {id:?}")))?;
            (seq, db.sequence_jobs(id)?)
        };
        let mut frames = Vec::with_capacity(rows.len());
        for row in &rows {
            let v = views::job_view(self, row)?;
            frames.push(FrameView {
                number: row.sequence_frame.unwrap_or(0),
                job_id: row.id.clone(),
                state: row.state,
                halting: v.halting,
                spp: v.spp,
                haltspp: row.haltspp,
                active_leases: v.active_leases,
                reason: row.reason.clone(),
                output: row.output_name("png"),
            });
        }
        Ok(SequenceView {
            state: sequence_state(&frames).into(),
            frames_done: frames.iter().filter(|f| f.state == JobState::Done).count(),
            id: seq.id,
            name: seq.name,
            policy: seq.policy,
            owner: seq.owner,
            created_ms: seq.created_ms,
            frames,
        })
    }

    /// Views of every sequence, oldest first.
    pub fn sequence_views(&self) -> Result<Vec<SequenceView>> {
        let ids: Vec<String> = lock(&self.db)
            .sequences()?
            .into_iter()
            .map(|s| s.id)
            .collect();
        ids.iter().map(|id| self.sequence_view(id)).collect()
    }

    /// Each sequence's policy (for the scheduler).
    pub fn sequence_policies(&self) -> Result<std::collections::HashMap<String, Policy>> {
        let rows = lock(&self.db).sequences()?;
        Ok(rows
            .into_iter()
            .map(|s| (s.id, Policy::parse(&s.policy).unwrap_or_default()))
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_numbered_with_four_digits_at_least() {
        assert_eq!(frame_name("shot", 1), "shot_0001");
        assert_eq!(frame_name("shot", 12345), "shot_12345");
        assert_eq!(frame_name("shot", -3), "shot_-003");
    }
}
