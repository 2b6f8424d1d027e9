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
//!
//! This file is the delivery task and its settings; `policy` holds what it decides from
//! (signatures, the backoff, what a status means) and the API's view of a delivery.

use crate::config::Config;
use crate::db::{Db, HookOutcome, HookRow};
use crate::error::{Result, ServerError};
use std::sync::Arc;
use std::time::Duration;

mod policy;

pub use policy::{backoff, origin, signature, verdict, Verdict, WebhookView};

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

fn now_ms() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| i64::try_from(d.as_millis()).unwrap_or(i64::MAX))
}

/// The HTTP client of deliveries: redirects not followed, the per-attempt timeout.
fn http_client(settings: &Settings) -> Result<reqwest::Client> {
    reqwest::Client::builder()
        .redirect(reqwest::redirect::Policy::none())
        .timeout(settings.timeout)
        .connect_timeout(settings.timeout)
        .user_agent(concat!("luxfarm/", env!("CARGO_PKG_VERSION")))
        .build()
        .map_err(|e| ServerError::Internal(format!("webhook HTTP client: {e}")))
}

/// Starts the delivery task on the current tokio runtime.
pub fn spawn<S: Outbox>(store: Arc<S>, settings: Settings) -> Result<()> {
    let client = http_client(&settings)?;
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
                let recorded = futures_util::future::join_all(attempts).await;
                if recorded.contains(&false) {
                    // The store refused an outcome: those deliveries are still due; pause
                    // rather than post them again at once.
                    tokio::time::sleep(Duration::from_secs(5)).await;
                }
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

/// One attempt at a delivery, and its outcome recorded (false when the store refused it).
async fn deliver<S: Outbox>(
    store: &Arc<S>,
    settings: &Settings,
    client: &reqwest::Client,
    row: HookRow,
) -> bool {
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
    if let Err(e) = &recorded {
        tracing::error!(delivery = %row.id, error = %e, "webhook outcome not recorded");
    }
    recorded.is_ok()
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

    /// The store alone, as the delivery task sees it.
    struct Store(std::sync::Mutex<Db>);

    impl Outbox for Store {
        fn with_db<T>(&self, f: impl FnOnce(&Db) -> Result<T>) -> Result<T> {
            f(&self.0.lock().unwrap())
        }
    }

    /// A loopback HTTP server answering every request with `answer` (status line and
    /// headers); returns its URL.
    async fn answering(answer: &'static str) -> String {
        use tokio::io::{AsyncReadExt, AsyncWriteExt};
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
        let url = format!("http://{}/hook", listener.local_addr().unwrap());
        tokio::spawn(async move {
            while let Ok((mut conn, _)) = listener.accept().await {
                let mut buf = Vec::new();
                let mut chunk = [0u8; 4096];
                // Read the headers and a body of Content-Length bytes.
                while let Ok(n) = conn.read(&mut chunk).await {
                    if n == 0 {
                        break;
                    }
                    buf.extend_from_slice(&chunk[..n]);
                    let text = String::from_utf8_lossy(&buf).to_string();
                    if let Some(end) = text.find("\r\n\r\n") {
                        let len = text
                            .lines()
                            .find_map(|l| {
                                l.to_ascii_lowercase()
                                    .strip_prefix("content-length:")
                                    .and_then(|v| v.trim().parse::<usize>().ok())
                            })
                            .unwrap_or(0);
                        if buf.len() >= end + 4 + len {
                            break;
                        }
                    }
                }
                let reply = format!("{answer}\r\nContent-Length: 0\r\nConnection: close\r\n\r\n");
                let _ = conn.write_all(reply.as_bytes()).await;
            }
        });
        url
    }

    /// A store with one failed job whose `failed` event goes to `url`.
    fn store_with_hook(dir: &std::path::Path, url: &str) -> Arc<Store> {
        let mut db = Db::open(&dir.join("farm.sqlite")).unwrap();
        db.set_hook_targets(Some(url.into()), None);
        db.insert_job(&crate::db::NewJob {
            id: "j",
            name: "j",
            bundle_hash: "h",
            scene_path: "s.lxs",
            width: 2,
            height: 2,
            ..Default::default()
        })
        .unwrap();
        db.set_job_state("j", crate::db::JobState::Failed, "why", 1)
            .unwrap();
        Arc::new(Store(std::sync::Mutex::new(db)))
    }

    fn quick(attempts: u32) -> Settings {
        Settings {
            secret: Some(b"k".to_vec()),
            attempts,
            backoff: Duration::from_millis(10),
            max_wait: Duration::from_secs(60),
            timeout: Duration::from_secs(10),
        }
    }

    /// Makes one attempt at every pending delivery, whenever due; returns the job's rows.
    async fn attempt_all(store: &Arc<Store>, settings: &Settings) -> Vec<HookRow> {
        let client = http_client(settings).unwrap();
        for row in store.with_db(|db| db.due_hooks(i64::MAX, 10)).unwrap() {
            deliver(store, settings, &client, row).await;
        }
        store.with_db(|db| db.hooks_of_job("j")).unwrap()
    }

    #[tokio::test]
    async fn a_client_error_is_given_up_at_once() {
        let dir = tempfile::tempdir().unwrap();
        let store = store_with_hook(dir.path(), &answering("HTTP/1.1 404 Not Found").await);
        let rows = attempt_all(&store, &quick(5)).await;
        assert_eq!((rows[0].attempts, rows[0].last_status), (1, Some(404)));
        assert!(rows[0].gave_up_ms.is_some() && rows[0].delivered_ms.is_none());
        assert_eq!(rows[0].last_error, "HTTP 404");
    }

    #[tokio::test]
    async fn server_errors_are_retried_until_the_attempts_run_out() {
        let dir = tempfile::tempdir().unwrap();
        let url = answering("HTTP/1.1 503 Service Unavailable").await;
        let store = store_with_hook(dir.path(), &url);
        let settings = quick(3);
        let before = now_ms();
        let rows = attempt_all(&store, &settings).await;
        assert_eq!((rows[0].attempts, rows[0].gave_up_ms), (1, None));
        assert!(rows[0].next_ms >= before + 10, "the first backoff");
        attempt_all(&store, &settings).await;
        let rows = attempt_all(&store, &settings).await;
        assert_eq!(rows[0].attempts, 3);
        assert!(rows[0].gave_up_ms.is_some(), "given up after 3 attempts");
        assert!(attempt_all(&store, &settings).await[0].attempts == 3);
    }

    #[tokio::test]
    async fn retry_after_sets_the_next_attempt() {
        let dir = tempfile::tempdir().unwrap();
        let url = answering("HTTP/1.1 429 Too Many Requests\r\nRetry-After: 7").await;
        let store = store_with_hook(dir.path(), &url);
        let before = now_ms();
        let rows = attempt_all(&store, &quick(5)).await;
        assert_eq!(rows[0].last_status, Some(429));
        assert!(rows[0].next_ms >= before + 7000, "{rows:?}");
        assert!(rows[0].next_ms < now_ms() + 60_000, "{rows:?}");
    }

    #[tokio::test]
    async fn a_refused_connection_is_retried_and_named() {
        let dir = tempfile::tempdir().unwrap();
        // A port that was just free: nothing listens there.
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let store = store_with_hook(dir.path(), &format!("http://127.0.0.1:{port}/h"));
        let rows = attempt_all(&store, &quick(5)).await;
        assert_eq!((rows[0].attempts, rows[0].last_status), (1, None));
        assert!(rows[0].last_error.contains("cannot connect"), "{rows:?}");
        assert!(rows[0].gave_up_ms.is_none());
    }
}
