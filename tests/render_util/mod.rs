//! Helpers shared by the render integration tests: locating ../shared, rendering a scene
//! description to a film, and comparing films.

#![allow(dead_code)]

use luxfarm::film::{Film, FilmParams};
use luxfarm::lxs::{
    parse_file, parse_str, Entity, Loc, ParamSet, ParamValue, ParseOptions, SceneDescription,
};
use luxfarm::render::{Session, SessionOptions};
use std::path::{Path, PathBuf};

/// The shared material directory: `../shared` from the repository root, else /work/shared.
pub fn shared_dir() -> PathBuf {
    let local = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared"));
    if local.join("scenes").is_dir() {
        local
    } else {
        PathBuf::from("/work/shared")
    }
}

pub fn scene_path(rel: &str) -> PathBuf {
    shared_dir().join("scenes").join(rel)
}

pub fn parse(path: &Path) -> SceneDescription {
    parse_file(path, &ParseOptions::default()).expect("scene parses")
}

/// Parses scene text as if it were the file `path` (relative names resolve beside it).
pub fn parse_text(text: &str, path: &Path) -> SceneDescription {
    parse_str(text, &path.to_string_lossy(), &ParseOptions::default()).expect("scene parses")
}

/// Renders `passes` passes of the scene with the given options.
pub fn render(desc: &SceneDescription, base: &Path, opts: SessionOptions, passes: u32) -> Film {
    let mut s = Session::new(desc, base, opts).expect("session builds");
    for _ in 0..passes {
        assert!(s.render_pass().complete);
    }
    s.take_film()
}

/// Per-pixel weight-normalised XYZ of group 0 (0 where no weight).
pub fn normalized_xyz(f: &Film) -> Vec<[f64; 3]> {
    let mut v = Vec::with_capacity(f.pixel_count());
    for y in 0..f.height() {
        for x in 0..f.width() {
            let p = f.pixel(0, 0, x, y).expect("pixel in range");
            v.push(if p[4] != 0.0 {
                [p[0] / p[4], p[1] / p[4], p[2] / p[4]]
            } else {
                [0.0; 3]
            });
        }
    }
    v
}

/// RMS over the weight-normalised X, Y, Z of every pixel (LuxRender's regression metric).
pub fn rms(a: &Film, b: &Film) -> f64 {
    let (a, b) = (normalized_xyz(a), normalized_xyz(b));
    assert_eq!(a.len(), b.len());
    let mut se = 0.0;
    for (p, q) in a.iter().zip(&b) {
        for c in 0..3 {
            se += (p[c] - q[c]).powi(2);
        }
    }
    (se / (3 * a.len()).max(1) as f64).sqrt()
}

/// Y averaged over `block`×`block` pixel blocks: a low-noise view for "same image within
/// noise" comparisons.
pub fn block_means(f: &Film, block: u32) -> Vec<f64> {
    let xyz = normalized_xyz(f);
    let (bw, bh) = (f.width() / block, f.height() / block);
    let mut out = vec![0.0; (bw * bh) as usize];
    for y in 0..bh * block {
        for x in 0..bw * block {
            let i = ((y / block) * bw + x / block) as usize;
            out[i] += xyz[(y * f.width() + x) as usize][1] / f64::from(block * block);
        }
    }
    out
}

/// Y averaged over `block`-pixel blocks of a square film's rows 0..size-1, the last block row
/// one row short: the blocks LuxCore's film is compared with, one row down (its film lies one
/// row below the scene's pixel centres; see scripts/luxcore_common.py). Rows from the top.
pub fn luxcore_blocks(f: &Film, block: u32) -> Vec<f64> {
    let xyz = normalized_xyz(f);
    let size = f.width();
    let n = size / block;
    let mut out = vec![0.0; (n * n) as usize];
    for by in 0..n {
        let rows = by * block..((by + 1) * block).min(size - 1);
        let count = f64::from(rows.len() as u32 * block);
        for y in rows {
            for x in 0..n * block {
                out[(by * n + x / block) as usize] += xyz[(y * size + x) as usize][1] / count;
            }
        }
    }
    out
}

/// Asserts that every block LuxCore renders lit is within 3 % of LuxCore's figure and every
/// block it renders dark is dark here too (at most 1e-6 of LuxCore's brightest), printing
/// each pair first.
pub fn assert_blocks_match_luxcore(what: &str, ours: &[f64], luxcore: &[f64]) {
    let max = luxcore.iter().cloned().fold(0.0, f64::max);
    for (i, (a, b)) in ours.iter().zip(luxcore).enumerate() {
        eprintln!(
            "{what} block {i}: luxfarm {a:.5} LuxCore {b:.5} ({:+.2} %)",
            if *b > 0.0 { 100.0 * (a / b - 1.0) } else { 0.0 }
        );
    }
    for (i, (a, b)) in ours.iter().zip(luxcore).enumerate() {
        if *b == 0.0 {
            assert!(
                *a <= 1e-6 * max,
                "{what} block {i}: {a} where LuxCore is dark"
            );
        } else {
            assert!(
                (a - b).abs() <= 0.03 * b,
                "{what} block {i}: {a} vs LuxCore {b}"
            );
        }
    }
}

/// Asserts that the block means `other` match `a` about as well as `a2` (the same scene as
/// `a` on another sample stream) do: their RMS difference is at most 1.6 times the
/// stream-to-stream noise plus 1 % of the mean, and the image is not black.
pub fn assert_within_noise(a: &[f64], a2: &[f64], other: &[f64], what: &str) {
    let noise = rmse(a, a2);
    let diff = rmse(a, other);
    let mean = a.iter().sum::<f64>() / a.len() as f64;
    assert!(mean > 0.0, "{what}: black image");
    assert!(
        diff <= 1.6 * noise + 0.01 * mean,
        "{what}: difference {diff:.5} vs noise {noise:.5} (mean {mean:.4})"
    );
}

pub fn rmse(a: &[f64], b: &[f64]) -> f64 {
    let se: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
    (se / a.len().max(1) as f64).sqrt()
}

/// Replaces the Film statement's resolution and halt settings in scene text.
pub fn with_resolution(text: &str, res: u32) -> String {
    text.replace(
        "\"integer xresolution\" [256]",
        &format!("\"integer xresolution\" [{res}]"),
    )
    .replace(
        "\"integer yresolution\" [256]",
        &format!("\"integer yresolution\" [{res}]"),
    )
}

/// Centroids along x (in pixels) of the film's X and Z, and the total weight.
pub fn centroids(f: &Film) -> (f64, f64, f64) {
    let xyz = normalized_xyz(f);
    let (mut sx, mut wx, mut sz, mut wz) = (0.0, 0.0, 0.0, 0.0);
    for (i, p) in xyz.iter().enumerate() {
        let x = (i as u32 % f.width()) as f64 + 0.5;
        sx += p[0] * x;
        wx += p[0];
        sz += p[2] * x;
        wz += p[2];
    }
    (sx / wx.max(1e-12), sz / wz.max(1e-12), wx + wz)
}

/// The parameters of a `fleximage` Film of `width` × `height` with the linear tonemapping
/// kernel and the `extra` parameters (image effects and the like).
pub fn linear_film_params(width: i32, height: i32, extra: &[(&str, ParamValue)]) -> FilmParams {
    let mut ps = ParamSet::new();
    ps.add("xresolution", ParamValue::Integer(vec![width]));
    ps.add("yresolution", ParamValue::Integer(vec![height]));
    ps.add("tonemapkernel", ParamValue::String(vec!["linear".into()]));
    for (n, v) in extra {
        ps.add(n, v.clone());
    }
    FilmParams::from_entity(Some(&Entity {
        kind: "fleximage".into(),
        params: ps,
        loc: Loc::default(),
    }))
    .unwrap()
}
