//! A worker drains on SIGTERM as a Kubernetes pod is stopped: a real `luxfarm worker` in the
//! middle of a job gets SIGTERM, stops rendering, uploads its last delta, waits until the
//! master holds it durably, and exits with status 0 within the pod's grace period (the
//! `terminationGracePeriodSeconds` of `deploy/k8s/worker.yaml`, read here: the only bound, a
//! guard against a hang rather than a timing claim). The master's film then holds exactly the
//! samples of every delta the worker was told was acknowledged, the ones after the signal
//! included, and its lease ended without counting as a failure.

mod farm_common;

use farm_common::*;
use std::collections::BTreeSet;
use std::path::Path;

/// The worker pods' grace period (seconds) from the manifest.
fn grace_period() -> u64 {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR")).join("../deploy/k8s/worker.yaml");
    let text = std::fs::read_to_string(&manifest).expect("deploy/k8s/worker.yaml");
    text.lines()
        .find_map(|l| {
            l.trim()
                .strip_prefix("terminationGracePeriodSeconds:")?
                .trim()
                .parse()
                .ok()
        })
        .expect("the worker Deployment sets terminationGracePeriodSeconds")
}

/// The names of the deltas a worker kept as merged by the master.
fn merged_names(dir: &Path) -> BTreeSet<String> {
    files_under(dir)
        .iter()
        .filter_map(|p| p.file_name()?.to_str().map(str::to_string))
        .filter(|n| n.ends_with(".merged.lxd"))
        .collect()
}

#[test]
fn a_worker_told_to_stop_uploads_its_last_delta_and_exits_within_the_grace_period() {
    let grace = grace_period();
    assert!(grace > 0);
    let dir = tempfile::tempdir().unwrap();
    let s = server(
        &dir.path().join("data"),
        &["--upload-interval", "1", "--checkpoint-interval", "2"],
    );
    let scene = std::fs::read(small_scene(dir.path(), "drain", (16, 12), "")).unwrap();
    let (st, job) = post_job(&s, scene, "?filename=d.lxs&halttime=3600");
    assert_eq!(st, 201, "{job}");
    let id = job["id"].as_str().unwrap().to_string();
    let kept = dir.path().join("kept");
    let mut w = worker(&s.url(), 1, &["--keep-deltas", kept.to_str().unwrap()]);
    let v = wait_job(&s, &id, 300, |v| {
        v["merged_deltas"].as_u64().unwrap_or(0) >= 2
    });
    assert_eq!(v["state"], "rendering", "{v}");

    let before = merged_names(&kept);
    let signalled = std::time::Instant::now();
    w.term();
    let status = w
        .wait_exit(grace)
        .unwrap_or_else(|| panic!("the worker did not exit within the {grace} s grace period"));
    assert!(status.success(), "{status:?}");
    eprintln!(
        "the worker exited {:.1} s after SIGTERM (grace period {grace} s)",
        signalled.elapsed().as_secs_f64()
    );

    // Deltas were acknowledged after the signal: its last one at least.
    let after = merged_names(&kept);
    assert!(
        after.len() > before.len() && after.is_superset(&before),
        "before {before:?}, after {after:?}"
    );
    let (sum, n) = sum_kept(&[&kept]);
    let v = get_json(&s.api(&format!("/jobs/{id}")));
    assert_eq!(v["merged_deltas"].as_u64(), Some(n as u64), "{v}");
    assert_eq!(v["samples"].as_f64(), Some(sum.total_samples()), "{v}");
    assert!(sum.total_samples() > 0.0);
    // The worker left only once its deltas were durable: the checkpoint holds them all.
    assert_same_sums(&final_checkpoint(&s, &id), &sum);
    // The lease ended cleanly: no longer active, not a failure of the worker, the job renders
    // on for the next worker.
    assert_eq!(v["state"], "rendering", "{v}");
    assert_eq!(v["active_leases"], 0, "{v}");
    assert_eq!(v["failures"].as_array().map(Vec::len), Some(0), "{v}");
}
