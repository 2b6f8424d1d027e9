//! The webhook outbox: one row per delivery (a job's event to one URL), written in the
//! transaction that records the job's end, read and updated by the delivery task
//! (`crate::webhooks`).
//!
//! ```text
//! set_job_state(final) --queue_hooks (same transaction)--> row: attempts 0, next_ms now
//!   --delivery task: due_hooks--> POST --record_hook_attempt-->
//!       delivered_ms set | next_ms pushed back (retry) | gave_up_ms set
//! ```
//!
//! The payload is fixed when the row is written, so every attempt (and a redelivery after a
//! master restart) sends the same bytes under the same delivery id. One job sends an event
//! to one URL at most once (unique index), whatever restarts happen in between.

use super::{Db, JobRow};
use crate::error::Result;
use rusqlite::{params, OptionalExtension, Row};
use std::sync::Arc;

/// Where a job's events go: the master-wide hook and the base of output URLs (from the
/// configuration), and the wake-up of the delivery task.
#[derive(Clone, Debug, Default)]
pub struct HookTargets {
    /// The master-wide hook URL (`--webhook`).
    pub master: Option<String>,
    /// The master's public address (`--public-url`), the base of output URLs in payloads.
    pub public_url: Option<String>,
    /// Notified when deliveries were queued.
    pub wake: Arc<tokio::sync::Notify>,
}

/// One delivery as stored.
#[derive(Clone, Debug)]
pub struct HookRow {
    /// The delivery id (`X-Luxfarm-Delivery`), kept by every attempt.
    pub id: String,
    pub job_id: String,
    /// done, failed, cancelled or halted.
    pub event: String,
    /// `master` (the `--webhook` hook) or `job` (the job's own).
    pub scope: String,
    pub url: String,
    /// The JSON body sent.
    pub payload: String,
    pub created_ms: i64,
    pub attempts: u32,
    /// When the next attempt is due (pending deliveries).
    pub next_ms: i64,
    /// The HTTP status of the last attempt, if an answer came.
    pub last_status: Option<u16>,
    /// Why the last attempt failed (empty after a success).
    pub last_error: String,
    pub delivered_ms: Option<i64>,
    pub gave_up_ms: Option<i64>,
}

/// What an attempt at a delivery came to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HookOutcome {
    /// A 2xx answer: done.
    Delivered,
    /// A failure worth retrying, at the given time.
    RetryAt(i64),
    /// A failure not worth retrying, or the last attempt failed.
    GiveUp,
}

const HOOK_COLS: &str = "id, job_id, event, scope, url, payload, created_ms, attempts, next_ms, \
    last_status, last_error, delivered_ms, gave_up_ms";

fn hook_from_row(r: &Row<'_>) -> rusqlite::Result<HookRow> {
    Ok(HookRow {
        id: r.get(0)?,
        job_id: r.get(1)?,
        event: r.get(2)?,
        scope: r.get(3)?,
        url: r.get(4)?,
        payload: r.get(5)?,
        created_ms: r.get(6)?,
        attempts: r.get::<_, i64>(7)?.clamp(0, u32::MAX as i64) as u32,
        next_ms: r.get(8)?,
        last_status: r
            .get::<_, Option<i64>>(9)?
            .and_then(|s| u16::try_from(s).ok()),
        last_error: r.get(10)?,
        delivered_ms: r.get(11)?,
        gave_up_ms: r.get(12)?,
    })
}

/// A new delivery id: `d` and 32 hex digits from the system's random source (a clock-derived
/// id when that fails, still unique within this master).
fn delivery_id(job_id: &str, event: &str, url: &str, now_ms: i64) -> String {
    let mut buf = [0u8; 16];
    if getrandom::getrandom(&mut buf).is_err() {
        use sha2::{Digest, Sha256};
        let mut h = Sha256::new();
        for part in [job_id, event, url] {
            h.update(part.as_bytes());
            h.update([0]);
        }
        h.update(now_ms.to_le_bytes());
        buf.copy_from_slice(&h.finalize()[..16]);
    }
    let hex: String = buf.iter().map(|b| format!("{b:02x}")).collect();
    format!("d{hex}")
}

/// The JSON body of a job's event. Output URLs are under `public_url` when given, paths
/// otherwise; a done job names its image and film, a failed or cancelled one its film when a
/// checkpoint holds samples.
pub fn payload(
    row: &JobRow,
    event: &str,
    delivery: &str,
    reason: &str,
    samples: f64,
    public_url: Option<&str>,
    now_ms: i64,
) -> serde_json::Value {
    let pixels = (row.width as f64 * row.height as f64).max(1.0);
    let base = public_url.unwrap_or("").trim_end_matches('/');
    let url = |file: &str| format!("{base}/api/v1/jobs/{}/{file}", row.id);
    let mut outputs = serde_json::Map::new();
    if event == "done" {
        outputs.insert("image_png".into(), url("image.png").into());
        outputs.insert("image_exr".into(), url("image.exr").into());
    }
    if matches!(event, "done" | "failed" | "cancelled") && row.ckpt_gen > 0 {
        outputs.insert("film_flm".into(), url("film.flm").into());
    }
    let elapsed = match (row.first_lease_ms, row.finished_ms) {
        (Some(a), Some(b)) => Some((b - a) as f64 / 1000.0),
        (Some(a), None) => Some((now_ms - a) as f64 / 1000.0),
        _ => None,
    };
    let finite = |v: f64| if v.is_finite() { v } else { 0.0 };
    serde_json::json!({
        "event": event,
        "delivery": delivery,
        "created_ms": now_ms,
        "job": {
            "id": row.id,
            "name": row.name,
            "state": row.state.as_str(),
            "reason": reason,
            "owner": row.owner,
            "samples": finite(samples),
            "spp": finite(samples / pixels),
            "width": row.width,
            "height": row.height,
            "haltspp": row.haltspp,
            "halttime": row.halttime,
            "haltthreshold": row.haltthreshold,
            "submitted_ms": row.submitted_ms,
            "started_ms": row.first_lease_ms,
            "finished_ms": row.finished_ms,
            "elapsed": elapsed,
            "sequence": row.sequence_id,
            "sequence_frame": row.sequence_frame,
            "url": format!("{base}/api/v1/jobs/{}", row.id),
        },
        "outputs": outputs,
    })
}

impl Db {
    /// Sets where jobs' events go (the master's configuration).
    pub fn set_hook_targets(&mut self, master: Option<String>, public_url: Option<String>) {
        self.hooks.master = master.filter(|u| !u.is_empty());
        self.hooks.public_url = public_url.filter(|u| !u.is_empty());
    }

    /// What the delivery task waits on.
    pub fn hook_wake(&self) -> Arc<tokio::sync::Notify> {
        self.hooks.wake.clone()
    }

    /// The (scope, URL) pairs a job's events go to: the master's hook and the job's own (once
    /// when they are the same).
    fn hook_urls(&self, row: &JobRow) -> Vec<(&'static str, String)> {
        let mut urls = Vec::new();
        if let Some(u) = &self.hooks.master {
            urls.push(("master", u.clone()));
        }
        if !row.webhook.is_empty() && self.hooks.master.as_deref() != Some(row.webhook.as_str()) {
            urls.push(("job", row.webhook.clone()));
        }
        urls
    }

    /// Queues a job's event for the master's hook and the job's own (inside the caller's
    /// transaction when it has one). `reason` overrides the stored reason (the halt rule of a
    /// `halted` event). Returns how many deliveries were queued; an event already queued for
    /// a URL is not queued again.
    pub(super) fn queue_hooks(
        &self,
        job_id: &str,
        event: &str,
        reason: Option<&str>,
        now_ms: i64,
    ) -> Result<usize> {
        let Some(row) = self.job(job_id)? else {
            return Ok(0);
        };
        let urls = self.hook_urls(&row);
        if urls.is_empty() {
            return Ok(0);
        }
        let (samples, _) = self.job_totals(job_id)?;
        let reason = reason.unwrap_or(&row.reason);
        let mut queued = 0;
        for (scope, url) in urls {
            let id = delivery_id(job_id, event, &url, now_ms);
            let public = self.hooks.public_url.as_deref();
            let body = payload(&row, event, &id, reason, samples, public, now_ms).to_string();
            queued += self.conn.execute(
                "INSERT OR IGNORE INTO webhooks (id, job_id, event, scope, url, payload, \
                 created_ms, next_ms) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?7)",
                params![id, job_id, event, scope, url, body, now_ms],
            )?;
        }
        Ok(queued)
    }

    /// Queues the `halted` event of a job whose halt rule holds (its reason: the rule).
    pub fn queue_halted(&self, job_id: &str, reason: &str, now_ms: i64) -> Result<()> {
        if self.queue_hooks(job_id, "halted", Some(reason), now_ms)? > 0 {
            self.hooks.wake.notify_one();
        }
        Ok(())
    }

    /// Pending deliveries due by `now_ms`, the longest waiting first.
    pub fn due_hooks(&self, now_ms: i64, limit: usize) -> Result<Vec<HookRow>> {
        let sql = format!(
            "SELECT {HOOK_COLS} FROM webhooks WHERE delivered_ms IS NULL AND gave_up_ms IS NULL \
             AND next_ms <= ?1 ORDER BY next_ms, created_ms LIMIT ?2"
        );
        let mut st = self.conn.prepare(&sql)?;
        let limit = i64::try_from(limit).unwrap_or(i64::MAX);
        let rows = st.query_map(params![now_ms, limit], hook_from_row)?;
        Ok(rows.collect::<rusqlite::Result<_>>()?)
    }

    /// When the next pending delivery is due (None: nothing pending).
    pub fn next_hook_ms(&self) -> Result<Option<i64>> {
        Ok(self
            .conn
            .query_row(
                "SELECT MIN(next_ms) FROM webhooks WHERE delivered_ms IS NULL \
                 AND gave_up_ms IS NULL",
                [],
                |r| r.get::<_, Option<i64>>(0),
            )
            .optional()?
            .flatten())
    }

    /// Records an attempt at a delivery: its answer's status or its error, and what follows.
    pub fn record_hook_attempt(
        &self,
        id: &str,
        status: Option<u16>,
        error: &str,
        outcome: HookOutcome,
        now_ms: i64,
    ) -> Result<()> {
        let (delivered, next, gave_up) = match outcome {
            HookOutcome::Delivered => (Some(now_ms), None, None),
            HookOutcome::RetryAt(t) => (None, Some(t), None),
            HookOutcome::GiveUp => (None, None, Some(now_ms)),
        };
        self.conn.execute(
            "UPDATE webhooks SET attempts = attempts + 1, last_status = ?2, last_error = ?3, \
             delivered_ms = ?4, next_ms = COALESCE(?5, next_ms), gave_up_ms = ?6 WHERE id = ?1",
            params![id, status, error, delivered, next, gave_up],
        )?;
        Ok(())
    }

    /// A job's deliveries, oldest first.
    pub fn hooks_of_job(&self, job_id: &str) -> Result<Vec<HookRow>> {
        let sql =
            format!("SELECT {HOOK_COLS} FROM webhooks WHERE job_id = ?1 ORDER BY created_ms, id");
        let mut st = self.conn.prepare(&sql)?;
        let rows = st.query_map([job_id], hook_from_row)?;
        Ok(rows.collect::<rusqlite::Result<_>>()?)
    }
}

#[cfg(test)]
mod tests {
    use super::super::{JobState, NewJob};
    use super::*;

    fn store(dir: &std::path::Path, master: Option<&str>) -> Db {
        let mut db = Db::open(&dir.join("farm.sqlite")).unwrap();
        db.set_hook_targets(
            master.map(str::to_string),
            Some("https://farm.example/".into()),
        );
        db
    }

    fn job(db: &Db, id: &str, webhook: &str) {
        db.insert_job(&NewJob {
            id,
            name: "shot",
            bundle_hash: "h",
            scene_path: "s.lxs",
            width: 4,
            height: 2,
            webhook,
            ..NewJob::default()
        })
        .unwrap();
    }

    #[test]
    fn a_job_end_queues_one_delivery_per_url_in_its_transaction() {
        let dir = tempfile::tempdir().unwrap();
        let db = store(dir.path(), Some("http://hooks.example/all"));
        job(&db, "j1", "http://hooks.example/mine");
        job(&db, "j2", "");
        db.ledger_insert("l1", 1, "j1", 16.0, 10, 5).unwrap();
        db.set_job_state("j1", JobState::Rendering, "", 1).unwrap();
        assert!(db.hooks_of_job("j1").unwrap().is_empty(), "not final");
        db.set_job_state("j1", JobState::Done, "haltspp 2 reached", 9)
            .unwrap();
        // A second final write (e.g. after a restart) queues nothing more.
        db.set_job_state("j1", JobState::Done, "haltspp 2 reached", 10)
            .unwrap();
        let hooks = db.hooks_of_job("j1").unwrap();
        assert_eq!(hooks.len(), 2);
        let scopes: Vec<_> = hooks.iter().map(|h| h.scope.as_str()).collect();
        assert!(scopes.contains(&"master") && scopes.contains(&"job"));
        let body: serde_json::Value = serde_json::from_str(&hooks[0].payload).unwrap();
        assert_eq!(body["event"], "done");
        assert_eq!(body["delivery"], hooks[0].id.as_str());
        assert_eq!(body["job"]["reason"], "haltspp 2 reached");
        assert_eq!(body["job"]["spp"], 2.0);
        assert_eq!(
            body["outputs"]["image_png"],
            "https://farm.example/api/v1/jobs/j1/image.png"
        );
        assert_eq!(db.due_hooks(9, 10).unwrap().len(), 2);
        assert_eq!(db.next_hook_ms().unwrap(), Some(9));
        // Cancelling a queued job without a hook of its own goes to the master's only.
        db.set_job_state("j2", JobState::Cancelled, "cancelled by user", 11)
            .unwrap();
        let h2 = db.hooks_of_job("j2").unwrap();
        assert_eq!((h2.len(), h2[0].event.as_str()), (1, "cancelled"));
    }

    #[test]
    fn attempts_are_recorded_until_delivered_or_given_up() {
        let dir = tempfile::tempdir().unwrap();
        let db = store(dir.path(), Some("http://hooks.example/all"));
        job(&db, "j", "");
        db.set_job_state("j", JobState::Failed, "no worker can take it", 5)
            .unwrap();
        let id = db.hooks_of_job("j").unwrap()[0].id.clone();
        db.record_hook_attempt(&id, Some(500), "HTTP 500", HookOutcome::RetryAt(50), 6)
            .unwrap();
        assert!(db.due_hooks(49, 10).unwrap().is_empty());
        let due = db.due_hooks(50, 10).unwrap();
        assert_eq!((due[0].attempts, due[0].last_status), (1, Some(500)));
        db.record_hook_attempt(&id, Some(204), "", HookOutcome::Delivered, 51)
            .unwrap();
        assert!(db.due_hooks(i64::MAX, 10).unwrap().is_empty());
        assert_eq!(db.next_hook_ms().unwrap(), None);
        let h = &db.hooks_of_job("j").unwrap()[0];
        assert_eq!((h.attempts, h.delivered_ms), (2, Some(51)));
    }

    #[test]
    fn without_any_hook_nothing_is_queued() {
        let dir = tempfile::tempdir().unwrap();
        let db = store(dir.path(), None);
        job(&db, "j", "");
        db.set_job_state("j", JobState::Done, "", 5).unwrap();
        db.queue_halted("j", "haltspp", 5).unwrap();
        assert!(db.hooks_of_job("j").unwrap().is_empty());
    }
}
