//! The ground truth for our radiometric scale: LuxRender's own regression scene
//! (directlighting/simple, a 6500 K blackbody point light over matte surfaces) rendered by us
//! against LuxRender's reference.flm.
//!
//! Rendered at the full 512×512 resolution but 8 spp instead of the scene's 127 (debug
//! builds are slow): with one point light and direct lighting only, each camera ray's
//! estimate is exact and only antialiasing is noisy.
//!
//! What holds and is asserted: the radiometric scale and its spatial distribution — mean Y
//! over the image within 1 %, the mean XYZ of the achromatic (white matte) surfaces within 1 %,
//! and every 32×32 block of white surface within 1 % of LuxRender's in X, Y and Z (measured at
//! 128 spp: within 0.1 % almost everywhere, 2 % in two blocks cut by edges); and LuxRender's own
//! regression criterion: its runner calls `luxcomp -e 0.25` without `-t`, and luxcomp's
//! default metric is the MSE, so simple.cfg's 0.25 bounds the MSE (ours: 0.110 at 128 spp).
//!
//! What does NOT hold: the RMS ≤ 0.25, and no render can reach it. The reference is a
//! spectral render (random wavelengths) whose per-pixel colour noise on the white surfaces is
//! X 0.33, Y 0.21, Z 1.01 (measured as the residual against our render, whose own noise there
//! is 0.01 and whose block means agree to 0.1 %). That noise alone puts any unbiased, noise-free
//! render at RMS 0.32; a second spectral render would add its own. We measure RMS 0.332 at
//! 128 spp (0.41 at the 8 spp used here). The RMS bound asserted below guards against regressions.

mod render_util;

use luxfarm::film::compare::compare;
use luxfarm::film::flm::read_flm;
use luxfarm::lxs::ParamValue;
use luxfarm::render::{Session, SessionOptions};
use render_util::*;

const DIR: &str = "testsuite/core_regression_tests/tests/integrators/directlighting/simple";

#[test]
fn directlighting_simple_matches_luxrender_scale() {
    let scene = scene_path(&format!("{DIR}/default.lxs"));
    let mut desc = parse(&scene);
    if let Some(sampler) = desc.sampler.as_mut() {
        sampler
            .params
            .add("pixelsamples", ParamValue::Integer(vec![8]));
    }
    let opts = SessionOptions {
        threads: 2,
        seed: 0,
        stream: 0,
    };
    let mut s = Session::new(&desc, scene.parent().unwrap(), opts).unwrap();
    assert_eq!(s.pixel_samples(), 8);
    s.render_pass();
    let ours = s.take_film();
    let reference = scene_path(&format!("{DIR}/reference.flm"));
    let (reference, _) = read_flm(std::fs::File::open(reference).unwrap()).unwrap();
    let c = compare(&reference, &ours).unwrap();
    let (r, o) = (normalized_xyz(&reference), normalized_xyz(&ours));
    let yr: f64 = r.iter().map(|p| p[1]).sum();
    let yo: f64 = o.iter().map(|p| p[1]).sum();
    // Achromatic surfaces: lit pixels whose reference Z is close to Y (not the red cube).
    let white: Vec<usize> = (0..r.len())
        .filter(|&i| r[i][1] > 1.0 && r[i][2] > 0.8 * r[i][1])
        .collect();
    let mean = |v: &[[f64; 3]], c: usize| white.iter().map(|&i| v[i][c]).sum::<f64>();
    eprintln!(
        "RMS {:.4}, mean Y ratio {:.4}, {} white pixels",
        c.rms,
        yo / yr,
        white.len()
    );
    assert!(white.len() > 50_000);
    assert!((yo / yr - 1.0).abs() < 0.01, "mean Y ratio {}", yo / yr);
    for ch in 0..3 {
        let ratio = mean(&o, ch) / mean(&r, ch);
        eprintln!("white surfaces, channel {ch}: ours/reference {ratio:.4}");
        assert!((ratio - 1.0).abs() < 0.01, "channel {ch}: ratio {ratio}");
    }
    assert!(c.rms <= 0.5, "RMS {} > 0.5", c.rms);
    assert!(
        c.mse <= 0.25,
        "MSE {} > 0.25 (luxcomp's default metric)",
        c.mse
    );
    let (w, h) = (ours.width() as usize, ours.height() as usize);
    let mut blocks = 0;
    for by in 0..h / 32 {
        for bx in 0..w / 32 {
            let ids: Vec<usize> = (by * 32..by * 32 + 32)
                .flat_map(|y| (bx * 32..bx * 32 + 32).map(move |x| y * w + x))
                .filter(|i| white.binary_search(i).is_ok())
                .collect();
            if ids.len() < 512 {
                continue;
            }
            blocks += 1;
            for ch in 0..3 {
                let so: f64 = ids.iter().map(|&i| o[i][ch]).sum();
                let sr: f64 = ids.iter().map(|&i| r[i][ch]).sum();
                let ratio = so / sr;
                assert!(
                    (ratio - 1.0).abs() < 0.01,
                    "block ({bx}, {by}) channel {ch}: ours/reference {ratio}"
                );
            }
        }
    }
    eprintln!("{blocks} blocks of white surface agree within 1 %");
    assert!(blocks > 50, "only {blocks} white blocks");
}
