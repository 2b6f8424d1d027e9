//! cornell.lxs (analytic spheres) and cornell-mesh.lxs (tessellated) give the same image
//! within noise, and the Cornell box scaled by 1e-4 and 1e5 renders like the original (no
//! acne, no light leaks: offsets follow error bounds, not a fixed epsilon).
//!
//! Reduced to 64×64 pixels and 8 spp (debug builds are slow); "within noise" is calibrated
//! per test: the difference between two scenes must stay close to the difference between two
//! independent renders (other stream) of the same scene, compared on 8×8 block means of Y.

mod render_util;

use luxfarm::lxs::SceneDescription;
use luxfarm::render::SessionOptions;
use render_util::*;
use std::path::Path;

const RES: u32 = 64;
const PASSES: u32 = 8;

fn load(rel: &str) -> (SceneDescription, std::path::PathBuf) {
    let path = scene_path(rel);
    let text = with_resolution(&std::fs::read_to_string(&path).unwrap(), RES);
    (parse_text(&text, &path), path)
}

fn blocks(desc: &SceneDescription, base: &Path, stream: u64) -> Vec<f64> {
    let f = render(
        desc,
        base,
        SessionOptions {
            threads: 2,
            seed: 11,
            stream,
        },
        PASSES,
    );
    block_means(&f, 8)
}

#[test]
fn analytic_and_mesh_spheres_agree() {
    let (a, pa) = load("cornell/cornell.lxs");
    let (m, pm) = load("cornell/cornell-mesh.lxs");
    let base_a = pa.parent().unwrap();
    let ba = blocks(&a, base_a, 0);
    let ba2 = blocks(&a, base_a, 1);
    let bm = blocks(&m, pm.parent().unwrap(), 2);
    assert_within_noise(&ba, &ba2, &bm, "cornell-mesh vs cornell");
}

/// The Cornell box with world and camera scaled by `s` (eye, target and hither too).
fn scaled(s: f64) -> (SceneDescription, std::path::PathBuf) {
    let path = scene_path("cornell/cornell.lxs");
    let text = with_resolution(&std::fs::read_to_string(&path).unwrap(), RES);
    let mut out = String::new();
    for line in text.lines() {
        if let Some(rest) = line.strip_prefix("LookAt ") {
            let v: Vec<f64> = rest
                .split_whitespace()
                .map(|t| t.parse().unwrap())
                .collect();
            let e: Vec<String> = v[..6].iter().map(|x| format!("{:e}", x * s)).collect();
            let up: Vec<String> = v[6..].iter().map(|x| x.to_string()).collect();
            out.push_str(&format!("LookAt {} {}\n", e.join(" "), up.join(" ")));
        } else if line.starts_with("Camera ") {
            out.push_str(&format!("{line} \"float hither\" [{:e}]\n", 1e-3 * s));
        } else if line.starts_with("WorldBegin") {
            out.push_str(&format!("WorldBegin\nScale {s:e} {s:e} {s:e}\n"));
        } else {
            out.push_str(line);
            out.push('\n');
        }
    }
    (parse_text(&out, &path), path)
}

#[test]
fn scaled_cornell_boxes_render_the_same() {
    let (a, pa) = load("cornell/cornell.lxs");
    let base = pa.parent().unwrap();
    let ba = blocks(&a, base, 0);
    let ba2 = blocks(&a, base, 1);
    for s in [1e-4, 1e5] {
        let (d, p) = scaled(s);
        let bs = blocks(&d, p.parent().unwrap(), 2);
        assert_within_noise(&ba, &ba2, &bs, &format!("scale {s:e}"));
    }
}
