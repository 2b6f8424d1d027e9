//! Precise halts: a job with `haltspp 16` on a 64x64 scene rendered by two workers ends
//! between 16 spp and 16 + one pass per worker, however long the upload interval is — each
//! lease gets a sample budget from what the job still needs, the workers stop at it and
//! upload at once.

mod farm_common;

use farm_common::*;

#[test]
fn haltspp_16_ends_within_one_pass_per_worker() {
    let dir = tempfile::tempdir().unwrap();
    // an upload interval far beyond the render: only the budgets can end the job in time
    let s = server(&dir.path().join("data"), &["--upload-interval", "3600"]);
    // one sample per pixel and pass (pixelsamples 1)
    let scene = std::fs::read(small_scene(dir.path(), "h", (64, 64), "")).unwrap();
    let (st, job) = post_job(&s, scene, "?filename=h.lxs&haltspp=16");
    assert_eq!(st, 201, "{job}");
    let id = job["id"].as_str().unwrap().to_string();
    let _w1 = worker(&s.url(), 1, &[]);
    let _w2 = worker(&s.url(), 1, &[]);
    // a hang guard only
    let v = wait_job(&s, &id, 600, |v| {
        v["state"] != "queued" && v["state"] != "rendering"
    });
    assert_eq!(v["state"], "done", "{v}");
    let spp = v["spp"].as_f64().unwrap();
    assert!(spp >= 16.0, "{v}");
    assert!(
        spp <= 16.0 + 2.0,
        "spp {spp} overshoots one pass per worker: {v}"
    );
}
