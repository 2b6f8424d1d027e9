//! What the delivery task decides from: the signature of a body, the wait before a retry,
//! what an answer's status means, and how a delivery is shown (its hook by origin only).
//! Pure functions; `super` (the delivery task) calls them for every attempt.

use crate::db::HookRow;
use crate::error::{Result, ServerError};
use hmac::{KeyInit, Mac};
use std::time::Duration;

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

#[cfg(test)]
mod tests {
    use super::*;

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
}
