//! The user sampling map across the farm (`/api/v1/jobs/{id}/sampling-map`): a master and a
//! worker on loopback render a 32×16 textured plane with the random sampler (not
//! noise-aware). Bad uploads get JSON errors with their status; after a PUT of an image
//! weighting the left half 9:1, the worker's deltas (kept with `--keep-deltas`; box filter of
//! radius 0.5, so a pixel's weight sum is its sample count) give the left pixels about nine
//! times the samples of the right ones; the map survives a master restart (a fresh worker of
//! the restarted master samples by it too); DELETE returns the workers to uniform sampling.
//! With the metropolis sampler (whose deposits carry no sample counts) a map starving the right
//! half shows in which pixels a delta's chains still deposit: before it nearly every pixel,
//! after it only a few of the right half's, and after DELETE nearly every one again.

mod farm_common;

use farm_common::*;
use luxfarm::imageio::{encode_exr, encode_png, ChannelSet, ExrCompression, ExrImage, LdrImage};
use luxfarm_wire::codec;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

const W: u32 = 32;
const H: u32 = 16;

fn scene() -> Vec<u8> {
    scene_with(r#"Sampler "random" "integer pixelsamples" [4]"#)
}

fn scene_with(sampler: &str) -> Vec<u8> {
    format!(
        r#"LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [-1 1 -0.5 0.5]
Film "fleximage" "integer xresolution" [{W}] "integer yresolution" [{H}]
  "bool write_png" ["false"] "bool write_exr" ["false"] "bool write_resume_flm" ["false"]
PixelFilter "box" "float xwidth" [0.5] "float ywidth" [0.5]
{sampler}
SurfaceIntegrator "path" "integer maxdepth" [2]
WorldBegin
LightSource "infinite" "color L" [1 1 1]
AttributeBegin
  Texture "checks" "color" "checkerboard" "float uscale" [90] "float vscale" [45]
    "color tex1" [0.9 0.9 0.9] "color tex2" [0.05 0.05 0.05]
  Material "matte" "texture Kd" ["checks"]
  Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
    "point P" [-2 -1 0  2 -1 0  2 1 0  -2 1 0] "float uv" [0 0 1 0 1 1 0 1]
AttributeEnd
WorldEnd
"#
    )
    .into_bytes()
}

/// A gray 8-bit PNG of `w` × `h` whose pixel (x, y) is `v(x, y)` (0..=255).
fn png(w: u32, h: u32, v: impl Fn(u32, u32) -> u8) -> Vec<u8> {
    let gray: Vec<f32> = (0..w * h)
        .map(|i| (f32::from(v(i % w, i / w)) + 0.5) / 255.0)
        .collect();
    let img = LdrImage {
        width: w,
        height: h,
        rgb: &vec![[0.0; 3]; gray.len()],
        gray: &gray,
        alpha: &[],
    };
    let mut out = Vec::new();
    encode_png(&mut out, &img, ChannelSet::Y, false).unwrap();
    out
}

/// A float RGB OpenEXR of `w` × `h` with value `v(x, y)` in every channel.
fn exr(w: u32, h: u32, v: impl Fn(u32, u32) -> f32) -> Vec<u8> {
    let rgb: Vec<[f32; 3]> = (0..w * h)
        .map(|i| {
            let x = v(i % w, i / w);
            [x, x, x]
        })
        .collect();
    let img = ExrImage {
        width: w,
        height: h,
        rgb: &rgb,
        gray: &[],
        alpha: &[],
        z: None,
    };
    let mut out = std::io::Cursor::new(Vec::new());
    encode_exr(&mut out, &img, ChannelSet::Rgb, false, ExrCompression::Zip).unwrap();
    out.into_inner()
}

fn nine_to_one() -> Vec<u8> {
    png(W, H, |x, _| if x < W / 2 { 225 } else { 25 })
}

/// PUT of `body` to the job's sampling map: status and JSON body.
fn put(s: &Server, id: &str, body: Vec<u8>) -> (u16, serde_json::Value) {
    let r = http()
        .put(s.api(&format!("/jobs/{id}/sampling-map")))
        .body(body)
        .send()
        .unwrap();
    let status = r.status().as_u16();
    (status, r.json().unwrap_or(serde_json::Value::Null))
}

fn call(s: &Server, method: reqwest::Method, id: &str) -> (u16, serde_json::Value) {
    let r = http()
        .request(method, s.api(&format!("/jobs/{id}/sampling-map")))
        .send()
        .unwrap();
    let status = r.status().as_u16();
    (status, r.json().unwrap_or(serde_json::Value::Null))
}

/// The left/right ratio of a kept delta's sample counts (per-pixel weight sums); none when
/// the delta holds no samples.
fn left_right_ratio(path: &Path) -> Option<f64> {
    let film = codec::decode(&std::fs::read(path).unwrap()).unwrap();
    let counts: Vec<f64> = film.buffer(0, 0).unwrap().chunks(5).map(|p| p[4]).collect();
    let (mut l, mut r) = (0.0, 0.0);
    for (i, c) in counts.iter().enumerate() {
        if (i as u32 % W) < W / 2 {
            l += c;
        } else {
            r += c;
        }
    }
    (l + r > 0.0).then(|| l / r.max(1.0))
}

fn merged(dir: &Path) -> BTreeSet<PathBuf> {
    files_under(dir)
        .into_iter()
        .filter(|p| p.to_string_lossy().ends_with(".merged.lxd"))
        .collect()
}

/// Waits (at most `secs`) for a merged delta in `dir`, not among `old`, whose `measure`
/// (none: the delta holds nothing) `ok` accepts; the measures seen.
fn wait_for(
    dir: &Path,
    old: &BTreeSet<PathBuf>,
    secs: u64,
    measure: impl Fn(&Path) -> Option<f64>,
    ok: impl Fn(f64) -> bool,
) -> (bool, Vec<f64>) {
    let end = Instant::now() + Duration::from_secs(secs);
    let mut seen = Vec::new();
    let mut checked = BTreeSet::new();
    while Instant::now() < end {
        for p in merged(dir).difference(old) {
            if !checked.insert(p.clone()) {
                continue;
            }
            if let Some(m) = measure(p) {
                seen.push(m);
                if ok(m) {
                    return (true, seen);
                }
            }
        }
        std::thread::sleep(Duration::from_millis(200));
    }
    (false, seen)
}

#[test]
fn a_user_map_reaches_the_workers_survives_a_restart_and_clears() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let args = ["--upload-interval", "0.5", "--max-upload", "20000"];
    let s = server(&data, &args);
    let (st, job) = post_job(&s, scene(), "?filename=plane.lxs&haltspp=100000&seed=4");
    assert_eq!(st, 201, "{job}");
    let id = job["id"].as_str().unwrap().to_string();

    // Bad requests, each a JSON error with its status.
    let (st, e) = put(&s, "nosuchjob", nine_to_one());
    assert_eq!((st, e["error"].as_str()), (404, Some("not_found")), "{e}");
    let (st, e) = put(&s, &id, png(W - 1, H, |_, _| 9));
    assert_eq!(st, 422, "{e}");
    let detail = e["detail"].as_str().unwrap();
    assert!(detail.contains("31x16") && detail.contains("32x16"), "{e}");
    let (st, e) = put(&s, &id, png(W, H, |_, _| 0));
    assert_eq!(
        (st, e["error"].as_str()),
        (422, Some("unprocessable")),
        "{e}"
    );
    let (st, e) = put(&s, &id, exr(W, H, |_, _| 0.0));
    assert_eq!(
        (st, e["error"].as_str()),
        (422, Some("unprocessable")),
        "{e}"
    );
    assert!(e["detail"].as_str().unwrap().contains("zero"), "{e}");
    let (st, e) = put(
        &s,
        &id,
        exr(W, H, |x, y| if (x, y) == (3, 2) { -1.0 } else { 1.0 }),
    );
    assert_eq!(st, 422, "{e}");
    assert!(e["detail"].as_str().unwrap().contains("(3, 2)"), "{e}");
    let (st, e) = put(
        &s,
        &id,
        exr(W, H, |x, _| if x == 7 { f32::NAN } else { 1.0 }),
    );
    assert_eq!(st, 422, "{e}");
    let (st, e) = put(&s, &id, b"no image here".to_vec());
    assert_eq!((st, e["error"].as_str()), (400, Some("bad_request")), "{e}");
    let (st, e) = put(&s, &id, vec![7u8; 30_000]);
    assert_eq!(
        (st, e["error"].as_str()),
        (413, Some("payload_too_large")),
        "{e}"
    );
    // Nothing was stored; clearing no map is no error.
    let (st, e) = call(&s, reqwest::Method::DELETE, &id);
    assert_eq!(st, 200, "{e}");
    let (st, e) = call(&s, reqwest::Method::GET, &id);
    assert_eq!((st, e["error"].as_str()), (404, Some("not_found")), "{e}");

    // The 9:1 map.
    let (st, v) = put(&s, &id, nine_to_one());
    assert_eq!(st, 200, "{v}");
    assert_eq!(
        (v["set"].as_bool(), v["applied"].as_bool()),
        (Some(true), Some(true)),
        "{v}"
    );
    let version = v["version"].as_u64().unwrap();
    let (st, got) = call(&s, reqwest::Method::GET, &id);
    assert_eq!(st, 200, "{got}");
    let weights: Vec<f64> = got["weights"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_f64().unwrap())
        .collect();
    assert_eq!(weights.len(), (W * H) as usize);
    assert!((weights[0] / weights[(W - 1) as usize] - 9.0).abs() < 1e-4);
    assert_eq!(got["version"].as_u64(), Some(version));

    // A worker samples by it.
    let keep_a = dir.path().join("kept-a");
    let mut wa = worker(&s.url(), 1, &["--keep-deltas", keep_a.to_str().unwrap()]);
    let (ok, seen) = wait_for(&keep_a, &BTreeSet::new(), 180, left_right_ratio, |r| {
        (r - 9.0).abs() < 1.5
    });
    assert!(ok, "left/right samples of worker A's deltas: {seen:?}");
    eprintln!("worker A, left/right samples per delta: {seen:?}");
    wa.term();
    wa.wait_exit(60).expect("worker A exits");

    // The master restarts; the map is still there, and a new worker samples by it.
    let mut s = s;
    s.proc.term();
    s.proc.wait_exit(120).expect("the master exits");
    let s = server(&data, &args);
    let (st, again) = call(&s, reqwest::Method::GET, &id);
    assert_eq!(st, 200, "{again}");
    assert_eq!(again["weights"], got["weights"]);
    assert_eq!(again["version"].as_u64(), Some(version));
    let keep_b = dir.path().join("kept-b");
    let _wb = worker(&s.url(), 1, &["--keep-deltas", keep_b.to_str().unwrap()]);
    let (ok, seen) = wait_for(&keep_b, &BTreeSet::new(), 180, left_right_ratio, |r| {
        (r - 9.0).abs() < 1.5
    });
    assert!(ok, "left/right samples of worker B's deltas: {seen:?}");

    // Cleared: uniform again.
    let before = merged(&keep_b);
    let (st, v) = call(&s, reqwest::Method::DELETE, &id);
    assert_eq!((st, v["set"].as_bool()), (200, Some(false)), "{v}");
    assert!(v["version"].as_u64().unwrap() > version, "{v}");
    let (st, _) = call(&s, reqwest::Method::GET, &id);
    assert_eq!(st, 404);
    let (ok, seen) = wait_for(&keep_b, &before, 180, left_right_ratio, |r| {
        (r - 1.0).abs() < 0.1
    });
    assert!(ok, "left/right samples after DELETE: {seen:?}");

    // An ended job's map can no longer change.
    let r = http().delete(s.api(&format!("/jobs/{id}"))).send().unwrap();
    assert_eq!(r.status().as_u16(), 200);
    let (st, e) = put(&s, &id, nine_to_one());
    assert_eq!((st, e["error"].as_str()), (409, Some("conflict")), "{e}");
}

/// The share of right-half pixels (the border columns out) a kept delta deposited anything in.
fn right_reached(path: &Path) -> Option<f64> {
    let film = codec::decode(&std::fs::read(path).unwrap()).unwrap();
    let w: Vec<f64> = film.buffer(0, 0)?.chunks(5).map(|p| p[4]).collect();
    if w.iter().sum::<f64>() <= 0.0 {
        return None;
    }
    let right: Vec<f64> = w
        .iter()
        .enumerate()
        .filter(|(i, _)| (*i as u32 % W) >= W / 2 + 2)
        .map(|(_, v)| *v)
        .collect();
    Some(right.iter().filter(|v| **v > 0.0).count() as f64 / right.len() as f64)
}

#[test]
fn metropolis_workers_follow_a_user_map() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &["--upload-interval", "0.5"]);
    let metropolis = r#"Sampler "metropolis" "float largemutationprob" [0.4]"#;
    let (st, job) = post_job(
        &s,
        scene_with(metropolis),
        "?filename=plane.lxs&haltspp=100000&seed=5",
    );
    assert_eq!(st, 201, "{job}");
    let id = job["id"].as_str().unwrap().to_string();
    let keep = dir.path().join("kept");
    let _w = worker(&s.url(), 1, &["--keep-deltas", keep.to_str().unwrap()]);

    // Without a map the chains reach (nearly) every pixel.
    let (ok, seen) = wait_for(&keep, &BTreeSet::new(), 180, right_reached, |r| r > 0.9);
    assert!(ok, "share of right pixels reached before the map: {seen:?}");

    // The right half at a thousandth of the left's density.
    let (st, v) = put(
        &s,
        &id,
        exr(W, H, |x, _| if x < W / 2 { 1.0 } else { 0.001 }),
    );
    assert_eq!(st, 200, "{v}");
    assert_eq!(v["applied"].as_bool(), Some(true), "{v}");
    let before = merged(&keep);
    let (ok, seen) = wait_for(&keep, &before, 180, right_reached, |r| r < 0.25);
    assert!(ok, "share of right pixels reached after the map: {seen:?}");
    eprintln!("share of right pixels reached per delta after the map: {seen:?}");

    // Cleared: (nearly) every pixel again.
    let before = merged(&keep);
    let (st, _) = call(&s, reqwest::Method::DELETE, &id);
    assert_eq!(st, 200);
    let (ok, seen) = wait_for(&keep, &before, 180, right_reached, |r| r > 0.9);
    assert!(ok, "share of right pixels reached after DELETE: {seen:?}");
}
