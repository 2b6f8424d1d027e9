//! Helpers of the light-transport tests: scenes with their sampler and integrator replaced,
//! independent renders, and statistics of block means (mean and standard error over runs).

#![allow(dead_code)]

use luxfarm::film::Film;
use luxfarm::lxs::{parse_file, parse_str, ParamValue, ParseOptions, SceneDescription};
use luxfarm::render::{Session, SessionOptions};
use luxfarm::tonemap::{film_xyz, TonemapParams};
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

/// A scene with its Sampler and SurfaceIntegrator replaced by the statements in `setup`
/// (LuxRender text) and its film resolution set to `w` × `h`.
pub fn scene(rel: &str, setup: &str, w: u32, h: u32) -> (SceneDescription, PathBuf) {
    let path = scene_path(rel);
    let mut desc = parse_file(&path, &ParseOptions::default()).expect("scene parses");
    let text = format!("{setup}\nWorldBegin\nWorldEnd\n");
    let over = parse_str(&text, "setup.lxs", &ParseOptions::default()).expect("setup parses");
    desc.sampler = over.sampler;
    desc.surface_integrator = over.surface_integrator;
    if let Some(f) = desc.film.as_mut() {
        f.params
            .add("xresolution", ParamValue::Integer(vec![w as i32]));
        f.params
            .add("yresolution", ParamValue::Integer(vec![h as i32]));
        f.params
            .add("cropwindow", ParamValue::Float(vec![0.0, 1.0, 0.0, 1.0]));
    }
    let dir = path.parent().expect("scene directory").to_path_buf();
    (desc, dir)
}

/// A scene from text, its relative files beside `near`.
pub fn scene_text(text: &str, near: &Path) -> SceneDescription {
    parse_str(text, &near.to_string_lossy(), &ParseOptions::default()).expect("scene parses")
}

/// Renders `passes` passes with stream `stream`.
pub fn render(desc: &SceneDescription, dir: &Path, stream: u64, passes: u32) -> Film {
    let opts = SessionOptions {
        threads: 2,
        seed: 7,
        stream,
    };
    let mut s = Session::new(desc, dir, opts).expect("session builds");
    for _ in 0..passes {
        assert!(s.render_pass().complete);
    }
    s.take_film()
}

/// Luminance Y of the film's image (every buffer normalised as the tonemapper does).
pub fn luminance(f: &Film) -> Vec<f64> {
    film_xyz(f, &TonemapParams::default())
        .xyz
        .iter()
        .map(|p| f64::from(p[1]))
        .collect()
}

/// Means of Y over `block` × `block` pixel blocks.
pub fn block_means(f: &Film, block: u32) -> Vec<f64> {
    let y = luminance(f);
    let (bw, bh) = (f.width() / block, f.height() / block);
    let mut out = vec![0.0; (bw * bh) as usize];
    for py in 0..bh * block {
        for px in 0..bw * block {
            let i = ((py / block) * bw + px / block) as usize;
            out[i] += y[(py * f.width() + px) as usize] / f64::from(block * block);
        }
    }
    out
}

/// Block means of `runs` independent renders (streams `first`, `first + 1`, ...).
pub fn runs(
    desc: &SceneDescription,
    dir: &Path,
    first: u64,
    runs: u64,
    passes: u32,
    block: u32,
) -> Vec<Vec<f64>> {
    (first..first + runs)
        .map(|s| block_means(&render(desc, dir, s, passes), block))
        .collect()
}

/// Per block: the mean over runs and its standard error.
pub fn mean_se(runs: &[Vec<f64>]) -> (Vec<f64>, Vec<f64>) {
    let n = runs.len() as f64;
    let k = runs.first().map_or(0, Vec::len);
    let mut mean = vec![0.0; k];
    for r in runs {
        for (m, v) in mean.iter_mut().zip(r) {
            *m += v / n;
        }
    }
    let mut se = vec![0.0; k];
    for r in runs {
        for ((s, v), m) in se.iter_mut().zip(r).zip(&mean) {
            *s += (v - m).powi(2) / (n - 1.0).max(1.0);
        }
    }
    for s in &mut se {
        *s = (*s / n).sqrt();
    }
    (mean, se)
}

/// Asserts that two sets of runs estimate the same block means: every block's difference
/// within `zmax` combined standard errors (plus `rel` of the block's mean, for the bias of
/// a finite number of samples where a method has it), and the mean squared z not far above
/// 1. Returns the largest |z|.
pub fn assert_agree(what: &str, a: &[Vec<f64>], b: &[Vec<f64>], zmax: f64, rel: f64) -> f64 {
    let (ma, sa) = mean_se(a);
    let (mb, sb) = mean_se(b);
    let mut worst = 0.0f64;
    let mut z2 = 0.0;
    for i in 0..ma.len() {
        let se = (sa[i].powi(2) + sb[i].powi(2)).sqrt();
        let tol = se + rel * ma[i].abs().max(mb[i].abs());
        let z = if tol > 0.0 {
            (ma[i] - mb[i]) / tol
        } else {
            0.0
        };
        eprintln!(
            "{what}: block {i}: {:.5} ± {:.5} vs {:.5} ± {:.5}: z {z:.2}",
            ma[i], sa[i], mb[i], sb[i]
        );
        worst = worst.max(z.abs());
        z2 += z * z;
    }
    let mean_z2 = z2 / ma.len().max(1) as f64;
    eprintln!("{what}: max |z| {worst:.2}, mean z² {mean_z2:.2}");
    assert!(ma.iter().sum::<f64>() > 0.0, "{what}: black image");
    assert!(worst < zmax, "{what}: max |z| {worst:.2} >= {zmax}");
    assert!(mean_z2 < 4.0, "{what}: mean z² {mean_z2:.2}");
    worst
}

/// A session over the Cornell box at `size`² with `setup`, seed 11, on `stream`.
pub fn cornell_session(setup: &str, size: u32, threads: usize, stream: u64) -> Session {
    let (desc, dir) = scene("cornell/cornell.lxs", setup, size, size);
    let opts = SessionOptions {
        threads,
        seed: 11,
        stream,
    };
    Session::new(&desc, &dir, opts).expect("session builds")
}

/// Two passes of the Cornell box at 24² with `setup`.
pub fn cornell_film(setup: &str, threads: usize, stream: u64) -> Film {
    let mut s = cornell_session(setup, 24, threads, stream);
    for _ in 0..2 {
        assert!(s.render_pass().complete);
    }
    s.take_film()
}

/// The per-screen films of a chain sampler do not depend on the thread count.
pub fn assert_thread_independent(setup: &str) {
    let a = cornell_film(setup, 1, 3);
    let b = cornell_film(setup, 2, 3);
    for buf in 0..2 {
        assert_eq!(a.buffer(0, buf), b.buffer(0, buf), "buffer {buf}");
    }
    assert!(a.buffer(0, 0).unwrap().iter().any(|v| *v > 0.0));
}

/// Two workers on their own streams: the merged film is the exact sum of theirs (buffers
/// and sample counts) and differs from either (independent chains). Returns one worker's
/// film for the caller's own checks.
pub fn assert_streams_merge_exactly(setup: &str) -> Film {
    let a = cornell_film(setup, 2, 0);
    let b = cornell_film(setup, 2, 1);
    let mut m = a.clone();
    m.merge(&b).expect("same layout");
    for buf in 0..2 {
        let (va, vb, vm) = (
            a.buffer(0, buf).unwrap(),
            b.buffer(0, buf).unwrap(),
            m.buffer(0, buf).unwrap(),
        );
        assert_ne!(va, vb, "streams 0 and 1 ran the same chains");
        for ((x, y), z) in va.iter().zip(vb).zip(vm) {
            assert_eq!(x + y, *z);
        }
    }
    assert_eq!(m.sample_count(0), a.sample_count(0) + b.sample_count(0));
    a
}

/// An axis-aligned box of centre `c` and half sides `h` as a trianglemesh, normals outward.
pub fn box_mesh(c: [f32; 3], h: [f32; 3]) -> String {
    let corner = |i: usize| {
        let sx = if matches!(i, 1 | 2 | 5 | 6) {
            h[0]
        } else {
            -h[0]
        };
        let sy = if matches!(i, 2 | 3 | 6 | 7) {
            h[1]
        } else {
            -h[1]
        };
        let sz = if i >= 4 { h[2] } else { -h[2] };
        format!("{} {} {}", c[0] + sx, c[1] + sy, c[2] + sz)
    };
    let points: Vec<String> = (0..8).map(corner).collect();
    let faces = [
        [0, 3, 2, 1],
        [4, 5, 6, 7],
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
    ];
    let indices: Vec<String> = faces
        .iter()
        .flat_map(|[a, b, c, d]| [a, b, c, a, c, d])
        .map(ToString::to_string)
        .collect();
    format!(
        "Shape \"trianglemesh\" \"integer indices\" [{}] \"point P\" [{}]",
        indices.join(" "),
        points.join(" ")
    )
}
