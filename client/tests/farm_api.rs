//! Farm REST API without rendering: bad bundles refused (4xx JSON, nothing written outside the
//! data dir), the bearer token, queue order and cancel, the OpenAPI document and metrics.

mod farm_common;

use std::path::Path;

use farm_common::*;
use std::io::Write;

fn zip_with(entries: &[(&str, &[u8])]) -> Vec<u8> {
    let mut w = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let opts = zip::write::SimpleFileOptions::default();
    for (name, data) in entries {
        w.start_file(*name, opts).unwrap();
        w.write_all(data).unwrap();
    }
    w.finish().unwrap().into_inner()
}

fn assert_error(status: u16, body: &serde_json::Value, want: u16, detail_has: &str) {
    assert_eq!(status, want, "{body}");
    assert!(body["error"].is_string(), "{body}");
    let detail = body["detail"].as_str().unwrap_or("");
    assert!(
        detail.contains(detail_has),
        "{detail:?} lacks {detail_has:?}"
    );
}

#[test]
fn bad_bundles_are_refused_with_json_errors() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let s = server(&data, &["--max-upload", "200000"]);
    let scene_dir = dir.path().join("scene");
    std::fs::create_dir_all(&scene_dir).unwrap();
    let scene = std::fs::read(small_scene(&scene_dir, "ok", (8, 6), "")).unwrap();

    // zip slip
    let z = zip_with(&[("ok.lxs", &scene), ("../evil.lxs", b"x")]);
    let (st, body) = post_job(&s, z, "?filename=b.zip");
    assert_error(st, &body, 400, "'..' refused");
    // absolute path
    let z = zip_with(&[("/tmp/abs.lxs", &scene)]);
    let (st, body) = post_job(&s, z, "?filename=b.zip");
    assert_error(st, &body, 400, "absolute path refused");
    // symlink in a tar
    let mut b = tar::Builder::new(Vec::new());
    let mut h = tar::Header::new_ustar();
    h.set_entry_type(tar::EntryType::Symlink);
    h.set_size(0);
    b.append_link(&mut h, "ok.lxs", "/etc/passwd").unwrap();
    let (st, body) = post_job(&s, b.into_inner().unwrap(), "?filename=b.tar");
    assert_error(st, &body, 400, "refused");
    // missing include: 4xx naming file:line
    let text = "WorldBegin\nInclude \"missing.lxo\"\nWorldEnd\n";
    let (st, body) = post_job(&s, text.as_bytes().to_vec(), "?filename=inc.lxs");
    assert_eq!(st, 400, "{body}");
    let detail = body["detail"].as_str().unwrap();
    assert!(detail.contains("inc.lxs:2"), "{detail}");
    // oversized
    let (st, body) = post_job(&s, vec![b'#'; 300_000], "?filename=big.lxs");
    assert_eq!(st, 413, "{body}");
    assert!(body["error"].is_string(), "{body}");
    // not a scene
    let (st, body) = post_job(&s, vec![0u8, 1, 2, 3, 255, 0], "?filename=x.bin");
    assert_eq!(st, 415, "{body}");
    // a zip without a scene
    let z = zip_with(&[("readme.txt", b"hello")]);
    let (st, body) = post_job(&s, z, "?filename=b.zip");
    assert_error(st, &body, 400, "no .lxs");

    // nothing was written outside the data dir, and no job exists
    assert!(!dir.path().join("evil.lxs").exists());
    assert!(!std::path::Path::new("/tmp/abs.lxs").exists());
    let outside: Vec<_> = files_under(dir.path())
        .into_iter()
        .filter(|p| !p.starts_with(&data) && !p.starts_with(&scene_dir))
        .collect();
    assert!(outside.is_empty(), "{outside:?}");
    let jobs = get_json(&s.api("/jobs"));
    assert_eq!(jobs.as_array().map(Vec::len), Some(0), "{jobs}");
    // staging directories were cleaned up
    assert!(files_under(&data.join("tmp")).is_empty());
}

#[test]
fn token_is_required_when_set() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &["--token", "s3cret"]);
    let c = http();
    let r = c.get(s.api("/jobs")).send().unwrap();
    assert_eq!(r.status().as_u16(), 401);
    let body: serde_json::Value = r.json().unwrap();
    assert_eq!(body["error"], "unauthorized");
    let r = c.get(s.api("/jobs")).bearer_auth("wrong").send().unwrap();
    assert_eq!(r.status().as_u16(), 401);
    let r = c.get(s.api("/jobs")).bearer_auth("s3cret").send().unwrap();
    assert_eq!(r.status().as_u16(), 200);
    let r = c.get(format!("http://{}/healthz", s.addr)).send().unwrap();
    assert_eq!(r.status().as_u16(), 200);
    // the CLI (gRPC) is refused without the token, accepted with it
    let out = std::process::Command::new(exe())
        .args(["jobs", "--master", &s.url()])
        .env_remove("LUXFARM_TOKEN")
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("unauthorized"));
    let out = std::process::Command::new(exe())
        .args(["jobs", "--master", &s.url(), "--token", "s3cret"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn non_loopback_without_token_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = std::process::Command::new(exe())
        .args(["server", "--listen", "0.0.0.0:0", "--data-dir"])
        .arg(dir.path())
        .env_remove("LUXFARM_TOKEN")
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--token"));
}

#[test]
fn queue_order_and_cancel() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &[]);
    let scene = std::fs::read(small_scene(dir.path(), "q", (8, 6), "")).unwrap();
    let mut ids = Vec::new();
    for (name, prio) in [("a", 0), ("b", 5), ("c", 0)] {
        let (st, body) = post_job(
            &s,
            scene.clone(),
            &format!("?filename=q.lxs&name={name}&priority={prio}&haltspp=3"),
        );
        assert_eq!(st, 201, "{body}");
        assert_eq!(body["state"], "queued");
        assert_eq!(body["haltspp"], 3.0);
        ids.push(body["id"].as_str().unwrap().to_string());
    }
    let jobs = get_json(&s.api("/jobs"));
    let names: Vec<&str> = jobs
        .as_array()
        .unwrap()
        .iter()
        .map(|j| j["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["b", "a", "c"]);
    let c = http();
    let r = c
        .delete(s.api(&format!("/jobs/{}", ids[0])))
        .send()
        .unwrap();
    assert_eq!(r.status().as_u16(), 200);
    let v: serde_json::Value = r.json().unwrap();
    assert_eq!(v["state"], "cancelled");
    let r = c
        .delete(s.api(&format!("/jobs/{}", ids[0])))
        .send()
        .unwrap();
    assert_eq!(r.status().as_u16(), 409);
    let r = c.get(s.api("/jobs/nope")).send().unwrap();
    assert_eq!(r.status().as_u16(), 404);
    let v: serde_json::Value = r.json().unwrap();
    assert_eq!(v["error"], "not_found");
    // the preview of a job without samples is "not ready", as JSON
    let r = c
        .get(s.api(&format!("/jobs/{}/preview.png", ids[1])))
        .send()
        .unwrap();
    assert_eq!(r.status().as_u16(), 503);
}

#[test]
fn a_job_without_a_name_is_named_after_its_film() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &[]);
    // A raw .lxs without ?filename=: the Film's filename names the job.
    let named = small_scene(
        dir.path(),
        "n",
        (8, 6),
        r#""string filename" ["renders/hall"]"#,
    );
    let (st, body) = post_job(&s, std::fs::read(named).unwrap(), "");
    assert_eq!(st, 201, "{body}");
    assert_eq!(body["name"], "hall");
    // Without a Film filename: the scene's own name in the bundle.
    let plain = std::fs::read(small_scene(dir.path(), "kitchen", (8, 6), "")).unwrap();
    let (st, body) = post_job(&s, plain, "?filename=kitchen.lxs");
    assert_eq!(st, 201, "{body}");
    assert_eq!(body["name"], "kitchen");
}

#[test]
fn multipart_submission_and_documents() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &[]);
    let scene = std::fs::read(small_scene(dir.path(), "m", (8, 6), "")).unwrap();
    let form = reqwest::blocking::multipart::Form::new()
        .part(
            "file",
            reqwest::blocking::multipart::Part::bytes(scene).file_name("m.lxs"),
        )
        .text("halttime", "7")
        .text("priority", "2");
    let r = http().post(s.api("/jobs")).multipart(form).send().unwrap();
    assert_eq!(r.status().as_u16(), 201);
    let v: serde_json::Value = r.json().unwrap();
    assert_eq!(v["halttime"], 7.0);
    assert_eq!(v["priority"], 2);
    assert_eq!(v["name"], "m");
    let doc = get_json(&s.api("/openapi.json"));
    assert!(
        doc["paths"]["/api/v1/jobs/{id}/preview.png"].is_object(),
        "{doc}"
    );
    assert!(doc["paths"]["/api/v1/jobs"]["post"].is_object());
    let metrics = http()
        .get(format!("http://{}/metrics", s.addr))
        .send()
        .unwrap()
        .text()
        .unwrap();
    assert!(
        metrics.contains("luxfarm_jobs{state=\"queued\"} 1"),
        "{metrics}"
    );
}

/// `luxfarm jobs` against `url` trusting `ca` (None: the system's roots).
fn jobs_over_tls(url: &str, ca: Option<&Path>) -> std::process::Output {
    let mut cmd = std::process::Command::new(exe());
    cmd.args(["jobs", "--master", url]);
    if let Some(ca) = ca {
        cmd.arg("--ca-cert").arg(ca);
    }
    cmd.output().unwrap()
}

/// `luxfarm certs` makes a private CA and a master certificate; the master serves REST and
/// gRPC over TLS with it, clients trusting the CA connect, others are told what to do. A
/// second run keeps the CA, so a certificate for more names needs no new `ca.crt`.
#[test]
fn certs_make_a_private_ca_and_tls_serves_rest_and_grpc() {
    let dir = tempfile::tempdir().unwrap();
    let certs = dir.path().join("certs");
    let make = |extra: &[&str]| {
        std::process::Command::new(exe())
            .args([
                "certs",
                "--dir",
                certs.to_str().unwrap(),
                "--name",
                "localhost",
            ])
            .args(extra)
            .output()
            .unwrap()
    };
    let out = make(&[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (ca, crt, key) = (
        certs.join("ca.crt"),
        certs.join("master.crt"),
        certs.join("master.key"),
    );
    #[cfg(unix)]
    for k in [&key, &certs.join("ca.key")] {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(k).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o600, "{}", k.display());
    }
    // A second run refuses to replace the master's key without --force.
    let again = make(&[]);
    assert!(!again.status.success());
    assert!(String::from_utf8_lossy(&again.stderr).contains("--force"));
    let ca_before = std::fs::read(&ca).unwrap();
    let out = make(&["--name", "127.0.0.1", "--force"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(std::fs::read(&ca).unwrap(), ca_before, "the CA is kept");
    let s = server(
        &dir.path().join("data"),
        &[
            "--tls-cert",
            crt.to_str().unwrap(),
            "--tls-key",
            key.to_str().unwrap(),
        ],
    );
    let port = s.addr.rsplit(':').next().unwrap().to_string();
    // Both names of the reissued certificate, trusted through the kept CA.
    for host in ["localhost", "127.0.0.1"] {
        let out = jobs_over_tls(&format!("https://{host}:{port}"), Some(&ca));
        assert!(
            out.status.success(),
            "{host}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    // Without the CA the certificate is unknown: the error says which option to use.
    let out = jobs_over_tls(&format!("https://localhost:{port}"), None);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--ca-cert"), "{err}");
    // A worker registers over TLS (gRPC) with the CA.
    let _w = worker(
        &format!("https://localhost:{port}"),
        1,
        &["--ca-cert", ca.to_str().unwrap()],
    );
    let end = std::time::Instant::now() + std::time::Duration::from_secs(60);
    let listed = loop {
        let out = std::process::Command::new(exe())
            .args(["workers", "--master", &format!("https://localhost:{port}")])
            .arg("--ca-cert")
            .arg(&ca)
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stdout).to_string();
        if !text.trim().is_empty() || std::time::Instant::now() > end {
            break text;
        }
        std::thread::sleep(std::time::Duration::from_millis(200));
    };
    assert!(!listed.trim().is_empty(), "no worker registered over TLS");
    eprintln!("workers over TLS: {listed}");
    // plain HTTP to a TLS port fails
    let out = jobs_over_tls(&format!("http://localhost:{port}"), None);
    assert!(!out.status.success());
}
