//! The user sampling map on one machine (LuxRender's `luxSetUserSamplingMap`): a 32×16 film of
//! a finely textured matte plane (every pixel noisy) under an infinite light, random sampler.
//! A user map weighting the left half 9:1 gives the left pixels nine times the samples of the
//! right ones (the box filter of radius 0.5 puts each sample's weight 1 in its own pixel, so a
//! pixel's weight sum is its sample count), pixels of weight 0 take none, and the image agrees
//! with a uniform render within noise. With a noise-aware sampler the map the passes follow is
//! the product of both maps; erpt does not take the map (metropolis does: `transport_mlt`).

mod render_util;

use luxfarm::film::Film;
use luxfarm::render::{Session, SessionOptions};
use luxfarm::sampler::map::SamplingMap;
use render_util::*;
use std::path::Path;
use std::sync::Arc;

const W: u32 = 32;
const H: u32 = 16;

fn scene(sampler: &str) -> String {
    format!(
        r#"LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [-1 1 -0.5 0.5]
Film "fleximage" "integer xresolution" [{W}] "integer yresolution" [{H}]
  "float convergencestep" [4] "bool write_png" ["false"] "bool write_exr" ["false"]
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
}

const RANDOM: &str = r#"Sampler "random" "integer pixelsamples" [4]"#;

fn session(sampler: &str, stream: u64) -> Session {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/usermap.lxs");
    let desc = parse_text(&scene(sampler), &path);
    let opts = SessionOptions {
        threads: 2,
        seed: 11,
        stream,
    };
    Session::new(&desc, path.parent().unwrap(), opts).expect("session builds")
}

/// The user's weights: `left` on the left half, `right` on the right half.
fn halves_map(left: f32, right: f32) -> Arc<SamplingMap> {
    let w: Vec<f32> = (0..W * H)
        .map(|i| if i % W < W / 2 { left } else { right })
        .collect();
    Arc::new(SamplingMap::from_weights(&w, W, H).unwrap())
}

/// Per-pixel weight sums (sample counts) of group 0, buffer 0.
fn counts(f: &Film) -> Vec<f64> {
    f.buffer(0, 0).unwrap().chunks(5).map(|p| p[4]).collect()
}

/// Mean count of the left and right halves.
fn halves(c: &[f64]) -> (f64, f64) {
    let (mut l, mut r) = (0.0, 0.0);
    for (i, v) in c.iter().enumerate() {
        if (i as u32 % W) < W / 2 {
            l += v;
        } else {
            r += v;
        }
    }
    let n = f64::from(W / 2 * H);
    (l / n, r / n)
}

#[test]
fn sample_counts_follow_a_user_map_of_nine_to_one() {
    let mut s = session(RANDOM, 1);
    assert!(s.takes_maps() && !s.noise_aware());
    assert!(s.set_user_map(Some(halves_map(9.0, 1.0))).unwrap());
    let passes = 6;
    for _ in 0..passes {
        assert!(s.render_pass().complete);
    }
    let (l, r) = halves(&counts(s.film()));
    eprintln!("samples per pixel: left {l:.2} right {r:.2}");
    // densities 1.8 and 0.2 of 4 samples per pass
    assert!((l / f64::from(passes) - 7.2).abs() < 0.25, "left {l}");
    assert!((r / f64::from(passes) - 0.8).abs() < 0.1, "right {r}");
    assert!((l / r - 9.0).abs() < 1.0, "ratio {}", l / r);
    // Cleared: back to uniform sampling.
    let before = counts(s.film());
    assert!(s.set_user_map(None).unwrap());
    assert!(s.sampling_map().is_none());
    s.render_pass();
    let after = counts(s.film());
    let pass: Vec<f64> = after.iter().zip(&before).map(|(a, b)| a - b).collect();
    let (l, r) = halves(&pass);
    assert!((l - 4.0).abs() < 0.1 && (r - 4.0).abs() < 0.1, "{l} {r}");
}

#[test]
fn pixels_of_weight_zero_take_no_samples() {
    let mut s = session(RANDOM, 1);
    // column 5 and row 3 painted out
    let w: Vec<f32> = (0..W * H)
        .map(|i| if i % W == 5 || i / W == 3 { 0.0 } else { 1.0 })
        .collect();
    s.set_user_map(Some(Arc::new(SamplingMap::from_weights(&w, W, H).unwrap())))
        .unwrap();
    for _ in 0..3 {
        s.render_pass();
    }
    let c = counts(s.film());
    for (i, v) in c.iter().enumerate() {
        let (x, y) = (i as u32 % W, i as u32 / W);
        if x == 5 || y == 3 {
            assert_eq!(*v, 0.0, "pixel {x},{y}");
        } else {
            assert!(*v > 0.0, "pixel {x},{y}");
        }
    }
}

#[test]
fn a_user_mapped_image_agrees_with_a_uniform_render_within_noise() {
    let mapped = |stream: u64| {
        let mut s = session(RANDOM, stream);
        s.set_user_map(Some(halves_map(9.0, 1.0))).unwrap();
        for _ in 0..16 {
            s.render_pass();
        }
        block_means(&s.take_film(), 8)
    };
    let (a, a2) = (mapped(1), mapped(2));
    let mut u = session(RANDOM, 3);
    for _ in 0..32 {
        u.render_pass();
    }
    let uniform = block_means(&u.take_film(), 8);
    eprintln!("mapped {a:?}\nuniform {uniform:?}");
    assert_within_noise(&a, &a2, &uniform, "user-mapped vs uniform");
}

#[test]
fn a_noise_aware_sampler_follows_the_product_of_both_maps() {
    let sampler = r#"Sampler "sobol" "integer pixelsamples" [4] "bool noiseaware" ["true"]"#;
    let mut s = session(sampler, 1);
    assert!(s.noise_aware());
    let user = halves_map(1.0, 3.0);
    s.set_user_map(Some(user.clone())).unwrap();
    // Before the first noise-aware map: the user map alone.
    assert_eq!(s.sampling_map(), Some(&*user));
    for _ in 0..4 {
        s.render_pass();
    }
    let m = s.sampling_map().expect("a map").clone();
    assert_ne!(m, *user, "the noise-aware map was multiplied in");
    // The right half keeps more density than the left: the user's 3:1, lowered by the
    // noise-aware map (the right half, sampled more, is the less noisy one).
    let mean = |x0: u32, x1: u32| -> f32 {
        let v: Vec<f32> = (0..H)
            .flat_map(|y| (x0..x1).map(move |x| (x, y)))
            .map(|(x, y)| m.density(x, y))
            .collect();
        v.iter().sum::<f32>() / v.len() as f32
    };
    let ratio = mean(W / 2, W) / mean(0, W / 2);
    assert!(ratio > 1.1 && ratio < 5.0, "right/left density {ratio}");
}

#[test]
fn erpt_does_not_take_the_map() {
    let mut s = session(r#"Sampler "erpt""#, 1);
    assert!(!s.takes_maps());
    assert!(!s.set_user_map(Some(halves_map(9.0, 1.0))).unwrap());
    assert!(s.sampling_map().is_none());
    let why = s
        .renderable()
        .setup
        .sampler
        .map_refusal()
        .expect("a reason");
    assert!(why.contains("not applied"), "{why}");
    // a map of the wrong size is refused whatever the sampler
    let mut s = session(RANDOM, 1);
    let small = Arc::new(SamplingMap::uniform(W - 1, H).unwrap());
    let e = s.set_user_map(Some(small)).unwrap_err().to_string();
    assert!(e.contains("31x16") && e.contains("32x16"), "{e}");
}

/// Under a map each pixel takes the next indices of its own sample sequence (`render::counts`),
/// so a map that gives every pixel `pixelsamples` a pass draws exactly the samples of a render
/// without a map: the films are the same bytes, for the stratified samplers too. (Before,
/// passes under a map drew strided indices of their own and lost sobol's stratification.)
#[test]
fn an_even_map_draws_the_very_samples_of_no_map() {
    for sampler in [
        r#"Sampler "sobol" "integer pixelsamples" [4]"#,
        r#"Sampler "lowdiscrepancy" "integer pixelsamples" [4]"#,
        RANDOM,
    ] {
        let mut plain = session(sampler, 0);
        let mut even = session(sampler, 0);
        for pass in 0..4 {
            if pass == 1 {
                // The map arrives after a uniform pass, as a farm worker's would.
                assert!(even.set_user_map(Some(halves_map(1.0, 1.0))).unwrap());
            }
            plain.render_pass();
            even.render_pass();
        }
        assert_eq!(
            plain.film().buffer(0, 0).unwrap(),
            even.film().buffer(0, 0).unwrap(),
            "{sampler}"
        );
    }
}
