//! The speed/accuracy trade of a running job over REST, on loopback: a master and a worker
//! render a small scene with `haltthreshold`; the job's view carries an error history (the
//! film's relative error and the convergence test's failing fraction against time and spp)
//! that grows, with a projection to the threshold; `/trade?target=` projects the relative
//! error to a target (finite once the fit has enough points) and refuses bad targets with a
//! JSON 400; `/convergence.png` serves the last convergence map while the job renders and a
//! JSON 404 once it ended.

mod farm_common;

use farm_common::*;
use serde_json::Value;

fn history(v: &Value) -> Vec<Value> {
    v["trade"]["history"]
        .as_array()
        .cloned()
        .unwrap_or_default()
}

fn is_finite_number(v: &Value) -> bool {
    v.as_f64().is_some_and(f64::is_finite)
}

#[test]
fn a_running_job_shows_its_error_history_and_projection() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &["--upload-interval", "0.5"]);
    // A threshold no small render reaches soon (no failing pixel at all): the job renders on
    // while the history grows.
    let scene = small_scene(
        dir.path(),
        "t",
        (96, 96),
        "\"float haltthreshold\" [0.00001] \"float convergencestep\" [4]",
    );
    let (st, job) = post_job(&s, std::fs::read(scene).unwrap(), "?filename=t.lxs");
    assert_eq!(st, 201, "{job}");
    assert_eq!(job["trade"]["estimate"], "relative_error");
    assert_eq!(history(&job).len(), 0, "{job}");
    assert_eq!(
        job["trade"]["threshold_projection"]["status"],
        "not_enough_data"
    );
    let id = job["id"].as_str().unwrap().to_string();
    let _w = worker(&s.url(), 1, &[]);

    // The history grows (the waits are hang guards only).
    let first = wait_job(&s, &id, 300, |v| history(v).len() >= 2);
    let n0 = history(&first).len();
    assert!(n0 >= 2, "no history: {first}");
    let trade = |target: &str| get_json(&s.api(&format!("/jobs/{id}/trade?target={target}")));
    let t = wait_view(&s, &format!("/jobs/{id}/trade?target=0.0001"), 300, |t| {
        history(&serde_json::json!({ "trade": t })).len() >= n0 + 4
            && t["target_projection"]["status"] == "projected"
    });
    let h = history(&serde_json::json!({ "trade": &t }));
    assert!(h.len() > n0, "the history did not grow past {n0}: {t}");
    for w in h.windows(2) {
        assert!(w[0]["secs"].as_f64() <= w[1]["secs"].as_f64(), "{h:?}");
        assert!(w[0]["spp"].as_f64() < w[1]["spp"].as_f64(), "{h:?}");
    }
    for p in &h {
        assert!(
            is_finite_number(&p["estimate"]) && p["estimate"].as_f64() > Some(0.0),
            "{p}"
        );
        let f = p["failing"].as_f64().unwrap_or(0.0);
        assert!((0.0..=1.0).contains(&f), "{p}");
    }
    // The relative error falls: the last point is below the first.
    assert!(
        h.last().unwrap()["estimate"].as_f64() < h[0]["estimate"].as_f64(),
        "{h:?}"
    );
    let p = &t["target_projection"];
    assert_eq!(p["status"], "projected", "{t}");
    assert_eq!(p["metric"], "relative_error", "{p}");
    let at = p["at_secs"].as_f64().unwrap();
    let last = h.last().unwrap()["secs"].as_f64().unwrap();
    assert!(at.is_finite() && at >= last, "{p}");
    assert!(is_finite_number(&p["remaining_secs"]), "{p}");
    let exponent = p["fit"]["exponent"].as_f64().unwrap();
    assert!(exponent < 0.0, "{p}");
    eprintln!("trade after {} points: {p}", h.len());
    // The projection to haltthreshold is there, on the failing fraction, never NaN.
    let tp = &t["threshold_projection"];
    assert_eq!(tp["metric"], "failing_fraction", "{t}");
    assert_eq!(tp["target"], 0.00001f32 as f64, "{tp}");
    let statuses = [
        "projected",
        "reached",
        "not_enough_data",
        "no_trend",
        "noisy",
        "unreachable",
    ];
    assert!(statuses.iter().any(|s| tp["status"] == *s), "{tp}");
    // The job's own view carries the same history.
    let v = get_json(&s.api(&format!("/jobs/{id}")));
    assert!(history(&v).len() >= h.len(), "{v}");

    // A target above the latest estimate is reached already.
    let t = trade("10");
    assert_eq!(t["target_projection"]["status"], "reached", "{t}");
    assert_eq!(t["target_projection"]["remaining_secs"], 0.0, "{t}");
    for bad in ["11", "0", "-1", "abc", "NaN"] {
        let r = http()
            .get(s.api(&format!("/jobs/{id}/trade?target={bad}")))
            .send()
            .unwrap();
        assert_eq!(r.status(), 400, "target {bad}");
        let body: Value = r.json().unwrap();
        assert_eq!(body["error"], "bad_request", "{body}");
    }
    let r = http()
        .get(s.api(&format!("/jobs/{id}/trade?nope=1")))
        .send()
        .unwrap();
    assert_eq!(r.status(), 400);
    let r = http().get(s.api("/jobs/nope/trade")).send().unwrap();
    assert_eq!(r.status(), 404);
    assert_eq!(r.json::<Value>().unwrap()["error"], "not_found");

    // The convergence map: a PNG the size of the film (or of max_size).
    let r = http()
        .get(s.api(&format!("/jobs/{id}/convergence.png")))
        .send()
        .unwrap();
    assert_eq!(r.status(), 200);
    assert_eq!(r.headers()["content-type"], "image/png");
    let png = r.bytes().unwrap();
    assert_eq!(&png[1..4], b"PNG");
    // IHDR width and height, big endian, at bytes 16..24
    let dims = |b: &[u8]| {
        (
            u32::from_be_bytes([b[16], b[17], b[18], b[19]]),
            u32::from_be_bytes([b[20], b[21], b[22], b[23]]),
        )
    };
    assert_eq!(dims(&png), (96, 96));
    let small = http()
        .get(s.api(&format!("/jobs/{id}/convergence.png?max_size=16")))
        .send()
        .unwrap()
        .bytes()
        .unwrap();
    assert_eq!(dims(&small), (16, 16));
    // a job still rendering: the halt did not end it meanwhile
    assert_eq!(
        get_json(&s.api(&format!("/jobs/{id}")))["state"],
        "rendering"
    );
    let r = http()
        .get(s.api(&format!("/jobs/{id}/convergence.png?max_size=0")))
        .send()
        .unwrap();
    assert_eq!(r.status(), 400);

    // Once the job ended there is no map to show.
    let r = http().delete(s.api(&format!("/jobs/{id}"))).send().unwrap();
    assert_eq!(r.status(), 200);
    let r = http()
        .get(s.api(&format!("/jobs/{id}/convergence.png")))
        .send()
        .unwrap();
    assert_eq!(r.status(), 404);
    assert_eq!(r.json::<Value>().unwrap()["error"], "not_found");
}
