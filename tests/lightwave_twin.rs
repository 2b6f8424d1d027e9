//! A LightWave scene of our own (`tests/data/lightwave/cube_sun.lws`: the sample cube turned
//! and moved, a coloured distant light, a camera) and its hand-written .lxs twin
//! (`cube_sun.lxs`) render the same image within noise; the twin with the heading's sign
//! left unconverted does not, so the comparison can tell a wrong conversion.

mod lightwave_util;
mod render_util;

use lightwave_util::*;
use luxfarm::lxs::{parse_str, ParseOptions, SceneDescription};
use luxfarm::render::SessionOptions;
use render_util::{block_means, render, rmse};
use std::path::Path;

const PASSES: u32 = 16;

fn blocks(desc: &SceneDescription, base: &Path, stream: u64) -> Vec<f64> {
    let opts = SessionOptions {
        threads: 2,
        seed: 7,
        stream,
    };
    block_means(&render(desc, base, opts, PASSES), 4)
}

fn twin(text: &str) -> SceneDescription {
    let path = data().join("cube_sun.lxs");
    let mut d = parse_str(text, &path.to_string_lossy(), &ParseOptions::default()).unwrap();
    shrink(&mut d, 32, 24);
    d
}

#[test]
fn cube_under_a_distant_light_matches_its_lxs_twin() {
    // the scene loads its object from Objects/ beside it, as LightWave content does
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("Objects")).unwrap();
    std::fs::copy(
        samples().join("LWS/simple_cube.lwo"),
        dir.path().join("Objects/simple_cube.lwo"),
    )
    .unwrap();
    let scene = dir.path().join("cube_sun.lws");
    std::fs::copy(data().join("cube_sun.lws"), &scene).unwrap();
    let mut lw = load_at(&scene, Some(0));
    shrink(&mut lw, 32, 24);

    let text = std::fs::read_to_string(data().join("cube_sun.lxs")).unwrap();
    let lxs = twin(&text);

    let a = blocks(&lw, dir.path(), 0);
    let a2 = blocks(&lw, dir.path(), 1);
    let b = blocks(&lxs, &data(), 2);
    let noise = rmse(&a, &a2);
    let diff = rmse(&a, &b);
    let mean = a.iter().sum::<f64>() / a.len() as f64;
    let max = a.iter().cloned().fold(0.0, f64::max);
    assert!(
        max > 2.0 * mean && mean > 0.0,
        "the cube is lit: mean {mean}, max {max}"
    );
    assert!(
        diff <= 1.6 * noise + 0.01 * mean,
        "difference {diff} vs noise {noise} (mean {mean})"
    );

    // The heading taken over without the mirror's sign change turns the cube the other way.
    let wrong = twin(&text.replace("Rotate -30 0 0 1", "Rotate 30 0 0 1"));
    let w = blocks(&wrong, &data(), 2);
    let wrong_diff = rmse(&a, &w);
    assert!(
        wrong_diff > 3.0 * (1.6 * noise + 0.01 * mean),
        "a wrong heading is told apart: {wrong_diff} vs noise {noise}"
    );
}
