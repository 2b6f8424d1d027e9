//! Webhooks: a job's end (done, failed, cancelled) and its halt rule holding (halted) are
//! posted as JSON to the master's hook (`--webhook`) and to the job's own (its `webhook`
//! submission field), signed, retried, and durable across master restarts.
//!
//! ```text
//! job state written final (db::set_job_state) --same transaction--> outbox row (db::outbox)
//!   --wake--> delivery task (this file, a tokio task: no farm lock held while sending)
//!   --POST body, X-Luxfarm-Event/-Delivery/-Timestamp/-Signature--> receiver
//!   2xx: delivered | 408, 429, 5xx, 3xx, timeout, connect error: retried after a backoff
//!   | other 4xx or the last attempt: given up  --> outcome recorded on the row (API, logs)
//! ```
//!
//! Delivery is at least once: an attempt cut short by a master stop is made again after the
//! restart with the same delivery id and body, so receivers deduplicate on
//! `X-Luxfarm-Delivery`. The signature is `sha256=` and the hex HMAC-SHA256 of the body under
//! the secret of `--webhook-secret-file`; without a secret deliveries are unsigned.

use crate::config::Config;
use crate::db::{Db, HookOutcome, HookRow};
use crate::error::{Result, ServerError};
use hmac::{KeyInit, Mac};
use std::sync::Arc;
use std::time::Duration;

/// Deliveries attempted at once.
const BATCH: usize = 16;
/// Largest secret file read (bytes).
const MAX_SECRET: u64 = 64 * 1024;
/// Longest sleep of the delivery task without a wake-up (it looks at the outbox again).
const IDLE: Duration = Duration::from_secs(60);

/// What the delivery task needs of the master: its store, under the master's lock, taken
/// only for the short queries.
pub trait Outbox: Send + Sync + 'static {
    /// Runs `f` on the store.
    fn with_db<T>(&self, f: impl FnOnce(&Db) -> Result<T>) -> Result<T>;
}

/// How deliveries are made: the signing secret and the retry schedule.
#[derive(Clone, Debug)]
pub struct Settings {
    /// The HMAC key (None: unsigned deliveries).
    pub secret: Option<Vec<u8>>,
    /// Attempts before a delivery is given up.
    pub attempts: u32,
    /// Wait before the first retry; each further retry waits twice as long, up to `max_wait`.
    pub backoff: Duration,
    pub max_wait: Duration,
    /// Time one attempt may take.
    pub timeout: Duration,
}

impl Settings {
    /// The settings of the master's options, reading the secret file (its content, without a
    /// trailing line break; empty or unreadable is an error naming the file).
    pub fn from_config(cfg: &Config) -> Result<Settings> {
        let secret = match &cfg.webhook_secret_file {
            Some(path) => Some(read_secret(path)?),
            None => None,
        };
        Ok(Settings {
            secret,
            attempts: cfg.webhook_attempts.max(1),
            backoff: Duration::from_secs_f64(cfg.webhook_backoff),
            max_wait: Duration::from_secs_f64(cfg.webhook_backoff_max),
            timeout: Duration::from_secs_f64(cfg.webhook_timeout),
        })
    }
}

fn read_secret(path: &std::path::Path) -> Result<Vec<u8>> {
    let name = path.display().to_string();
    let len = std::fs::metadata(path)
        .map_err(ServerError::file(name.clone()))?
        .len();
    if len > MAX_SECRET {
        return Err(ServerError::Internal(format!(
            "{name}: a webhook secret of {len} bytes; at most {MAX_SECRET} are read"
        )));
    }
    let mut secret = std::fs::read(path).map_err(ServerError::file(name.clone()))?;
    while secret.last().is_some_and(|b| *b == b'\n' || *b == b'\r') {
        secret.pop();
    }
    if secret.is_empty() {
        return Err(ServerError::Internal(format!(
            "{name}: the webhook secret file is empty"
        )));
    }
    Ok(secret)
}

/// The `X-Luxfarm-Signature` value of a body: `sha256=` and the hex HMAC-SHA256. (HMAC
/// takes keys of every length, longer ones hashed first; the error is the library's.)
pub fn signature(secret: &[u8], body: &[u8]) -> Result<String> {
    let mut mac = hmac::Hmac::<sha2::Sha256>::new_from_slice(secret)
        .map_err(|e| ServerError::Internal(format!("webhook signature: {e}")))?;
    mac.update(body);
    let tag = mac.finalize().into_bytes();
    let hex: String = tag.iter().map(|b| format!("{b:02x}")).collect();
    Ok(format!("sha256={hex}"))
}

/// The wait after the `made`-th failed attempt (1 for the first): `backoff`, doubled at
/// each further attempt, at most `max_wait`.
pub fn backoff(made: u32, backoff: Duration, max_wait: Duration) -> Duration {
    let doublings = made.saturating_sub(1).min(62);
    let factor = (1u64 << doublings) as f64;
    let wait = backoff.as_secs_f64() * factor;
    if wait.is_finite() && wait < max_wait.as_secs_f64() {
        Duration::from_secs_f64(wait)
    } else {
        max_wait
    }
}

/// What an answer's status means for the delivery.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    Delivered,
    Retry,
    Permanent,
}

/// 2xx delivers; 408 (timeout) and 429 (too many requests) and every status that is not a
/// client error (5xx, and redirects, which are not followed) are retried; other 4xx are not.
pub fn verdict(status: u16) -> Verdict {
    match status {
        200..=299 => Verdict::Delivered,
        408 | 429 => Verdict::Retry,
        400..=499 => Verdict::Permanent,
        _ => Verdict::Retry,
    }
}

/// The origin of a URL (`https://host:port`), what the API and logs show of a hook URL (its
/// path and query may hold a token).
pub fn origin(url: &str) -> String {
    match reqwest::Url::parse(url) {
        Ok(u) => u.origin().ascii_serialization(),
        Err(_) => "(invalid URL)".into(),
    }
}

/// A delivery as the API shows it (`GET /api/v1/jobs/{id}/webhooks`).
#[derive(Clone, Debug, serde::Serialize, utoipa::ToSchema)]
pub struct WebhookView {
    /// The delivery id (`X-Luxfarm-Delivery`).
    pub delivery: String,
    /// done, failed, cancelled or halted.
    pub event: String,
    /// `master` (the `--webhook` hook) or `job` (the job's own).
    pub scope: String,
    /// The hook's origin (scheme, host, port; the rest of the URL is not shown).
    pub target: String,
    /// pending, delivered or failed (given up).
    pub status: String,
    pub attempts: u32,
    /// The HTTP status of the last attempt, when an answer came.
    pub last_status: Option<u16>,
    /// Why the last attempt failed (empty after a success).
    pub last_error: String,
    pub created_ms: i64,
    /// When the next attempt is due (pending deliveries).
    pub next_ms: Option<i64>,
    pub delivered_ms: Option<i64>,
    pub gave_up_ms: Option<i64>,
}

impl WebhookView {
    pub fn new(row: &HookRow) -> WebhookView {
        let status = match (row.delivered_ms, row.gave_up_ms) {
            (Some(_), _) => "delivered",
            (None, Some(_)) => "failed",
            _ => "pending",
        };
        WebhookView {
            delivery: row.id.clone(),
            event: row.event.clone(),
            scope: row.scope.clone(),
            target: origin(&row.url),
            status: status.into(),
            attempts: row.attempts,
            last_status: row.last_status,
            last_error: row.last_error.clone(),
            created_ms: row.created_ms,
            next_ms: (status == "pending").then_some(row.next_ms),
            delivered_ms: row.delivered_ms,
            gave_up_ms: row.gave_up_ms,
        }
    }
}

fn now_ms() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| i64::try_from(d.as_millis()).unwrap_or(i64::MAX))
}

/// Starts the delivery task on the current tokio runtime.
pub fn spawn<S: Outbox>(store: Arc<S>, settings: Settings) -> Result<()> {
    let client = reqwest::Client::builder()
        .redirect(reqwest::redirect::Policy::none())
        .timeout(settings.timeout)
        .connect_timeout(settings.timeout)
        .user_agent(concat!("luxfarm/", env!("CARGO_PKG_VERSION")))
        .build()
        .map_err(|e| ServerError::Internal(format!("webhook HTTP client: {e}")))?;
    let wake = store.with_db(|db| Ok(db.hook_wake()))?;
    tokio::spawn(run(store, Arc::new(settings), client, wake));
    Ok(())
}

/// Runs a query on the store off the async threads.
async fn query<S: Outbox, T: Send + 'static>(
    store: &Arc<S>,
    f: impl FnOnce(&Db) -> Result<T> + Send + 'static,
) -> Result<T> {
    let s = store.clone();
    tokio::task::spawn_blocking(move || s.with_db(f))
        .await
        .map_err(ServerError::internal)?
}

async fn run<S: Outbox>(
    store: Arc<S>,
    settings: Arc<Settings>,
    client: reqwest::Client,
    wake: Arc<tokio::sync::Notify>,
) {
    loop {
        let due = query(&store, |db| db.due_hooks(now_ms(), BATCH)).await;
        match due {
            Ok(due) if !due.is_empty() => {
                let attempts = due
                    .into_iter()
                    .map(|row| deliver(&store, &settings, &client, row));
                futures_util::future::join_all(attempts).await;
                continue;
            }
            Ok(_) => {}
            Err(e) => tracing::error!(error = %e, "webhook outbox unreadable"),
        }
        let wait = match query(&store, |db| db.next_hook_ms()).await {
            Ok(Some(t)) => Duration::from_millis(u64::try_from(t - now_ms()).unwrap_or(0)),
            Ok(None) => IDLE,
            Err(_) => Duration::from_secs(5),
        };
        tokio::select! {
            _ = wake.notified() => {}
            _ = tokio::time::sleep(wait.min(IDLE)) => {}
        }
    }
}

/// One attempt at a delivery, and its outcome recorded.
async fn deliver<S: Outbox>(
    store: &Arc<S>,
    settings: &Settings,
    client: &reqwest::Client,
    row: HookRow,
) {
    let (status, error, retry_after) = attempt(settings, client, &row).await;
    let made = row.attempts.saturating_add(1);
    let outcome = match status.map(verdict) {
        Some(Verdict::Delivered) => HookOutcome::Delivered,
        Some(Verdict::Permanent) => HookOutcome::GiveUp,
        _ if made >= settings.attempts => HookOutcome::GiveUp,
        _ => {
            let wait = retry_after
                .map(|w| w.min(settings.max_wait))
                .unwrap_or_else(|| backoff(made, settings.backoff, settings.max_wait));
            let wait_ms = i64::try_from(wait.as_millis()).unwrap_or(i64::MAX);
            HookOutcome::RetryAt(now_ms().saturating_add(wait_ms))
        }
    };
    let target = origin(&row.url);
    match outcome {
        HookOutcome::Delivered => tracing::info!(
            job = %row.job_id, event = %row.event, delivery = %row.id, %target,
            attempts = made, "webhook delivered"
        ),
        HookOutcome::RetryAt(t) => tracing::warn!(
            job = %row.job_id, event = %row.event, delivery = %row.id, %target,
            attempts = made, %error, retry_in_ms = t - now_ms(), "webhook failed; retrying"
        ),
        HookOutcome::GiveUp => tracing::error!(
            job = %row.job_id, event = %row.event, delivery = %row.id, %target,
            attempts = made, %error, "webhook given up"
        ),
    }
    let id = row.id.clone();
    let recorded = query(store, move |db| {
        db.record_hook_attempt(&id, status, &error, outcome, now_ms())
    })
    .await;
    if let Err(e) = recorded {
        tracing::error!(delivery = %row.id, error = %e, "webhook outcome not recorded");
    }
}

/// Posts the delivery once: the answer's status (if one came), what went wrong (empty on a
/// 2xx) and the answer's Retry-After (seconds), if any.
async fn attempt(
    settings: &Settings,
    client: &reqwest::Client,
    row: &HookRow,
) -> (Option<u16>, String, Option<Duration>) {
    let body = row.payload.clone().into_bytes();
    let mut req = client
        .post(&row.url)
        .header(reqwest::header::CONTENT_TYPE, "application/json")
        .header("X-Luxfarm-Event", &row.event)
        .header("X-Luxfarm-Delivery", &row.id)
        .header("X-Luxfarm-Timestamp", (now_ms() / 1000).to_string());
    if let Some(secret) = &settings.secret {
        match signature(secret, &body) {
            Ok(sig) => req = req.header("X-Luxfarm-Signature", sig),
            Err(e) => return (None, e.to_string(), None),
        }
    }
    match req.body(body).send().await {
        Ok(resp) => {
            let status = resp.status().as_u16();
            let retry_after = resp
                .headers()
                .get(reqwest::header::RETRY_AFTER)
                .and_then(|v| v.to_str().ok())
                .and_then(|v| v.trim().parse::<u64>().ok())
                .map(Duration::from_secs);
            let error = match verdict(status) {
                Verdict::Delivered => String::new(),
                _ => format!("HTTP {status}"),
            };
            (Some(status), error, retry_after)
        }
        Err(e) if e.is_timeout() => (
            None,
            format!("timed out after {} s", settings.timeout.as_secs_f64()),
            None,
        ),
        Err(e) if e.is_connect() => (None, format!("cannot connect: {}", chain(&e)), None),
        Err(e) => (None, chain(&e), None),
    }
}

/// An error with its sources, `: `-separated.
fn chain(e: &dyn std::error::Error) -> String {
    let mut text = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        text.push_str(": ");
        text.push_str(&s.to_string());
        source = s.source();
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    /// True when `header` is the signature of `body` under `secret` (compared in constant time),
    /// as a receiver checks it.
    fn verify(secret: &[u8], body: &[u8], header: &str) -> bool {
        let Some(hex) = header.strip_prefix("sha256=") else {
            return false;
        };
        let Some(tag) = unhex(hex) else {
            return false;
        };
        let Ok(mut mac) = hmac::Hmac::<sha2::Sha256>::new_from_slice(secret) else {
            return false;
        };
        mac.update(body);
        mac.verify_slice(&tag).is_ok()
    }

    fn unhex(s: &str) -> Option<Vec<u8>> {
        if !s.len().is_multiple_of(2) {
            return None;
        }
        (0..s.len())
            .step_by(2)
            .map(|i| u8::from_str_radix(s.get(i..i + 2)?, 16).ok())
            .collect()
    }

    #[test]
    fn signature_is_the_rfc_4231_hmac_sha256() {
        // RFC 4231 test case 2: key "Jefe", data "what do ya want for nothing?".
        let sig = signature(b"Jefe", b"what do ya want for nothing?").unwrap();
        assert_eq!(
            sig,
            "sha256=5bdcc146bf60754e6a042426089575c75a003f089d2739839dec58b964ec3843"
        );
        assert!(verify(b"Jefe", b"what do ya want for nothing?", &sig));
        assert!(!verify(b"jefe", b"what do ya want for nothing?", &sig));
        assert!(!verify(b"Jefe", b"what do ya want for nothing!", &sig));
        assert!(!verify(b"Jefe", b"what do ya want for nothing?", "sha1=00"));
        assert!(!verify(b"Jefe", b"x", "sha256=zz"));
        // A key longer than the block is hashed first (RFC 4231 test case 6).
        let key = [0xaau8; 131];
        let sig = signature(
            &key,
            b"Test Using Larger Than Block-Size Key - Hash Key First",
        )
        .unwrap();
        assert_eq!(
            sig,
            "sha256=60e431591ee0b67f0d8a26aacbf5b77f8e0bc6213728c5140546040f0ee37f54"
        );
    }

    #[test]
    fn backoff_doubles_from_the_first_wait_up_to_the_cap() {
        let s = |x: f64| Duration::from_secs_f64(x);
        let waits: Vec<f64> = (1..=8)
            .map(|n| backoff(n, s(1.0), s(30.0)).as_secs_f64())
            .collect();
        assert_eq!(waits, [1.0, 2.0, 4.0, 8.0, 16.0, 30.0, 30.0, 30.0]);
        assert_eq!(backoff(0, s(0.5), s(30.0)), s(0.5));
        assert_eq!(backoff(u32::MAX, s(1.0), s(600.0)), s(600.0));
    }

    #[test]
    fn client_errors_other_than_408_and_429_are_not_retried() {
        assert_eq!(verdict(200), Verdict::Delivered);
        assert_eq!(verdict(204), Verdict::Delivered);
        assert_eq!(verdict(500), Verdict::Retry);
        assert_eq!(verdict(503), Verdict::Retry);
        assert_eq!(verdict(408), Verdict::Retry);
        assert_eq!(verdict(429), Verdict::Retry);
        assert_eq!(verdict(301), Verdict::Retry);
        assert_eq!(verdict(400), Verdict::Permanent);
        assert_eq!(verdict(404), Verdict::Permanent);
        assert_eq!(verdict(410), Verdict::Permanent);
    }

    #[test]
    fn urls_are_shown_by_their_origin_only() {
        assert_eq!(
            origin("https://hooks.example/T000/B000/secret?x=1"),
            "https://hooks.example"
        );
        assert_eq!(origin("http://127.0.0.1:8080/h"), "http://127.0.0.1:8080");
    }

    #[test]
    fn a_secret_file_loses_its_line_break_and_may_not_be_empty() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("secret");
        std::fs::write(&p, "s3cret\n").unwrap();
        assert_eq!(read_secret(&p).unwrap(), b"s3cret");
        std::fs::write(&p, "\r\n").unwrap();
        assert!(read_secret(&p).unwrap_err().to_string().contains("empty"));
        let missing = read_secret(&dir.path().join("nope")).unwrap_err();
        assert!(missing.to_string().contains("nope"), "{missing}");
    }
}
