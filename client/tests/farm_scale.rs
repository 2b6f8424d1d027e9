//! The farm at production scale, against a real master with real workers on loopback:
//! a 24-frame Cornell box sequence with a moving camera (numbered .lxs files submitted with
//! `luxfarm submit frames/*.lxs`) renders on two workers, each frame to its halt, outputs
//! numbered; a tagged worker takes only jobs asking for its tag; a worker failing every lease
//! is blocked after `--block-after` failures while the job completes on another; the master's
//! Server-Sent Events arrive on a plain HTTP client; the schema of an older store is upgraded.

mod farm_common;

use farm_common::*;
use luxfarm_proto as pb;
use luxfarm_proto::connect;
use std::collections::BTreeSet;
use std::path::Path;
use std::process::Command;
use std::time::Duration;

fn rt() -> tokio::runtime::Runtime {
    tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .unwrap()
}

/// The Cornell box at `res`, its camera moved along x by frame (`shot_0001.lxs` ...).
fn cornell_frames(dir: &Path, frames: u32, res: u32) -> Vec<String> {
    let text = std::fs::read_to_string(shared().join("scenes/cornell/cornell.lxs")).unwrap();
    std::fs::create_dir_all(dir).unwrap();
    let mut names = Vec::new();
    for f in 1..=frames {
        let x = -0.6 + 1.2 * f64::from(f - 1) / f64::from(frames.max(2) - 1);
        let scene = text
            .replace(
                "LookAt 0 -3.9 1 0 0 1 0 0 1",
                &format!("LookAt {x:.4} -3.9 1 0 0 1 0 0 1"),
            )
            .replace(
                "\"integer xresolution\" [256] \"integer yresolution\" [256]",
                &format!("\"integer xresolution\" [{res}] \"integer yresolution\" [{res}]"),
            )
            .replace(
                "\"string filename\" [\"cornell\"]",
                &format!("\"string filename\" [\"shot_{f:04}\"]"),
            );
        assert!(scene.contains(&format!("LookAt {x:.4}")) && scene.contains(&format!("[{res}]")));
        let name = format!("shot_{f:04}.lxs");
        std::fs::write(dir.join(&name), scene).unwrap();
        names.push(name);
    }
    names
}

/// Polls a sequence until `pred` holds or `secs` pass.
fn wait_sequence(
    s: &Server,
    id: &str,
    secs: u64,
    pred: impl Fn(&serde_json::Value) -> bool,
) -> serde_json::Value {
    wait_view(s, &format!("/sequences/{id}"), secs, pred)
}

#[test]
fn a_cornell_sequence_renders_every_frame_to_its_halt_on_two_workers() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &["--upload-interval", "0.5"]);
    let frames = dir.path().join("frames");
    let names = cornell_frames(&frames, 24, 16);
    let _w1 = worker(&s.url(), 1, &["--name", "w1"]);
    let _w2 = worker(&s.url(), 1, &["--name", "w2"]);
    let out = Command::new(exe())
        .current_dir(&frames)
        .args([
            "submit",
            "--master",
            &s.url(),
            "--haltspp",
            "4",
            "--policy",
            "spread",
        ])
        .args(&names)
        .env_remove("LUXFARM_TOKEN")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    let seq = stdout
        .lines()
        .find_map(|l| l.strip_prefix("sequence "))
        .expect("the sequence id is printed first")
        .trim()
        .to_string();
    assert_eq!(stdout.lines().count(), 25, "{stdout}");
    let v = wait_sequence(&s, &seq, 600, |v| v["state"] == "done");
    assert_eq!(v["state"], "done", "{v}");
    assert_eq!(v["policy"], "spread");
    let frames = v["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 24);
    assert_eq!(v["frames_done"], 24);
    let mut workers = BTreeSet::new();
    for (i, f) in frames.iter().enumerate() {
        let n = i + 1;
        assert_eq!(f["number"], n, "{f}");
        assert_eq!(f["state"], "done", "{f}");
        assert!(
            f["spp"].as_f64().unwrap() >= 4.0,
            "frame {n} halted early: {f}"
        );
        assert_eq!(f["output"], format!("shot_{n:04}.png"));
        let job = get_json(&s.api(&format!("/jobs/{}", f["job_id"].as_str().unwrap())));
        assert_eq!(job["sequence"], seq.as_str());
        assert_eq!(job["name"], format!("shot_{n:04}"));
        for w in job["workers"].as_array().unwrap() {
            workers.insert(w["worker_id"].as_str().unwrap().to_string());
        }
    }
    assert_eq!(
        workers.len(),
        2,
        "both workers rendered frames: {workers:?}"
    );
    // The outputs download under their numbered names.
    let first = frames[0]["job_id"].as_str().unwrap();
    let r = http()
        .get(s.api(&format!("/jobs/{first}/image.png")))
        .send()
        .unwrap();
    assert_eq!(r.status().as_u16(), 200);
    let cd = r.headers()["content-disposition"]
        .to_str()
        .unwrap()
        .to_string();
    assert!(cd.contains("shot_0001.png"), "{cd}");
    assert!(r.bytes().unwrap().starts_with(b"\x89PNG"));
    let list = get_json(&s.api("/sequences"));
    assert_eq!(list.as_array().map(Vec::len), Some(1), "{list}");
}

/// Registers a protocol client as a worker with `tags`; returns its client and id.
async fn fake_worker(
    url: &str,
    tags: &[&str],
) -> (
    pb::worker_client::WorkerClient<connect::AuthChannel>,
    String,
) {
    let reg = connect::worker_client(connect::channel(url, None, None).unwrap())
        .register(pb::RegisterRequest {
            name: "failing".into(),
            threads: 1,
            protocol: pb::PROTOCOL_VERSION,
            build: pb::BUILD.into(),
            tags: tags.iter().map(|t| t.to_string()).collect(),
            ..Default::default()
        })
        .await
        .unwrap()
        .into_inner();
    let c = connect::worker_client(connect::channel(url, Some(&reg.worker_token), None).unwrap());
    (c, reg.worker_id)
}

#[test]
fn tagged_workers_take_only_their_jobs_and_failing_workers_are_blocked() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(
        &dir.path().join("data"),
        &["--upload-interval", "0.5", "--block-after", "2"],
    );
    let scene = std::fs::read(small_scene(dir.path(), "t", (16, 12), "")).unwrap();
    // An untagged job first, then one asking for the tag.
    let (st, plain) = post_job(&s, scene.clone(), "?filename=t.lxs&haltspp=4&name=plain");
    assert_eq!(st, 201, "{plain}");
    let (st, tagged) = post_job(
        &s,
        scene.clone(),
        "?filename=t.lxs&haltspp=4&name=tagged&tags=Special",
    );
    assert_eq!(st, 201, "{tagged}");
    assert_eq!(tagged["tags"], serde_json::json!(["special"]));
    let (plain, tagged) = (
        plain["id"].as_str().unwrap(),
        tagged["id"].as_str().unwrap(),
    );
    // The tagged worker passes over the older untagged job.
    let mut special = worker(&s.url(), 1, &["--tag", "special", "--name", "special"]);
    let t = wait_job(&s, tagged, 300, |v| v["state"] == "done");
    assert_eq!(t["state"], "done", "{t}");
    let ws = get_json(&s.api("/workers"));
    let sw = ws
        .as_array()
        .unwrap()
        .iter()
        .find(|w| w["name"] == "special")
        .unwrap();
    assert_eq!(sw["tags"], serde_json::json!(["special"]), "{sw}");
    let p = get_json(&s.api(&format!("/jobs/{plain}")));
    assert_eq!(p["state"], "queued", "{p}");
    assert_eq!(p["workers"].as_array().map(Vec::len), Some(0), "{p}");
    special.term();
    special.wait_exit(60);
    let r = http()
        .delete(s.api(&format!("/jobs/{plain}")))
        .send()
        .unwrap();
    assert_eq!(r.status().as_u16(), 200);

    // A worker failing every lease (a protocol client), beside one that renders.
    let (st, job) = post_job(&s, scene, "?filename=t.lxs&haltspp=400&name=flaky");
    assert_eq!(st, 201, "{job}");
    let job = job["id"].as_str().unwrap().to_string();
    let rt = rt();
    let (mut c, fake_id) = rt.block_on(fake_worker(&s.url(), &[]));
    let fail_next = |c: &mut pb::worker_client::WorkerClient<connect::AuthChannel>| {
        rt.block_on(async {
            let next = c
                .next_assignment(pb::NextRequest {
                    worker_id: fake_id.clone(),
                })
                .await
                .unwrap()
                .into_inner();
            let Some(a) = next.assignment else {
                return false;
            };
            assert_eq!(a.job_id, job);
            c.report_failure(pb::FailureReport {
                worker_id: fake_id.clone(),
                lease_id: a.lease_id,
                reason: "cannot open /home/render/secret/t.lxs: out of memory".into(),
            })
            .await
            .unwrap();
            true
        })
    };
    assert!(fail_next(&mut c), "the first lease");
    // A rendering worker joins; once it holds a lease, the flaky one fails again and is
    // blocked: the master gives it no more leases of the job.
    let _good = worker(&s.url(), 1, &["--name", "good"]);
    let v = wait_job(&s, &job, 300, |v| {
        v["workers"].as_array().is_some_and(|ws| {
            ws.iter()
                .any(|w| w["active"] == true && w["worker_id"] != fake_id.as_str())
        })
    });
    assert_eq!(v["state"], "rendering", "{v}");
    assert!(fail_next(&mut c), "the second lease");
    assert!(
        !fail_next(&mut c),
        "a blocked worker gets no lease of the job"
    );
    let done = wait_job(&s, &job, 600, |v| v["state"] == "done");
    assert_eq!(done["state"], "done", "{done}");
    let f = done["failures"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["worker_id"] == fake_id.as_str())
        .cloned()
        .unwrap_or_default();
    assert_eq!(f["failures"], 2, "{done}");
    assert_eq!(f["blocked"], true, "{done}");
    let reason = f["reason"].as_str().unwrap_or("");
    assert!(reason.contains("t.lxs") && !reason.contains("/home"), "{f}");
    let ws = get_json(&s.api("/workers"));
    let fw = ws
        .as_array()
        .unwrap()
        .iter()
        .find(|w| w["id"] == fake_id.as_str())
        .unwrap();
    assert_eq!(fw["blocked_jobs"], serde_json::json!([job]), "{fw}");
}

/// The next (event name, JSON data) pair of an SSE stream; None when the stream ends.
fn next_sse(
    lines: &mut impl Iterator<Item = std::io::Result<String>>,
) -> Option<(String, serde_json::Value)> {
    let mut event = String::new();
    for line in lines {
        let line = line.expect("the event stream stays open");
        if let Some(e) = line.strip_prefix("event: ") {
            event = e.to_string();
        } else if let Some(d) = line.strip_prefix("data: ") {
            return Some((event, serde_json::from_str(d).expect("JSON data")));
        }
    }
    None
}

/// Reads SSE events until one named `name` whose data satisfies `pred`; returns the data.
fn next_event(
    lines: &mut impl Iterator<Item = std::io::Result<String>>,
    name: &str,
    pred: impl Fn(&serde_json::Value) -> bool,
) -> serde_json::Value {
    while let Some((event, v)) = next_sse(lines) {
        if event == name && pred(&v) {
            return v;
        }
    }
    panic!("the event stream ended before a matching {name} event");
}

#[test]
fn server_sent_events_push_job_changes() {
    use std::io::BufRead;
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &["--upload-interval", "0.5"]);
    let client = reqwest::blocking::Client::builder()
        .timeout(Duration::from_secs(300))
        .build()
        .unwrap();
    let r = client
        .get(format!("{}/api/events", s.url()))
        .send()
        .unwrap();
    assert_eq!(r.status().as_u16(), 200);
    let ct = r.headers()["content-type"].to_str().unwrap().to_string();
    assert!(ct.starts_with("text/event-stream"), "{ct}");
    let mut lines = std::io::BufReader::new(r).lines();
    // The current state first: no jobs, no workers, no sequences.
    let jobs = next_event(&mut lines, "jobs", |_| true);
    assert_eq!(jobs, serde_json::json!([]));
    let scene = std::fs::read(small_scene(dir.path(), "e", (8, 6), "")).unwrap();
    let (st, job) = post_job(&s, scene, "?filename=e.lxs&haltspp=2");
    assert_eq!(st, 201, "{job}");
    let id = job["id"].as_str().unwrap().to_string();
    let has = |state: &'static str| {
        let id = id.clone();
        move |v: &serde_json::Value| {
            v.as_array().is_some_and(|js| {
                js.iter()
                    .any(|j| j["id"] == id.as_str() && j["state"] == state)
            })
        }
    };
    next_event(&mut lines, "jobs", has("queued"));
    let _w = worker(&s.url(), 1, &["--name", "sse"]);
    // The worker's arrival and the job's end may come in one update (the stream sends at most
    // one snapshot every 250 ms): read until both have been seen, in whatever order.
    let done = has("done");
    let (mut saw_worker, mut saw_done) = (false, false);
    while let Some((event, v)) = next_sse(&mut lines) {
        match event.as_str() {
            "workers"
                if v.as_array()
                    .is_some_and(|ws| ws.iter().any(|w| w["name"] == "sse")) =>
            {
                assert_eq!(v.as_array().map(Vec::len), Some(1), "{v}");
                saw_worker = true;
            }
            "jobs" if done(&v) => saw_done = true,
            _ => {}
        }
        if saw_worker && saw_done {
            return;
        }
    }
    panic!("the event stream ended before the worker and the job's end were seen");
}
