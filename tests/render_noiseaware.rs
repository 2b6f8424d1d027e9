//! Noise-aware sampling on one machine: a scene whose left half is a finely textured matte
//! plane (noisy: every sample lands on another check) and whose right half is an emitter seen
//! directly (every sample returns the same radiance). With `"bool noiseaware"` the first
//! pass samples every pixel `pixelsamples` times; once the session has built its map (at
//! `convergencestep` 4 spp, from each pixel's spread of contributions) the noisy half takes
//! clearly more samples per pixel than the converged one. The box filter of radius 0.5 puts each sample's weight 1
//! in its own pixel only, so a pixel's weight sum is its sample count (the samples of the
//! sample extent's margin, past the right and bottom edges, land in no pixel). The noise-aware film is
//! deterministic (1 and 2 threads give the same bytes) and agrees with a uniform render.

mod render_util;

use luxfarm::film::flm::write_flm;
use luxfarm::film::Film;
use luxfarm::render::{Session, SessionOptions};
use luxfarm::sampler::map::max_pixel_samples;
use render_util::*;
use std::path::Path;

const W: u32 = 32;
const H: u32 = 16;

fn scene(noiseaware: bool) -> String {
    format!(
        r#"LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [-1 1 -0.5 0.5]
Film "fleximage" "integer xresolution" [{W}] "integer yresolution" [{H}]
  "float convergencestep" [4] "bool write_png" ["false"] "bool write_exr" ["false"]
PixelFilter "box" "float xwidth" [0.5] "float ywidth" [0.5]
Sampler "random" "integer pixelsamples" [4] "bool noiseaware" ["{noiseaware}"]
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
}

fn session(noiseaware: bool, threads: usize) -> Session {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/noiseaware.lxs");
    let desc = parse_text(&scene(noiseaware), &path);
    let opts = SessionOptions {
        threads,
        seed: 5,
        stream: 2,
    };
    Session::new(&desc, path.parent().unwrap(), opts).expect("session builds")
}

/// Per-pixel weight sums of group 0, buffer 0.
fn weights(f: &Film) -> Vec<f64> {
    f.buffer(0, 0).unwrap().chunks(5).map(|p| p[4]).collect()
}

/// Mean of `v` over the left (x < W/2 - 2) and right (x >= W/2 + 2) columns (the blurred
/// border left out).
fn halves(v: &[f64]) -> (f64, f64) {
    let (mut l, mut r, mut nl, mut nr) = (0.0, 0.0, 0.0, 0.0);
    for (i, c) in v.iter().enumerate() {
        let x = i as u32 % W;
        if x + 2 < W / 2 {
            l += c;
            nl += 1.0;
        } else if x >= W / 2 + 2 {
            r += c;
            nr += 1.0;
        }
    }
    (l / nl, r / nr)
}

#[test]
fn sampling_follows_the_map_once_it_is_built() {
    let mut s = session(true, 2);
    assert!(s.noise_aware());
    assert!(
        !s.warnings().iter().any(|w| w.to_string().contains("noise")),
        "{:?}",
        s.warnings()
    );
    let mut before = vec![0.0; (W * H) as usize];
    let mut uniform_passes = 0;
    let mut margin_samples = 0.0;
    let mut ratios = Vec::new();
    for _ in 0..8 {
        let had_map = s.sampling_map().is_some();
        let stats = s.render_pass();
        assert!(stats.complete);
        let now = weights(s.film());
        let counts: Vec<f64> = now.iter().zip(&before).map(|(a, b)| a - b).collect();
        // The pass's samples are the film's, and every sample landed in one pixel but those
        // of the sample extent's margin: LuxRender's extent for this box filter reaches one
        // column and one row past the image, whose samples weigh on no pixel of the film.
        let total: f64 = counts.iter().sum();
        let margin = stats.samples as f64 - total;
        let margin_pixels = f64::from(W + H + 1);
        let most = if had_map {
            f64::from(max_pixel_samples(4)) * margin_pixels
        } else {
            4.0 * margin_pixels + 2.0
        };
        assert!(
            margin >= 0.0 && margin <= most && (had_map || margin >= most - 4.0),
            "{total} vs {stats:?}"
        );
        margin_samples += margin;
        if had_map {
            let (l, r) = halves(&counts);
            ratios.push(l / r);
        } else {
            uniform_passes += 1;
            // (a film position that rounds onto the next pixel's edge may move one count)
            assert!(counts.iter().all(|c| (c - 4.0).abs() <= 1.0), "{counts:?}");
            let (l, r) = halves(&counts);
            assert!((l / r - 1.0).abs() < 0.02, "{counts:?}");
        }
        before = now;
    }
    // The first map at 4 spp: the passes follow it from the second on.
    assert_eq!(uniform_passes, 1, "{ratios:?}");
    let mean_ratio = ratios.iter().sum::<f64>() / ratios.len() as f64;
    eprintln!("noisy/converged samples per pixel, passes under the map: {ratios:?}");
    assert!(
        mean_ratio > 3.0,
        "noisy/converged samples per pixel: {ratios:?}"
    );
    assert_eq!(
        s.film().total_samples(),
        weights(s.film()).iter().sum::<f64>() + margin_samples
    );
}

#[test]
fn noise_aware_films_are_deterministic_and_agree_with_uniform_sampling() {
    let flm = |threads: usize| {
        let mut s = session(true, threads);
        for _ in 0..5 {
            s.render_pass();
        }
        assert!(s.sampling_map().is_some());
        let mut out = Vec::new();
        write_flm(s.film(), s.film_params(), &mut out).unwrap();
        (out, s.take_film())
    };
    let (a, fa) = flm(1);
    let (b, _) = flm(2);
    assert!(a == b, "noise-aware FLMs differ between 1 and 2 threads");
    let mut u = session(false, 2);
    assert!(!u.noise_aware());
    // The uniform reference renders twice as long: its own noise then takes less of the
    // tolerance (at 5 passes one of its blocks was 5 % above the three others).
    for _ in 0..10 {
        u.render_pass();
    }
    let fu = u.take_film();
    // The emitter half is exact either way; 8-pixel block means of the textured half agree
    // within the noise of the checks (each pixel averages dark and bright checks).
    let (na, nu) = (normalized_xyz(&fa), normalized_xyz(&fu));
    for y in 0..H {
        for x in W / 2 + 1..W {
            let i = (y * W + x) as usize;
            assert!((na[i][1] - nu[i][1]).abs() < 1e-6, "pixel {x},{y}");
        }
    }
    let (ba, bu) = (block_means(&fa, 8), block_means(&fu, 8));
    for (i, (p, q)) in ba.iter().zip(&bu).enumerate() {
        assert!(
            (p - q).abs() < 0.05 * q.abs().max(0.05),
            "block {i}: {p} vs {q}"
        );
    }
}

/// Metropolis takes `noiseaware` (LuxRender's does): the session builds its map from the
/// spread of the chains' deposits and the chains follow it, with no warning, and the image stays that of
/// uniform sampling (8-pixel block means of the film's luminance, per-screen buffers
/// normalised as the tonemapper does).
#[test]
fn metropolis_takes_noiseaware_without_bias() {
    use luxfarm::tonemap::{film_xyz, TonemapParams};
    let text = scene(true).replace(
        r#"Sampler "random" "integer pixelsamples" [4]"#,
        r#"Sampler "metropolis" "integer pixelsamples" [4]"#,
    );
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/noiseaware.lxs");
    let desc = parse_text(&text, &path);
    let lum = |f: &Film| -> Vec<f64> {
        let xyz = film_xyz(f, &TonemapParams::default()).xyz;
        xyz.iter().map(|p| f64::from(p[1])).collect()
    };
    let blocks = |v: &[f64]| -> Vec<f64> {
        let mut out = vec![0.0; ((W / 8) * (H / 8)) as usize];
        for (i, y) in v.iter().enumerate() {
            let (px, py) = (i as u32 % W, i as u32 / W);
            out[((py / 8) * (W / 8) + px / 8) as usize] += y / 64.0;
        }
        out
    };
    let run = |stream: u64| {
        let opts = SessionOptions {
            threads: 2,
            seed: 5,
            stream,
        };
        let mut s = Session::new(&desc, path.parent().unwrap(), opts).unwrap();
        assert!(s.noise_aware());
        assert!(
            !s.warnings().iter().any(|w| w.to_string().contains("noise")),
            "{:?}",
            s.warnings()
        );
        for _ in 0..8 {
            s.render_pass();
        }
        assert!(
            s.sampling_map().is_some(),
            "no noise-aware map after 8 passes"
        );
        blocks(&lum(&s.take_film()))
    };
    let (a, a2) = (run(1), run(2));
    let mut u = session(false, 2);
    for _ in 0..16 {
        u.render_pass();
    }
    let uniform = blocks(&lum(&u.take_film()));
    eprintln!("metropolis noise-aware {a:?} / {a2:?}\nuniform {uniform:?}");
    assert_within_noise(&a, &a2, &uniform, "metropolis noise-aware vs uniform");
}

/// Metropolis drops black contributions from the image, but a noise-aware film still counts
/// them in its variance sums (as LuxRender deposits them): with no infinite light the left
/// half of the scene is black, and the session still builds its map.
#[test]
fn metropolis_builds_a_map_over_black_regions() {
    let text = scene(true)
        .replace(
            r#"Sampler "random" "integer pixelsamples" [4]"#,
            r#"Sampler "metropolis" "integer pixelsamples" [4]"#,
        )
        .replace(r#"LightSource "infinite" "color L" [1 1 1]"#, "");
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/noiseaware.lxs");
    let desc = parse_text(&text, &path);
    let opts = SessionOptions {
        threads: 2,
        seed: 5,
        stream: 1,
    };
    let mut s = Session::new(&desc, path.parent().unwrap(), opts).unwrap();
    for _ in 0..8 {
        s.render_pass();
    }
    let v = s
        .film()
        .variance()
        .expect("a noise-aware film keeps variance sums");
    let reached = v.sums().iter().filter(|p| p[0] > 0.0).count();
    assert_eq!(reached, (W * H) as usize, "pixels with a contribution");
    assert!(s.sampling_map().is_some(), "no map over a half-black film");
}
