//! Rendering through the farm with real worker processes: two workers render the Cornell scene
//! to haltspp 16 (the merged spp lands between 16 and the overshoot bound, and the merged film
//! is the exact sum of the acknowledged deltas); halttime and cancel end jobs; a worker killed
//! with SIGKILL mid-render leaves the job to the other; a master killed and restarted resumes
//! from its checkpoint without counting a delta twice.

mod farm_common;

use farm_common::*;
use std::path::Path;

fn cornell() -> Vec<u8> {
    let dir = shared().join("scenes/cornell");
    let text = std::fs::read_to_string(dir.join("cornell.lxs")).expect("cornell scene");
    text.into_bytes()
}

/// GET /metrics after a render: the merge latency histogram counts every merged delta, and
/// the upload bytes are those of the kept (lxd2-encoded) merged deltas.
fn check_metrics(s: &Server, merged: usize, kept: &[&Path]) {
    let text = http()
        .get(format!("{}/metrics", s.url()))
        .send()
        .unwrap()
        .text()
        .unwrap();
    let value = |name: &str| -> f64 {
        let line = text
            .lines()
            .find(|l| l.starts_with(name) && l[name.len()..].starts_with(' '))
            .unwrap_or_else(|| panic!("no {name} in /metrics:\n{text}"));
        line[name.len()..].trim().parse().unwrap()
    };
    assert!(
        text.contains("# TYPE luxfarm_merge_seconds histogram"),
        "{text}"
    );
    assert_eq!(value("luxfarm_merge_seconds_count"), merged as f64);
    assert_eq!(
        value("luxfarm_merge_seconds_bucket{le=\"+Inf\"}"),
        merged as f64
    );
    assert!(value("luxfarm_merge_seconds_bucket{le=\"0.001\"}") <= merged as f64);
    assert!(value("luxfarm_merge_seconds_sum") > 0.0);
    let mut bytes = 0u64;
    for d in kept {
        for p in files_under(d) {
            if p.to_string_lossy().ends_with(".merged.lxd") {
                let data = std::fs::read(&p).unwrap();
                assert_eq!(&data[..4], b"LXD2", "workers upload lxd2");
                bytes += data.len() as u64;
            }
        }
    }
    assert_eq!(value("luxfarm_upload_bytes_total"), bytes as f64);
}

#[test]
fn two_workers_render_cornell_to_haltspp() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &["--upload-interval", "1"]);
    let (st, job) = post_job(&s, cornell(), "?filename=cornell.lxs&haltspp=16&seed=7");
    assert_eq!(st, 201, "{job}");
    let id = job["id"].as_str().unwrap().to_string();
    let k1 = dir.path().join("k1");
    let k2 = dir.path().join("k2");
    let mut workers = [
        worker(&s.url(), 1, &["--keep-deltas", k1.to_str().unwrap()]),
        worker(&s.url(), 1, &["--keep-deltas", k2.to_str().unwrap()]),
    ];
    let v = wait_job(&s, &id, 600, |v| {
        v["state"] != "queued" && v["state"] != "rendering"
    });
    assert_eq!(v["state"], "done", "{v}");
    let spp = v["spp"].as_f64().unwrap();
    // overshoot bound: one upload interval of work from each worker (generously: 2 s each at
    // the measured rate) plus the pass in flight
    let rate_spp = v["samples_per_sec"].as_f64().unwrap_or(0.0) / (256.0 * 256.0);
    assert!(spp >= 16.0, "{v}");
    assert!(
        spp <= 16.0 + 2.0 * 2.0 * rate_spp.max(1.0) + 2.0,
        "spp {spp} overshoots: {v}"
    );
    stop_workers(&mut workers);
    let merged = final_checkpoint(&s, &id);
    let (sum, n) = sum_kept(&[&k1, &k2]);
    assert_eq!(n as u64, v["merged_deltas"].as_u64().unwrap());
    assert_same_sums(&merged, &sum);
    assert!(v["workers"].as_array().unwrap().len() >= 2, "{v}");
    check_metrics(&s, n, &[&k1, &k2]);
    // outputs
    let out = s.data.join("jobs").join(&id).join("out");
    for ext in ["png", "exr", "flm"] {
        assert!(out.join(format!("cornell.{ext}")).exists(), "cornell.{ext}");
    }
}

#[test]
fn halttime_cancel_and_queue_order() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &["--upload-interval", "0.5"]);
    let scene = std::fs::read(small_scene(dir.path(), "t", (32, 24), "")).unwrap();
    let (_, a) = post_job(&s, scene.clone(), "?filename=t.lxs&halttime=2&name=first");
    let (_, b) = post_job(
        &s,
        scene.clone(),
        "?filename=t.lxs&haltspp=100000&name=second",
    );
    let a = a["id"].as_str().unwrap().to_string();
    let b = b["id"].as_str().unwrap().to_string();
    let _w = worker(&s.url(), 1, &[]);
    // the first job runs first and ends on halttime
    let v = wait_job(&s, &a, 120, |v| v["state"] == "done");
    assert_eq!(v["state"], "done", "{v}");
    assert!(v["reason"].as_str().unwrap().contains("halttime"), "{v}");
    assert!(v["samples"].as_f64().unwrap() > 0.0);
    // the second starts after it, and a cancel ends it
    let vb = wait_job(&s, &b, 60, |v| v["samples"].as_f64().unwrap_or(0.0) > 0.0);
    assert_eq!(vb["state"], "rendering", "{vb}");
    let r = http().delete(s.api(&format!("/jobs/{b}"))).send().unwrap();
    assert_eq!(r.status().as_u16(), 200);
    let vb = wait_job(&s, &b, 30, |v| v["state"] == "cancelled");
    assert_eq!(vb["state"], "cancelled");
    assert!(vb["finished_ms"].as_i64().unwrap() >= v["finished_ms"].as_i64().unwrap());
    // the cancelled job's film is still downloadable
    let r = http()
        .get(s.api(&format!("/jobs/{b}/film.flm")))
        .send()
        .unwrap();
    assert_eq!(r.status().as_u16(), 200);
}

#[test]
fn killed_worker_and_restarted_master() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let mut s = server(
        &data,
        &[
            "--upload-interval",
            "0.5",
            "--worker-timeout",
            "3",
            "--checkpoint-interval",
            "1",
        ],
    );
    let addr = s.addr.clone();
    let scene = std::fs::read(small_scene(dir.path(), "k", (32, 24), "")).unwrap();
    let (_, job) = post_job(&s, scene, "?filename=k.lxs&haltspp=400");
    let id = job["id"].as_str().unwrap().to_string();
    let k1 = dir.path().join("k1");
    let k2 = dir.path().join("k2");
    let w1 = worker(&s.url(), 1, &["--keep-deltas", k1.to_str().unwrap()]);
    let mut w2 = [worker(
        &s.url(),
        1,
        &["--keep-deltas", k2.to_str().unwrap()],
    )];
    let v = wait_job(&s, &id, 120, |v| v["spp"].as_f64().unwrap_or(0.0) > 20.0);
    assert_eq!(v["state"], "rendering", "{v}");
    drop(w1); // SIGKILL
              // the master, killed and restarted on the same address, resumes from its checkpoint
    std::thread::sleep(std::time::Duration::from_millis(1500));
    drop(std::mem::replace(
        &mut s.proc,
        Proc(std::process::Command::new("true").spawn().unwrap()),
    ));
    let s2 = server_on(
        &data,
        &addr,
        &[
            "--upload-interval",
            "0.5",
            "--worker-timeout",
            "3",
            "--checkpoint-interval",
            "1",
        ],
    );
    let v = wait_job(&s2, &id, 300, |v| v["state"] == "done");
    assert_eq!(v["state"], "done", "{v}");
    assert!(v["spp"].as_f64().unwrap() >= 400.0);
    // no delta counted twice: the final film is the sum of the deltas in the master's ledger,
    // each of which a worker kept; a delta merged before the crash but after the last
    // checkpoint is either re-merged once (its ack was lost) or gone, never doubled
    let merged = final_checkpoint(&s2, &id);
    assert!((merged.total_samples() - v["samples"].as_f64().unwrap()).abs() < 1e-6);
    stop_workers(&mut w2);
    // The killed worker may have been acknowledged a delta it had no time to record: its
    // folder still holds it as sent. Every delta the master may have merged is in the folders.
    let (sum, _) = sum_kept(&[&k1, &k2]);
    let unrecorded: f64 = sent_only(&[&k1, &k2])
        .iter()
        .map(|f| f.total_samples())
        .sum();
    assert!(
        merged.total_samples() <= sum.total_samples() + unrecorded + 1e-6,
        "more samples merged than the workers sent: {} > {} + {unrecorded}",
        merged.total_samples(),
        sum.total_samples()
    );
}

#[test]
fn haltthreshold_ends_a_job() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &["--upload-interval", "0.3"]);
    let scene = std::fs::read(small_scene(
        dir.path(),
        "c",
        (24, 16),
        "\"integer convergencestep\" [4]",
    ))
    .unwrap();
    let (st, job) = post_job(&s, scene, "?filename=c.lxs&haltthreshold=0.5");
    assert_eq!(st, 201, "{job}");
    let id = job["id"].as_str().unwrap().to_string();
    let _w = worker(&s.url(), 1, &[]);
    let v = wait_job(&s, &id, 180, |v| v["state"] == "done");
    assert_eq!(v["state"], "done", "{v}");
    assert!(
        v["reason"].as_str().unwrap().contains("haltthreshold"),
        "{v}"
    );
}

#[test]
fn sigterm_uploads_the_last_delta() {
    let dir = tempfile::tempdir().unwrap();
    // a long upload interval: only the stop at SIGTERM uploads
    let s = server(&dir.path().join("data"), &["--upload-interval", "3600"]);
    let scene = std::fs::read(small_scene(dir.path(), "g", (24, 16), "")).unwrap();
    let (_, job) = post_job(&s, scene, "?filename=g.lxs&haltspp=1000000");
    let id = job["id"].as_str().unwrap().to_string();
    let keep = dir.path().join("keep");
    let mut w = worker(&s.url(), 1, &["--keep-deltas", keep.to_str().unwrap()]);
    let v = wait_job(&s, &id, 60, |v| {
        v["active_leases"].as_u64().unwrap_or(0) > 0
    });
    assert_eq!(v["state"], "rendering", "{v}");
    std::thread::sleep(std::time::Duration::from_millis(1500));
    w.term();
    let status = w.wait_exit(60).expect("worker exits after SIGTERM");
    assert!(status.success(), "{status:?}");
    let v = get_json(&s.api(&format!("/jobs/{id}")));
    assert_eq!(v["merged_deltas"], 1, "{v}");
    assert!(v["samples"].as_f64().unwrap() > 0.0, "{v}");
    assert_eq!(v["active_leases"], 0, "{v}");
    let (sum, n) = sum_kept(&[&keep]);
    assert_eq!(n, 1);
    assert_eq!(sum.total_samples(), v["samples"].as_f64().unwrap());
}
