//! The hardening points of the farm that need a real master on loopback: user tokens made
//! with `luxfarm token` and what each role may do; JSON bodies on 405, 414 and a tar entry
//! name too long for the bundle; idle connections that cannot starve the master; gRPC calls
//! to unknown methods or with undecodable messages; a data directory whose database was
//! emptied or whose checkpoint was deleted while the master was stopped; a worker's failure
//! reason that would name the worker's own files.

mod farm_common;

use farm_common::*;
use std::io::{Read, Write};
use std::net::TcpStream;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Runs `luxfarm token ...` against the master; returns (success, stdout, stderr).
fn token_cmd(s: &Server, admin: &str, args: &[&str]) -> (bool, String, String) {
    let out = Command::new(exe())
        .arg("token")
        .args(["--master", &s.url(), "--token", admin])
        .args(args)
        .env_remove("LUXFARM_TOKEN")
        .env_remove("LUXFARM_MASTER")
        .output()
        .expect("run luxfarm token");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A request with a bearer token; returns (status, JSON body or Null).
fn call(
    method: reqwest::Method,
    url: &str,
    token: &str,
    body: Option<Vec<u8>>,
) -> (u16, serde_json::Value) {
    let mut r = http().request(method, url).bearer_auth(token);
    if let Some(b) = body {
        r = r.body(b);
    }
    let resp = r.send().expect("request");
    let st = resp.status().as_u16();
    (st, resp.json().unwrap_or(serde_json::Value::Null))
}

fn assert_json_error(st: u16, body: &serde_json::Value, want: u16) {
    assert_eq!(st, want, "{body}");
    assert!(body["error"].is_string(), "no JSON error body: {body}");
    assert!(body["detail"].is_string(), "no JSON detail: {body}");
}

#[test]
fn token_command_makes_role_bound_tokens_that_revoke() {
    let dir = tempfile::tempdir().unwrap();
    let admin = "admin-secret-for-the-test";
    let s = server(&dir.path().join("data"), &["--token", admin]);
    let (ok, viewer, err) = token_cmd(&s, admin, &["add", "alice", "--role", "viewer"]);
    assert!(ok, "{err}");
    let viewer = viewer.trim().to_string();
    let (ok, bob, err) = token_cmd(&s, admin, &["add", "bob", "--role", "submitter"]);
    assert!(ok, "{err}");
    let bob = bob.trim().to_string();
    let (ok, carol, _) = token_cmd(&s, admin, &["add", "carol", "--role", "submitter"]);
    assert!(ok);
    let carol = carol.trim().to_string();
    assert!(viewer.len() >= 16 && bob != viewer && carol != bob);
    // A bad role is refused by the master, and the command fails.
    let (ok, _, err) = token_cmd(&s, admin, &["add", "eve", "--role", "superuser"]);
    assert!(!ok, "a bad role was accepted");
    assert!(err.contains("role"), "{err}");

    let scene = std::fs::read(small_scene(dir.path(), "t", (8, 8), "")).unwrap();
    let jobs = s.api("/jobs?filename=t.lxs&haltspp=1");
    // A viewer reads but cannot submit.
    let (st, body) = call(reqwest::Method::POST, &jobs, &viewer, Some(scene.clone()));
    assert_json_error(st, &body, 403);
    // A submitter submits; the job is theirs.
    let (st, job) = call(reqwest::Method::POST, &jobs, &bob, Some(scene.clone()));
    assert_eq!(st, 201, "{job}");
    let id = job["id"].as_str().unwrap().to_string();
    let job_url = s.api(&format!("/jobs/{id}"));
    let (st, seen) = call(reqwest::Method::GET, &job_url, &viewer, None);
    assert_eq!(st, 200, "{seen}");
    // Neither a viewer nor another submitter may cancel it; its owner may.
    let (st, body) = call(reqwest::Method::DELETE, &job_url, &viewer, None);
    assert_json_error(st, &body, 403);
    let (st, body) = call(reqwest::Method::DELETE, &job_url, &carol, None);
    assert_json_error(st, &body, 403);
    let (st, body) = call(reqwest::Method::DELETE, &job_url, &bob, None);
    assert_eq!(st, 200, "{body}");
    // No token, or a wrong one: 401.
    let (st, body) = call(reqwest::Method::GET, &s.api("/jobs"), "not-a-token", None);
    assert_json_error(st, &body, 401);

    // The list names the tokens and never shows them.
    let (ok, list, err) = token_cmd(&s, admin, &["list"]);
    assert!(ok, "{err}");
    for name in ["alice", "bob", "carol"] {
        assert!(list.contains(name), "{list}");
    }
    for secret in [&viewer, &bob, &carol] {
        assert!(!list.contains(secret.as_str()), "a token is listed: {list}");
    }
    // Only an admin manages tokens.
    let (ok, _, _) = token_cmd(&s, &bob, &["list"]);
    assert!(!ok, "a submitter listed the tokens");
    // Revoking alice's token shuts her out.
    let alice_id = list
        .lines()
        .find(|l| l.contains("alice"))
        .and_then(|l| l.split_whitespace().next())
        .expect("alice's id")
        .to_string();
    let (ok, revoked, err) = token_cmd(&s, admin, &["revoke", &alice_id]);
    assert!(ok, "{err}");
    assert!(revoked.contains("revoked"), "{revoked}");
    let (st, body) = call(reqwest::Method::GET, &s.api("/jobs"), &viewer, None);
    assert_json_error(st, &body, 401);
    let (st, _) = call(reqwest::Method::GET, &s.api("/jobs"), &bob, None);
    assert_eq!(st, 200);
}

/// A tar holding one file under `name`, written with the GNU long-name extension.
fn tar_with(name: &str, data: &[u8]) -> Vec<u8> {
    let mut b = tar::Builder::new(Vec::new());
    let mut h = tar::Header::new_gnu();
    h.set_size(data.len() as u64);
    h.set_mode(0o644);
    b.append_data(&mut h, name, data).unwrap();
    b.into_inner().unwrap()
}

#[test]
fn every_rest_error_has_a_json_body() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &[]);
    // 405: a method the route does not have.
    let r = http().put(s.api("/jobs")).send().unwrap();
    let st = r.status().as_u16();
    assert_json_error(st, &r.json().unwrap_or_default(), 405);
    // 414: a URI longer than the master reads.
    let long = format!("{}?x={}", s.api("/jobs"), "a".repeat(20_000));
    let r = http().get(long).send().unwrap();
    let st = r.status().as_u16();
    assert_json_error(st, &r.json().unwrap_or_default(), 414);
    // A bundle entry whose name is 300 characters long: a 4xx naming the problem, not a 500.
    let scene = std::fs::read(small_scene(dir.path(), "n", (8, 8), "")).unwrap();
    let long_name = format!("{}/scene.lxs", "d".repeat(290));
    let (st, body) = post_job(&s, tar_with(&long_name, &scene), "?filename=b.tar");
    assert!((400..500).contains(&st), "{st}: {body}");
    assert!(
        body["error"].is_string() && body["detail"].is_string(),
        "{body}"
    );
    // Unknown routes are JSON 404s.
    let (st, body) = call(reqwest::Method::GET, &s.api("/nope"), "", None);
    assert_json_error(st, &body, 404);
}

#[test]
fn idle_connections_are_closed_and_cannot_starve_the_master() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(
        &dir.path().join("data"),
        &[
            "--max-connections",
            "4",
            "--header-timeout",
            "1",
            "--idle-timeout",
            "2",
        ],
    );
    // Twice the connection limit, each sending half a request line and then nothing.
    let mut idle: Vec<TcpStream> = (0..8)
        .map(|_| {
            let mut c = TcpStream::connect(&s.addr).unwrap();
            c.write_all(b"GET /healthz HT").unwrap();
            c
        })
        .collect();
    // The master still answers: the silent connections are dropped after the header timeout.
    let end = Instant::now() + Duration::from_secs(60);
    let healthy = loop {
        let ok = reqwest::blocking::Client::builder()
            .timeout(Duration::from_secs(5))
            .build()
            .unwrap()
            .get(format!("{}/healthz", s.url()))
            .send()
            .is_ok_and(|r| r.status().is_success());
        if ok || Instant::now() > end {
            break ok;
        }
        std::thread::sleep(Duration::from_millis(200));
    };
    assert!(
        healthy,
        "/healthz never answered with idle connections held open"
    );
    // Each silent connection was closed by the master (read sees the end of the stream or a
    // reset, not a timeout).
    for c in &mut idle {
        c.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
        // Whatever the master answers before closing, the stream must end.
        let mut answer = Vec::new();
        match c.read_to_end(&mut answer) {
            Ok(_) => {}
            Err(e) => assert!(
                !matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ),
                "an idle connection stayed open: {e}"
            ),
        }
    }
}

/// Waits for `path` to exist, at most `secs`.
fn wait_for(secs: u64, what: &str, mut f: impl FnMut() -> bool) {
    let end = Instant::now() + Duration::from_secs(secs);
    while !f() {
        assert!(Instant::now() < end, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(200));
    }
}

/// Starts the master expecting it to refuse to start; returns its stderr.
fn refused_start(data: &std::path::Path) -> String {
    let out = Command::new(exe())
        .args(["server", "--listen", "127.0.0.1:0", "--data-dir"])
        .arg(data)
        .env_remove("LUXFARM_TOKEN")
        .stdin(Stdio::null())
        .output()
        .expect("run server");
    assert!(
        !out.status.success(),
        "the master started: {}",
        String::from_utf8_lossy(&out.stdout)
    );
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn a_deleted_checkpoint_fails_its_job_alone_and_an_emptied_database_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let id = {
        let s = server(
            &data,
            &["--checkpoint-interval", "0.3", "--upload-interval", "0.3"],
        );
        let scene = std::fs::read(small_scene(dir.path(), "c", (16, 16), "")).unwrap();
        let (st, job) = post_job(&s, scene, "?filename=c.lxs&haltspp=1000000");
        assert_eq!(st, 201, "{job}");
        let id = job["id"].as_str().unwrap().to_string();
        let _w = worker(&s.url(), 1, &[]);
        // A checkpoint the store has committed (its generation leads `film_version`): its
        // file is on disk before the store points at it, so a file alone is not enough.
        let committed = |v: &serde_json::Value| {
            v["film_version"]
                .as_str()
                .and_then(|f| f.split('-').next())
                .is_some_and(|g| g != "0")
        };
        let v = wait_job(&s, &id, 120, committed);
        assert!(committed(&v), "no checkpoint committed: {v}");
        let jobdir = data.join("jobs").join(&id);
        assert!(files_under(&jobdir)
            .iter()
            .any(|p| p.to_string_lossy().contains("checkpoint")));
        id
    };
    // Master and worker are gone (killed); the checkpoint goes too.
    for p in files_under(&data.join("jobs").join(&id)) {
        if p.to_string_lossy().contains("checkpoint") {
            std::fs::remove_file(p).unwrap();
        }
    }
    {
        let s = server(&data, &[]);
        let v = wait_job(&s, &id, 30, |v| v["state"] == "failed");
        assert_eq!(v["state"], "failed", "{v}");
        let why = v.to_string();
        assert!(
            why.contains("checkpoint"),
            "the reason names no checkpoint: {v}"
        );
        // The farm goes on: a new job renders to the end.
        let scene = std::fs::read(small_scene(dir.path(), "d", (8, 8), "")).unwrap();
        let (st, job) = post_job(&s, scene, "?filename=d.lxs&haltspp=1");
        assert_eq!(st, 201, "{job}");
        let next = job["id"].as_str().unwrap().to_string();
        let _w = worker(&s.url(), 1, &[]);
        let v = wait_job(&s, &next, 120, |v| v["state"] == "done");
        assert_eq!(v["state"], "done", "{v}");
    }
    // An emptied database beside the farm's files: the master refuses to start, naming it.
    std::fs::write(data.join("farm.sqlite"), b"").unwrap();
    let _ = std::fs::remove_file(data.join("farm.sqlite-wal"));
    let _ = std::fs::remove_file(data.join("farm.sqlite-shm"));
    let err = refused_start(&data);
    assert!(err.contains("farm.sqlite"), "{err}");
}

#[test]
fn a_worker_failure_reason_names_no_worker_path() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &[]);
    // A mesh the master can see is there but the worker cannot read: a PLY header that lies.
    let scene_dir = dir.path().join("bundle");
    std::fs::create_dir_all(&scene_dir).unwrap();
    let scene = small_scene(&scene_dir, "f", (8, 8), "");
    let text = std::fs::read_to_string(&scene).unwrap().replace(
        "WorldEnd",
        "Shape \"plymesh\" \"string filename\" [\"broken.ply\"]\nWorldEnd",
    );
    std::fs::write(&scene, text).unwrap();
    std::fs::write(
        scene_dir.join("broken.ply"),
        b"ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty float x\nend_header\n\x01\x02",
    )
    .unwrap();
    let mut b = tar::Builder::new(Vec::new());
    b.append_path_with_name(&scene, "f.lxs").unwrap();
    b.append_path_with_name(scene_dir.join("broken.ply"), "broken.ply")
        .unwrap();
    let (st, job) = post_job(&s, b.into_inner().unwrap(), "?filename=f.tar&haltspp=1");
    assert_eq!(st, 201, "{job}");
    let id = job["id"].as_str().unwrap().to_string();
    let cache = dir.path().join("worker-cache");
    let _w = worker(&s.url(), 1, &["--cache-dir", cache.to_str().unwrap()]);
    let v = wait_job(&s, &id, 120, |v| v["state"] == "failed");
    assert_eq!(v["state"], "failed", "{v}");
    let text = v.to_string();
    assert!(text.contains("broken.ply"), "the reason names no file: {v}");
    for leak in [
        cache.to_string_lossy().as_ref(),
        "worker-cache",
        dir.path().to_string_lossy().as_ref(),
    ] {
        assert!(!text.contains(leak), "the reason shows {leak}: {v}");
    }
}

/// A message whose field 1 is bytes where RegisterRequest has a string: with invalid UTF-8 it
/// cannot be decoded as a RegisterRequest.
#[derive(Clone, PartialEq, prost::Message)]
struct NotARegisterRequest {
    #[prost(bytes = "vec", tag = "1")]
    name: Vec<u8>,
}

/// One unary gRPC call of `path` carrying `msg`; the status code of the answer.
async fn grpc_call(url: &str, path: &'static str, msg: NotARegisterRequest) -> tonic::Code {
    let ch = luxfarm_proto::connect::channel(url, None, None).unwrap();
    let mut g = tonic::client::Grpc::new(ch);
    g.ready().await.unwrap();
    let codec = tonic_prost::ProstCodec::<NotARegisterRequest, ()>::default();
    let r = g
        .unary(
            tonic::Request::new(msg),
            tonic::codegen::http::uri::PathAndQuery::from_static(path),
            codec,
        )
        .await;
    match r {
        Ok(_) => tonic::Code::Ok,
        Err(s) => s.code(),
    }
}

#[test]
fn malformed_grpc_is_the_callers_fault_and_unknown_methods_are_unimplemented() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &[]);
    let url = s.url();
    let rt = tokio::runtime::Runtime::new().unwrap();
    rt.block_on(async {
        let bad = NotARegisterRequest {
            name: vec![0xff, 0xfe, 0x80],
        };
        let code = grpc_call(&url, "/luxfarm.v1.Worker/Register", bad.clone()).await;
        assert_eq!(code, tonic::Code::InvalidArgument);
        let code = grpc_call(&url, "/luxfarm.v1.Nope/Call", bad.clone()).await;
        assert_eq!(code, tonic::Code::Unimplemented);
        // The caller's rights are checked before the method is looked up: a non-worker
        // learns nothing about the Worker service's methods.
        let code = grpc_call(&url, "/luxfarm.v1.Worker/NoSuchCall", bad).await;
        assert_eq!(code, tonic::Code::PermissionDenied);
    });
    // The master is still serving.
    let ok = http().get(format!("{url}/healthz")).send().unwrap();
    assert!(ok.status().is_success());
}

#[test]
fn a_checkpoint_that_cannot_be_written_is_named_and_contained_to_its_job() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let s = server(
        &data,
        &["--checkpoint-interval", "0.3", "--upload-interval", "0.3"],
    );
    let scene = std::fs::read(small_scene(dir.path(), "a", (16, 16), "")).unwrap();
    let (st, job) = post_job(&s, scene, "?filename=a.lxs&haltspp=1000000");
    assert_eq!(st, 201, "{job}");
    let a = job["id"].as_str().unwrap().to_string();
    let _w = worker(&s.url(), 1, &[]);
    let jobdir = data.join("jobs").join(&a);
    wait_for(120, "a first checkpoint", || {
        files_under(&jobdir)
            .iter()
            .any(|p| p.to_string_lossy().contains("checkpoint"))
    });
    // The job's directory becomes a file: every later checkpoint write of this job fails.
    std::fs::rename(&jobdir, dir.path().join("moved-away")).unwrap();
    std::fs::write(&jobdir, b"not a directory").unwrap();
    let v = wait_job(&s, &a, 60, |v| v.to_string().contains("checkpoint failed"));
    let text = v.to_string();
    assert!(text.contains("checkpoint failed"), "{v}");
    assert!(
        text.contains(&format!("jobs/{a}")),
        "the file is not named: {v}"
    );
    assert!(
        !text.contains(&dir.path().to_string_lossy().to_string()),
        "a host path is shown: {v}"
    );
    // Another job still renders to its halt while the first one's checkpoints fail.
    let scene = std::fs::read(small_scene(dir.path(), "b", (8, 8), "")).unwrap();
    let (st, job) = post_job(&s, scene, "?filename=b.lxs&haltspp=1&priority=90");
    assert_eq!(st, 201, "{job}");
    let b = job["id"].as_str().unwrap().to_string();
    // Cancelling the failing job takes effect and frees its worker for the other one.
    let r = http().delete(s.api(&format!("/jobs/{a}"))).send().unwrap();
    assert_eq!(r.status().as_u16(), 200);
    let v = wait_job(&s, &a, 30, |v| v["state"] == "cancelled");
    assert_eq!(v["state"], "cancelled", "{v}");
    let v = wait_job(&s, &b, 120, |v| v["state"] == "done");
    assert_eq!(v["state"], "done", "{v}");
    assert!(
        files_under(&data.join("jobs").join(&b))
            .iter()
            .any(|p| p.to_string_lossy().contains("checkpoint")),
        "the other job wrote no checkpoint"
    );
}
