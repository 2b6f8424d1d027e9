//! Farm REST outputs with a render (the shared Cornell box): tonemapping query parameters of preview.png and image.png
//! (the picture changes in the right direction, bad values are JSON 400s naming the parameter,
//! the ETag follows the setting and answers 304), the job's tonemapping settings, the OpenAPI
//! document of the parameters, and the master's per-worker samples per second.

mod farm_common;

use farm_common::*;
use serde_json::Value;

/// GET with optional If-None-Match: (status, ETag, body).
fn get(url: &str, if_none_match: Option<&str>) -> (u16, String, Vec<u8>) {
    let mut req = http().get(url);
    if let Some(tag) = if_none_match {
        req = req.header("If-None-Match", tag);
    }
    let r = req.send().expect("GET");
    let status = r.status().as_u16();
    let etag = r
        .headers()
        .get("etag")
        .and_then(|v| v.to_str().ok())
        .unwrap_or("")
        .to_string();
    (status, etag, r.bytes().expect("body").to_vec())
}

/// Mean RGB value in [0, 1] of a PNG (decoded by the core's image loader).
fn mean_brightness(png: &[u8]) -> f64 {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("p.png");
    std::fs::write(&path, png).expect("write png");
    let img = luxfarm::texture::image_io::load(&path).expect("a PNG");
    let sum: f64 = img
        .texels
        .iter()
        .map(|t| f64::from(t[0] + t[1] + t[2]) / 3.0)
        .sum();
    sum / img.texels.len() as f64
}

/// `samples_per_sec` of every worker from the gRPC Jobs service.
fn grpc_worker_rates(url: &str) -> Vec<f64> {
    let rt = tokio::runtime::Runtime::new().expect("tokio runtime");
    rt.block_on(async {
        let ch = luxfarm_proto::connect::channel(url, None, None).expect("channel");
        let mut c = luxfarm_proto::connect::jobs_client(ch);
        let r = c
            .list_workers(luxfarm_proto::ListWorkersRequest {})
            .await
            .expect("ListWorkers");
        r.into_inner()
            .workers
            .iter()
            .map(|w| w.samples_per_sec)
            .collect()
    })
}

fn assert_bad_request(url: &str, names: &str) {
    let r = http().get(url).send().expect("GET");
    assert_eq!(r.status().as_u16(), 400, "{url}");
    let body: Value = r.json().expect("a JSON error body");
    assert_eq!(body["error"], "bad_request", "{body}");
    let detail = body["detail"].as_str().unwrap_or("");
    assert!(detail.contains(names), "{url}: {detail:?} lacks {names:?}");
}

#[test]
fn preview_tonemapping_query_etag_and_worker_rate() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &["--upload-interval", "0.5"]);
    let _w = worker(&s.url(), 1, &[]);
    let scene = std::fs::read(shared().join("scenes/cornell/cornell.lxs")).expect("cornell.lxs");
    let (st, job) = post_job(&s, scene, "?filename=cornell.lxs&haltspp=1000000");
    assert_eq!(st, 201, "{job}");
    let id = job["id"].as_str().unwrap().to_string();
    let job_url = |path: &str| s.api(&format!("/jobs/{id}{path}"));

    // While rendering, the master reports the worker's samples per second from its uploads.
    let v = wait_job(&s, &id, 180, |v| v["merged_deltas"].as_u64() >= Some(3));
    assert!(v["merged_deltas"].as_u64() >= Some(3), "{v}");
    let mut rate = 0.0;
    for _ in 0..100 {
        let ws = get_json(&s.api("/workers"));
        rate = ws[0]["samples_per_sec"].as_f64().unwrap_or(0.0);
        if rate > 0.0 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(200));
    }
    assert!(
        rate > 0.0,
        "no worker samples/s: {}",
        get_json(&s.api("/workers"))
    );
    // The worker's build names the instruction-set level its render core runs at.
    let ws = get_json(&s.api("/workers"));
    let build = ws[0]["build"].as_str().unwrap_or_default().to_string();
    assert!(
        build.starts_with("luxfarm ") && build.ends_with(luxfarm::isa::build_name()),
        "{ws}"
    );
    // The same number over gRPC (ListWorkers' WorkerInfo).
    let grpc_rate = grpc_worker_rates(&s.url());
    assert!(
        grpc_rate.iter().any(|&r| r > 0.0),
        "gRPC WorkerInfo.samples_per_sec: {grpc_rate:?}"
    );

    // The scene's settings (autolinear by default) and LuxRender's defaults.
    let tm = get_json(&job_url("/tonemap"));
    assert_eq!(tm["scene"]["kernel"], "autolinear", "{tm}");
    assert_eq!(tm["defaults"]["linear_sensitivity"], 50.0, "{tm}");
    let fstop = tm["defaults"]["linear_fstop"].as_f64().unwrap_or(0.0);
    assert!((fstop - 2.8).abs() < 1e-6, "{tm}");
    assert_eq!(tm["defaults"]["reinhard_burn"], 6.0, "{tm}");

    // Stop the render so the film (and so every ETag) stays put.
    let r = http().delete(job_url("")).send().unwrap();
    assert_eq!(r.status().as_u16(), 200);
    let v = wait_job(&s, &id, 60, |v| v["state"] == "cancelled");
    assert_eq!(v["state"], "cancelled", "{v}");

    let (st, default_tag, default_png) = get(&job_url("/preview.png"), None);
    assert_eq!(st, 200);
    let base = mean_brightness(&default_png);
    let bright_q = "?kernel=linear&linear_exposure=10000";
    let (st, bright_tag, bright_png) = get(&job_url(&format!("/preview.png{bright_q}")), None);
    assert_eq!(st, 200);
    let (st, _, dark_png) = get(
        &job_url("/preview.png?kernel=linear&linear_exposure=0.000001"),
        None,
    );
    assert_eq!(st, 200);
    let (bright, dark) = (mean_brightness(&bright_png), mean_brightness(&dark_png));
    assert!(
        bright > base + 0.05 && dark < base - 0.05,
        "mean brightness: default {base}, exposure 1e4 {bright}, exposure 1e-6 {dark}"
    );
    assert_ne!(bright_tag, default_tag);
    // A lower output gamma darkens the same kernel.
    let (_, _, gamma_png) = get(&job_url(&format!("/preview.png{bright_q}&gamma=1")), None);
    let (_, _, mid_png) = get(&job_url("/preview.png?kernel=reinhard"), None);
    let (_, _, mid_g1) = get(&job_url("/preview.png?kernel=reinhard&gamma=1"), None);
    assert!(mean_brightness(&gamma_png) <= bright);
    assert!(mean_brightness(&mid_g1) < mean_brightness(&mid_png));

    // ETags: the same request revalidates to an empty 304, another setting is a new ETag.
    let (st, tag2, body) = get(
        &job_url(&format!("/preview.png{bright_q}")),
        Some(&bright_tag),
    );
    assert_eq!((st, body.len()), (304, 0));
    assert_eq!(tag2, bright_tag);
    let other_q = "?kernel=linear&linear_exposure=20000";
    let (st, other_tag, body) = get(
        &job_url(&format!("/preview.png{other_q}")),
        Some(&bright_tag),
    );
    assert_eq!(st, 200);
    assert!(!body.is_empty());
    assert_ne!(other_tag, bright_tag);
    let (st, _, _) = get(&job_url("/preview.png"), Some(&default_tag));
    assert_eq!(st, 304);

    // image.png takes the same parameters (full size).
    let (st, _, full) = get(&job_url(&format!("/image.png{bright_q}")), None);
    assert_eq!(st, 200);
    let (_, _, full_default) = get(&job_url("/image.png"), None);
    assert!(mean_brightness(&full) > mean_brightness(&full_default) + 0.05);

    // Bad values: JSON 400 naming the parameter.
    assert_bad_request(&job_url("/preview.png?kernel=filmic"), "kernel");
    assert_bad_request(
        &job_url("/preview.png?linear_exposure=-1"),
        "linear_exposure",
    );
    assert_bad_request(&job_url("/preview.png?linear_fstop=NaN"), "linear_fstop");
    assert_bad_request(&job_url("/preview.png?reinhard_burn=inf"), "reinhard_burn");
    assert_bad_request(&job_url("/preview.png?gamma=abc"), "gamma");
    assert_bad_request(&job_url("/preview.png?max_size=0"), "max_size");
    assert_bad_request(&job_url("/preview.png?exposure=2"), "exposure");
    assert_bad_request(
        &job_url("/preview.png?kernel=reinhard&linear_exposure=2"),
        "linear_exposure",
    );
    assert_bad_request(
        &job_url("/image.png?kernel=linear&linear_gamma=100"),
        "linear_gamma",
    );

    // The OpenAPI document lists the parameters.
    let doc = get_json(&s.api("/openapi.json"));
    let params = doc["paths"]["/api/v1/jobs/{id}/preview.png"]["get"]["parameters"]
        .as_array()
        .cloned()
        .unwrap_or_default();
    let names: Vec<&str> = params.iter().filter_map(|p| p["name"].as_str()).collect();
    for want in [
        "kernel",
        "linear_exposure",
        "reinhard_burn",
        "contrast_ywa",
        "gamma",
    ] {
        assert!(names.contains(&want), "{want} not in {names:?}");
    }
    assert!(doc["paths"]["/api/v1/jobs/{id}/tonemap"]["get"].is_object());
}
