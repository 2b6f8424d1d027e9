//! Noise-aware sampling across the farm: a master and one worker on loopback render a scene
//! whose left half is a finely textured plane (noisy) and whose right half an emitter seen
//! directly (converged after one sample), with `"bool noiseaware"`. The master builds the
//! sampling map from the merged film (from the spread of each pixel's contributions, which
//! the deltas carry, once it has `convergencestep` spp) in its periodic tick and sends it with
//! its acknowledgements; the worker's kept deltas show its per-pixel sample counts (box
//! filter of radius 0.5: a pixel's weight sum is its sample count). The first delta, rendered
//! before any map can exist, samples every pixel equally (the second usually does too: the
//! map built from the first comes with a later acknowledgement); from the third on, a delta
//! gives the noisy half several times the samples of the converged half.

mod farm_common;

use farm_common::*;
use luxfarm_wire::codec;

const W: u32 = 32;
const H: u32 = 16;

fn scene() -> Vec<u8> {
    format!(
        r#"LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [-1 1 -0.5 0.5]
Film "fleximage" "integer xresolution" [{W}] "integer yresolution" [{H}]
  "float convergencestep" [4] "bool write_png" ["false"] "bool write_exr" ["false"]
  "bool write_resume_flm" ["false"]
PixelFilter "box" "float xwidth" [0.5] "float ywidth" [0.5]
Sampler "random" "integer pixelsamples" [4] "bool noiseaware" ["true"]
SurfaceIntegrator "path" "integer maxdepth" [2]
WorldBegin
LightSource "infinite" "color L" [1 1 1]
AttributeBegin
  Texture "checks" "color" "checkerboard" "float uscale" [60] "float vscale" [60]
    "color tex1" [0.9 0.9 0.9] "color tex2" [0.05 0.05 0.05]
  Material "matte" "texture Kd" ["checks"]
  Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
    "point P" [-2 -1 0  0 -1 0  0 1 0  -2 1 0] "float uv" [0 0 1 0 1 1 0 1]
AttributeEnd
AttributeBegin
  Material "matte" "color Kd" [0 0 0]
  AreaLightSource "area" "color L" [0.5 0.5 0.5]
  Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
    "point P" [0 -1 0  2 -1 0  2 1 0  0 1 0]
AttributeEnd
WorldEnd
"#
    )
    .into_bytes()
}

/// Per-pixel sample counts of a delta (weight sums of group 0's eye buffer).
fn counts(film: &luxfarm::film::Film) -> Vec<f64> {
    film.buffer(0, 0)
        .expect("eye buffer")
        .chunks(5)
        .map(|p| p[4])
        .collect()
}

/// Mean count of the noisy (left) and converged (right) columns, the blurred border out.
fn halves(c: &[f64]) -> (f64, f64) {
    let (mut l, mut r, mut nl, mut nr) = (0.0, 0.0, 0.0, 0.0);
    for (i, v) in c.iter().enumerate() {
        let x = i as u32 % W;
        if x + 2 < W / 2 {
            l += v;
            nl += 1.0;
        } else if x >= W / 2 + 2 {
            r += v;
            nr += 1.0;
        }
    }
    (l / nl, r / nr)
}

#[test]
fn the_workers_sampling_follows_the_masters_map_once_it_arrives() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &["--upload-interval", "0.5"]);
    let (st, job) = post_job(&s, scene(), "?filename=noisy.lxs&haltspp=256&seed=3");
    assert_eq!(st, 201, "{job}");
    let id = job["id"].as_str().unwrap().to_string();
    let keep = dir.path().join("kept");
    let mut workers = [worker(
        &s.url(),
        1,
        &["--keep-deltas", keep.to_str().unwrap()],
    )];
    let v = wait_job(&s, &id, 600, |v| {
        v["state"] != "queued" && v["state"] != "rendering"
    });
    assert_eq!(v["state"], "done", "{v}");
    stop_workers(&mut workers);
    let mut kept: Vec<_> = files_under(&keep)
        .into_iter()
        .filter(|p| p.to_string_lossy().ends_with(".merged.lxd"))
        .collect();
    // one lease: the names sort by sequence number
    kept.sort();
    let deltas: Vec<Vec<f64>> = kept
        .iter()
        .map(|p| counts(&codec::decode(&std::fs::read(p).unwrap()).unwrap()))
        .filter(|c| c.iter().sum::<f64>() > 0.0)
        .collect();
    let summary: Vec<String> = deltas
        .iter()
        .map(|c| {
            let (l, r) = halves(c);
            let min = c.iter().cloned().fold(f64::INFINITY, f64::min);
            let max = c.iter().cloned().fold(0.0, f64::max);
            format!("left {l:.1} right {r:.1} min {min} max {max}")
        })
        .collect();
    eprintln!("per-delta sample counts: {summary:#?}");
    assert!(deltas.len() >= 3, "{} deltas with samples", deltas.len());
    // Before the map: every pixel sampled alike (whole passes of 4 samples per pixel). A
    // camera sample whose film position rounds (f32) onto the next pixel's edge moves one
    // count to a neighbour now and then, so "alike" is within one sample.
    for (k, c) in deltas.iter().take(1).enumerate() {
        let mut sorted = c.clone();
        sorted.sort_by(f64::total_cmp);
        let median = sorted[sorted.len() / 2];
        assert!(
            median >= 4.0 && median % 4.0 == 0.0,
            "delta {k}: {summary:#?}"
        );
        assert!(
            c.iter().all(|v| (v - median).abs() <= 1.0),
            "delta {k} is not uniform before any map: {summary:#?}"
        );
        let (l, r) = halves(c);
        assert!((l / r - 1.0).abs() < 0.02, "delta {k}: {summary:#?}");
    }
    // After it: the noisy half takes several times the samples of the converged half.
    let ratios: Vec<f64> = deltas[2..]
        .iter()
        .map(|c| {
            let (l, r) = halves(c);
            l / r
        })
        .collect();
    assert!(
        ratios.iter().any(|r| *r > 3.0),
        "noisy/converged samples per pixel after the map: {ratios:?}"
    );
}
