//! Webhooks against a real master and a real HTTP receiver on loopback (a small HTTP/1.1
//! server in this file): a job rendered to its halt is posted `halted` then `done`, each
//! accepted once after a first attempt answered 500 (same delivery id both times), signed with
//! HMAC-SHA256 (checked here with an RFC 2104 HMAC written from sha2, which verifies with the
//! secret and not with another); a job failing because its only worker is blocked is posted
//! `failed` with its reason; a per-job URL that is not http(s) is a JSON 400 (and refused by
//! `luxfarm submit --webhook`, whose good URL gets the job's `cancelled`); a cancel whose
//! delivery was not acknowledged before the master was killed is delivered after its restart.

mod farm_common;

use farm_common::*;
use luxfarm_proto as pb;
use luxfarm_proto::connect;
use sha2::{Digest, Sha256};
use std::collections::HashMap;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// One request the receiver got, and the status it answered.
#[derive(Clone, Debug)]
struct Received {
    path: String,
    headers: HashMap<String, String>,
    body: Vec<u8>,
    answered: u16,
}

impl Received {
    fn header(&self, name: &str) -> &str {
        self.headers.get(name).map_or("", String::as_str)
    }
    fn json(&self) -> serde_json::Value {
        serde_json::from_slice(&self.body).expect("a JSON body")
    }
}

/// A receiver: answers 500 to the first attempt of every delivery id, then 200; while
/// `down` is set it answers 503 to everything.
struct Receiver {
    port: u16,
    got: Arc<Mutex<Vec<Received>>>,
    down: Arc<AtomicBool>,
}

impl Receiver {
    fn start() -> Receiver {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let port = listener.local_addr().unwrap().port();
        let got = Arc::new(Mutex::new(Vec::<Received>::new()));
        let down = Arc::new(AtomicBool::new(false));
        let (g, d) = (got.clone(), down.clone());
        std::thread::spawn(move || {
            for conn in listener.incoming().map_while(Result::ok) {
                let (g, d) = (g.clone(), d.clone());
                std::thread::spawn(move || serve(conn, &g, &d));
            }
        });
        Receiver { port, got, down }
    }

    fn url(&self, path: &str) -> String {
        format!("http://127.0.0.1:{}{path}", self.port)
    }

    /// Waits (bounded) until `pred` holds for the requests received; returns them.
    fn wait(&self, secs: u64, pred: impl Fn(&[Received]) -> bool) -> Vec<Received> {
        let end = Instant::now() + Duration::from_secs(secs);
        loop {
            let got = self.got.lock().unwrap().clone();
            if pred(&got) || Instant::now() > end {
                return got;
            }
            std::thread::sleep(Duration::from_millis(100));
        }
    }
}

/// Reads one request (headers, then Content-Length bytes), records it and answers.
fn serve(conn: TcpStream, got: &Mutex<Vec<Received>>, down: &AtomicBool) {
    let _ = conn.set_read_timeout(Some(Duration::from_secs(30)));
    let mut out = conn.try_clone().unwrap();
    let mut r = BufReader::new(conn);
    let mut line = String::new();
    if r.read_line(&mut line).unwrap_or(0) == 0 {
        return;
    }
    let path = line.split_whitespace().nth(1).unwrap_or("").to_string();
    let mut headers = HashMap::new();
    loop {
        let mut h = String::new();
        if r.read_line(&mut h).unwrap_or(0) == 0 || h.trim().is_empty() {
            break;
        }
        if let Some((k, v)) = h.split_once(':') {
            headers.insert(k.trim().to_ascii_lowercase(), v.trim().to_string());
        }
    }
    let len: usize = headers
        .get("content-length")
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    let mut body = vec![0; len];
    if r.read_exact(&mut body).is_err() {
        return;
    }
    let answered = {
        let mut got = got.lock().unwrap();
        let delivery = headers.get("x-luxfarm-delivery").cloned();
        let seen = got
            .iter()
            .any(|g| g.headers.get("x-luxfarm-delivery") == delivery.as_ref());
        let answered = if down.load(Ordering::SeqCst) {
            503
        } else if seen {
            200
        } else {
            500
        };
        got.push(Received {
            path,
            headers,
            body,
            answered,
        });
        answered
    };
    let reason = match answered {
        200 => "OK",
        500 => "Internal Server Error",
        _ => "Service Unavailable",
    };
    let _ = write!(
        out,
        "HTTP/1.1 {answered} {reason}\r\nContent-Length: 0\r\nConnection: close\r\n\r\n"
    );
}

/// HMAC-SHA256 from its definition (RFC 2104): H((K ^ opad) || H((K ^ ipad) || m)), the key
/// hashed first when longer than the 64-byte block.
fn hmac_sha256(key: &[u8], msg: &[u8]) -> String {
    let mut k = [0u8; 64];
    if key.len() > 64 {
        k[..32].copy_from_slice(&Sha256::digest(key));
    } else {
        k[..key.len()].copy_from_slice(key);
    }
    let mut inner = Sha256::new();
    inner.update(k.map(|b| b ^ 0x36));
    inner.update(msg);
    let mut outer = Sha256::new();
    outer.update(k.map(|b| b ^ 0x5c));
    outer.update(inner.finalize());
    outer
        .finalize()
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

fn signed_with(r: &Received, secret: &[u8]) -> bool {
    r.header("x-luxfarm-signature") == format!("sha256={}", hmac_sha256(secret, &r.body))
}

fn hook_args<'a>(url: &'a str, secret: &'a str) -> Vec<&'a str> {
    vec![
        "--webhook",
        url,
        "--webhook-secret-file",
        secret,
        "--webhook-backoff",
        "0.2",
        "--webhook-backoff-max",
        "1",
        "--webhook-attempts",
        "50",
    ]
}

/// The requests of one event at one path.
fn of<'a>(got: &'a [Received], path: &str, event: &str) -> Vec<&'a Received> {
    got.iter()
        .filter(|r| r.path == path && r.header("x-luxfarm-event") == event)
        .collect()
}

/// Every delivery of a job, once each has been delivered (bounded wait).
fn delivered(s: &Server, job: &str, n: usize) -> serde_json::Value {
    wait_view(s, &format!("/jobs/{job}/webhooks"), 120, |v| {
        v.as_array()
            .is_some_and(|a| a.len() == n && a.iter().all(|d| d["status"] == "delivered"))
    })
}

#[test]
fn job_ends_are_posted_signed_and_retried_once_each() {
    let dir = tempfile::tempdir().unwrap();
    let rx = Receiver::start();
    let secret = dir.path().join("secret");
    std::fs::write(&secret, "test-secret\n").unwrap();
    let master_hook = rx.url("/hooks/all");
    let mut args = hook_args(&master_hook, secret.to_str().unwrap());
    args.extend(["--upload-interval", "0.5", "--block-after", "1"]);
    let s = server(&dir.path().join("data"), &args);

    // A per-job URL that is not http(s), or too long, is refused with a JSON 400.
    let scene = small_scene(dir.path(), "hook", (16, 12), "");
    let bytes = std::fs::read(&scene).unwrap();
    let (st, e) = post_job(
        &s,
        bytes.clone(),
        "?filename=h.lxs&webhook=file:///etc/passwd",
    );
    assert_eq!(st, 400, "{e}");
    assert_eq!(e["error"], "bad_request", "{e}");
    assert!(e["detail"].as_str().unwrap().contains("webhook"), "{e}");
    let long = format!("http://x/{}", "a".repeat(2100));
    let (st, e) = post_job(
        &s,
        bytes.clone(),
        &format!("?filename=h.lxs&webhook={long}"),
    );
    assert_eq!(st, 400, "{e}");

    // A job with its own hook besides the master's renders to its halt.
    let job_hook = rx.url("/hooks/mine");
    let (st, job) = post_job(
        &s,
        bytes.clone(),
        &format!("?filename=h.lxs&haltspp=4&name=hooked&webhook={job_hook}"),
    );
    assert_eq!(st, 201, "{job}");
    let id = job["id"].as_str().unwrap().to_string();
    let w = worker(&s.url(), 1, &[]);
    let done = wait_job(&s, &id, 300, |v| v["state"] == "done");
    assert_eq!(done["state"], "done", "{done}");
    drop(w);

    let views = delivered(&s, &id, 4);
    let views = views.as_array().unwrap();
    assert_eq!(views.len(), 4, "{views:?}");
    for v in views {
        assert_eq!(v["status"], "delivered", "{v}");
        assert_eq!(v["attempts"], 2, "{v}");
        assert_eq!(v["last_status"], 200, "{v}");
        // The API shows the hook's origin, not its path.
        assert_eq!(v["target"], format!("http://127.0.0.1:{}", rx.port), "{v}");
    }
    let got = rx.got.lock().unwrap().clone();
    for path in ["/hooks/all", "/hooks/mine"] {
        for event in ["halted", "done"] {
            let tries = of(&got, path, event);
            assert_eq!(tries.len(), 2, "{path} {event}: {tries:?}");
            assert_eq!(
                tries.iter().map(|r| r.answered).collect::<Vec<_>>(),
                [500, 200]
            );
            let ids: Vec<&str> = tries
                .iter()
                .map(|r| r.header("x-luxfarm-delivery"))
                .collect();
            assert!(!ids[0].is_empty() && ids[0] == ids[1], "{ids:?}");
            assert_eq!(tries[0].body, tries[1].body, "a retry sends the same body");
            for r in &tries {
                assert!(signed_with(r, b"test-secret"), "{r:?}");
                assert!(!signed_with(r, b"another-secret"), "{r:?}");
                assert_eq!(r.header("content-type"), "application/json");
                assert!(r.header("x-luxfarm-timestamp").parse::<u64>().is_ok());
            }
        }
    }
    let done_hook = of(&got, "/hooks/all", "done")[1].json();
    assert_eq!(done_hook["event"], "done");
    assert_eq!(done_hook["job"]["id"], id.as_str());
    assert_eq!(done_hook["job"]["name"], "hooked");
    assert_eq!(done_hook["job"]["state"], "done");
    assert!(
        done_hook["job"]["spp"].as_f64().unwrap() >= 4.0,
        "{done_hook}"
    );
    assert_eq!(done_hook["job"]["samples"], done["samples"]);
    assert!(done_hook["job"]["finished_ms"].as_i64().is_some());
    let png = done_hook["outputs"]["image_png"].as_str().unwrap();
    let r = http().get(format!("{}{png}", s.url())).send().unwrap();
    assert_eq!(r.status().as_u16(), 200);
    assert!(r.bytes().unwrap().starts_with(b"\x89PNG"));
    let halted = of(&got, "/hooks/all", "halted")[1].json();
    assert!(
        halted["job"]["reason"]
            .as_str()
            .unwrap()
            .contains("haltspp"),
        "{halted}"
    );

    // A job only a failing worker can take fails once it is blocked; `failed` says why.
    let (st, job) = post_job(&s, bytes, "?filename=h.lxs&haltspp=4&tags=flaky");
    assert_eq!(st, 201, "{job}");
    let failing = job["id"].as_str().unwrap().to_string();
    let rt = tokio::runtime::Runtime::new().unwrap();
    rt.block_on(fail_one_lease(&s.url(), &failing));
    let v = wait_job(&s, &failing, 120, |v| v["state"] == "failed");
    assert_eq!(v["state"], "failed", "{v}");
    delivered(&s, &failing, 1);
    let got = rx.got.lock().unwrap().clone();
    let failed = of(&got, "/hooks/all", "failed");
    assert_eq!(failed.len(), 2, "{failed:?}");
    let body = failed[1].json();
    assert_eq!(body["job"]["id"], failing.as_str());
    assert_eq!(body["job"]["state"], "failed");
    let reason = body["job"]["reason"].as_str().unwrap();
    assert!(
        reason.contains("blocked") && reason.contains("scene too big"),
        "{reason}"
    );
    assert_eq!(reason, v["reason"].as_str().unwrap());

    // `luxfarm submit --webhook` (gRPC) names the job's own hook; a bad URL is refused.
    let cli = |hook: &str| {
        std::process::Command::new(exe())
            .arg("submit")
            .arg(&scene)
            .args(["--master", &s.url(), "--tag", "nobody", "--webhook", hook])
            .env_remove("LUXFARM_TOKEN")
            .output()
            .unwrap()
    };
    let refused = cli("ftp://127.0.0.1/x");
    assert!(!refused.status.success());
    let err = String::from_utf8_lossy(&refused.stderr);
    assert!(
        err.contains("webhook") && err.contains("only http and https"),
        "{err}"
    );
    let out = cli(&rx.url("/hooks/cli"));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let queued = String::from_utf8_lossy(&out.stdout).trim().to_string();
    let r = http()
        .delete(s.api(&format!("/jobs/{queued}")))
        .send()
        .unwrap();
    assert_eq!(r.status().as_u16(), 200);
    delivered(&s, &queued, 2);
    let got = rx.got.lock().unwrap().clone();
    let cancelled = of(&got, "/hooks/cli", "cancelled");
    assert_eq!(cancelled.len(), 2, "{cancelled:?}");
    assert_eq!(cancelled[1].json()["job"]["id"], queued.as_str());
    assert_eq!(of(&got, "/hooks/all", "cancelled").len(), 2);
}

/// Registers a protocol client as a worker tagged `flaky`, takes a lease of `job` and
/// reports it failed.
async fn fail_one_lease(url: &str, job: &str) {
    let reg = connect::worker_client(connect::channel(url, None, None).unwrap())
        .register(pb::RegisterRequest {
            name: "flaky".into(),
            threads: 1,
            protocol: pb::PROTOCOL_VERSION,
            build: pb::BUILD.into(),
            tags: vec!["flaky".into()],
            ..Default::default()
        })
        .await
        .unwrap()
        .into_inner();
    let mut c =
        connect::worker_client(connect::channel(url, Some(&reg.worker_token), None).unwrap());
    let next = c
        .next_assignment(pb::NextRequest {
            worker_id: reg.worker_id.clone(),
        })
        .await
        .unwrap()
        .into_inner();
    let a = next.assignment.expect("a lease of the tagged job");
    assert_eq!(a.job_id, job);
    c.report_failure(pb::FailureReport {
        worker_id: reg.worker_id,
        lease_id: a.lease_id,
        reason: "scene too big for this worker".into(),
    })
    .await
    .unwrap();
}

#[test]
fn an_unacknowledged_delivery_is_sent_after_a_master_restart() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let rx = Receiver::start();
    rx.down.store(true, Ordering::SeqCst);
    let secret = dir.path().join("secret");
    std::fs::write(&secret, "s").unwrap();
    let hook = rx.url("/hooks");
    let args = hook_args(&hook, secret.to_str().unwrap());
    let s = server(&data, &args);
    let scene = small_scene(dir.path(), "queued", (8, 6), "");
    let (st, job) = post_job(&s, std::fs::read(&scene).unwrap(), "?filename=q.lxs");
    assert_eq!(st, 201, "{job}");
    let id = job["id"].as_str().unwrap().to_string();
    let r = http().delete(s.api(&format!("/jobs/{id}"))).send().unwrap();
    assert_eq!(r.status().as_u16(), 200);
    // The receiver is down: the delivery is attempted, refused, and stays pending.
    let got = rx.wait(60, |g| g.len() >= 2);
    assert!(
        got.len() >= 2 && got.iter().all(|r| r.answered == 503),
        "{got:?}"
    );
    let pending = get_json(&s.api(&format!("/jobs/{id}/webhooks")));
    assert_eq!(pending[0]["status"], "pending", "{pending}");
    assert_eq!(pending[0]["last_status"], 503, "{pending}");
    let delivery = got[0].header("x-luxfarm-delivery").to_string();
    drop(s); // SIGKILL: nothing is flushed at exit.

    rx.down.store(false, Ordering::SeqCst);
    let before = rx.got.lock().unwrap().len();
    let s = server(&data, &args);
    let v = delivered(&s, &id, 1);
    assert_eq!(v[0]["status"], "delivered", "{v}");
    let got = rx.got.lock().unwrap().clone();
    let after: Vec<&Received> = got[before..].iter().collect();
    let accepted: Vec<&&Received> = after.iter().filter(|r| r.answered == 200).collect();
    assert_eq!(accepted.len(), 1, "{after:?}");
    assert_eq!(accepted[0].header("x-luxfarm-delivery"), delivery);
    assert_eq!(accepted[0].header("x-luxfarm-event"), "cancelled");
    assert!(signed_with(accepted[0], b"s"));
    let body = accepted[0].json();
    assert_eq!(body["job"]["reason"], "cancelled by user");
    // The restart queued nothing new for the job.
    let views = get_json(&s.api(&format!("/jobs/{id}/webhooks")));
    assert_eq!(views.as_array().map(Vec::len), Some(1), "{views}");
}
