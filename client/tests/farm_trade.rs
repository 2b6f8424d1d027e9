//! The speed/accuracy trade of a job over REST, on loopback: a master and a worker render a
//! small scene with `haltthreshold` until the threshold holds. While it renders the job's view
//! carries an error history (the film's relative error and the convergence test's failing
//! fraction against time and spp) and `/convergence.png` serves the last convergence map.
//! Once it is done the saved history (`/trade`) has grown, the projection to the threshold
//! says it was reached, a typed target relative error gets a finite projected time, bad
//! targets are JSON 400s, the map a JSON 404; after a master restart the history is the same.

mod farm_common;

use farm_common::*;
use serde_json::Value;

fn history(trade: &Value) -> Vec<Value> {
    trade["history"].as_array().cloned().unwrap_or_default()
}

fn is_finite_number(v: &Value) -> bool {
    v.as_f64().is_some_and(f64::is_finite)
}

/// The least-squares slope of ln(estimate) against ln(secs) over the last 24 points of a
/// history (the points the server's projection fits).
fn recent_log_slope(h: &[Value]) -> f64 {
    let xy: Vec<(f64, f64)> = h
        .iter()
        .filter_map(|p| Some((p["secs"].as_f64()?, p["estimate"].as_f64()?)))
        .filter(|(t, v)| *t > 0.0 && *v > 0.0)
        .map(|(t, v)| (t.ln(), v.ln()))
        .collect();
    let xy = &xy[xy.len().saturating_sub(24)..];
    let n = xy.len() as f64;
    let mx = xy.iter().map(|p| p.0).sum::<f64>() / n;
    let my = xy.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = xy.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = xy.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    sxy / sxx
}

/// IHDR width and height of a PNG.
fn png_size(b: &[u8]) -> (u32, u32) {
    assert_eq!(b.get(1..4), Some(&b"PNG"[..]), "not a PNG");
    (
        u32::from_be_bytes([b[16], b[17], b[18], b[19]]),
        u32::from_be_bytes([b[20], b[21], b[22], b[23]]),
    )
}

#[test]
fn a_jobs_error_history_grows_projects_and_survives_a_restart() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let mut s = server(&data, &["--upload-interval", "0.5"]);
    let scene = small_scene(
        dir.path(),
        "t",
        (96, 96),
        "\"float haltthreshold\" [0.00001] \"float convergencestep\" [4]",
    );
    let (st, job) = post_job(&s, std::fs::read(scene).unwrap(), "?filename=t.lxs");
    assert_eq!(st, 201, "{job}");
    assert_eq!(job["trade"]["estimate"], "relative_error");
    assert_eq!(history(&job["trade"]).len(), 0, "{job}");
    assert_eq!(
        job["trade"]["threshold_projection"]["status"],
        "not_enough_data"
    );
    let id = job["id"].as_str().unwrap().to_string();
    let w = worker(&s.url(), 1, &[]);

    // While it renders: a history in the job's view, and the convergence map (hang guards
    // only; the job renders for about a hundred spp more).
    let early = wait_job(&s, &id, 300, |v| history(&v["trade"]).len() >= 2);
    assert_eq!(early["state"], "rendering", "{early}");
    let n0 = history(&early["trade"]).len();
    let r = http()
        .get(s.api(&format!("/jobs/{id}/convergence.png")))
        .send()
        .unwrap();
    assert_eq!(r.status(), 200);
    assert_eq!(r.headers()["content-type"], "image/png");
    assert_eq!(png_size(&r.bytes().unwrap()), (96, 96));
    let small = http()
        .get(s.api(&format!("/jobs/{id}/convergence.png?max_size=16")))
        .send()
        .unwrap()
        .bytes()
        .unwrap();
    assert_eq!(png_size(&small), (16, 16));
    let r = http()
        .get(s.api(&format!("/jobs/{id}/convergence.png?max_size=0")))
        .send()
        .unwrap();
    assert_eq!(r.status(), 400);

    // The threshold holds; the saved history has grown and says so.
    let done = wait_job(&s, &id, 600, |v| v["state"] != "rendering");
    assert_eq!(done["state"], "done", "{done}");
    let trade = |target: &str| get_json(&s.api(&format!("/jobs/{id}/trade?target={target}")));
    let t = trade("0.01");
    let h = history(&t);
    assert!(h.len() > n0 + 3, "the history did not grow past {n0}: {t}");
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
    let (e0, e1) = (
        h[0]["estimate"].as_f64(),
        h[h.len() - 1]["estimate"].as_f64(),
    );
    assert!(e1 < e0, "the relative error did not fall: {h:?}");
    let tp = &t["threshold_projection"];
    assert_eq!(tp["metric"], "failing_fraction", "{t}");
    assert_eq!(tp["status"], "reached", "{tp}");
    assert!(is_finite_number(&tp["at_secs"]), "{tp}");
    let p = &t["target_projection"];
    assert_eq!(p["metric"], "relative_error", "{p}");
    // The projection fits the most recent points. A firefly late in the render can make the
    // relative error rise over them (seen in CI: 1.95 → 2.82 → 3.81 within the last 24
    // points); then the honest answer is "no_trend". The test checks the server's choice
    // against its own least-squares slope of the recent points, and the projected time when
    // the error falls.
    let slope = recent_log_slope(&h);
    if slope >= -0.02 {
        assert_eq!(p["status"], "no_trend", "slope {slope}: {t}");
    } else {
        assert!(
            p["status"] == "projected" || p["status"] == "noisy",
            "slope {slope}: {t}"
        );
    }
    if p["status"] == "projected" {
        let last = h[h.len() - 1]["secs"].as_f64().unwrap();
        let at = p["at_secs"].as_f64().unwrap();
        assert!(at.is_finite() && at > last, "{p}");
        assert!(is_finite_number(&p["remaining_secs"]), "{p}");
        assert!(p["fit"]["exponent"].as_f64() < Some(0.0), "{p}");
    }
    eprintln!("{} points; to relative error 0.01: {p}", h.len());

    // A target above the latest estimate is reached; bad targets are JSON 400s.
    let t10 = trade("10");
    assert_eq!(t10["target_projection"]["status"], "reached", "{t10}");
    assert_eq!(t10["target_projection"]["remaining_secs"], 0.0, "{t10}");
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
    // No map once the job ended.
    let r = http()
        .get(s.api(&format!("/jobs/{id}/convergence.png")))
        .send()
        .unwrap();
    assert_eq!(r.status(), 404);
    assert_eq!(r.json::<Value>().unwrap()["error"], "not_found");

    // A restarted master has the same history.
    drop(w);
    s.proc.term();
    assert!(s.proc.wait_exit(60).is_some(), "the master did not stop");
    let s2 = server(&data, &[]);
    let again = get_json(&s2.api(&format!("/jobs/{id}/trade?target=0.01")));
    assert_eq!(history(&again), h, "{again}");
    assert_eq!(again["target_projection"], t["target_projection"]);
}
