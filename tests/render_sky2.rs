//! `sky2` side by side with LuxCore (pyluxcore 2.11), whose `sky2` evaluates the same
//! Hosek–Wilkie RGB tables (× 683 lm/W): the reference numbers below were printed by
//! `python3 scripts/luxcore_sky2.py` (radiance in chosen directions) and
//! `python3 scripts/luxcore_sky2_render.py --spp 256` (32-pixel block means of the scene
//! [`SCENE`]); rerun those to regenerate them.

mod render_util;

use glam::Vec3A;
use luxfarm::light::sky2::Sky2Model;
use luxfarm::render::SessionOptions;
use luxfarm::spectrum::{rgb_to_xyz, xyz_to_rgb};
use render_util::*;

/// LuxCore's film RGB for (sun elevation°, turbidity, view elevation°, view azimuth° from the
/// sun).
#[rustfmt::skip]
const LUXCORE_DIRECTIONS: [(f32, f32, f32, f32, [f32; 3]); 15] = [
    (30.0, 3.0, 90.0, 0.0, [1041.92, 1969.22, 3948.66]),
    (30.0, 3.0, 45.0, 180.0, [1402.85, 2711.38, 5152.93]),
    (30.0, 3.0, 20.0, 90.0, [2897.29, 5020.21, 8246.07]),
    (30.0, 3.0, 5.0, 135.0, [6938.43, 10368.2, 12734.8]),
    (30.0, 3.0, 35.0, 10.0, [10831.0, 12297.9, 13483.9]),
    (10.0, 6.0, 90.0, 0.0, [875.127, 1414.95, 2168.23]),
    (10.0, 6.0, 45.0, 180.0, [1576.84, 2390.15, 3294.79]),
    (10.0, 6.0, 20.0, 90.0, [3008.28, 3998.25, 4652.01]),
    (10.0, 6.0, 5.0, 135.0, [4924.63, 5669.84, 5070.36]),
    (10.0, 6.0, 35.0, 10.0, [8114.51, 7563.83, 6196.99]),
    (60.0, 2.0, 90.0, 0.0, [1563.67, 2658.33, 5803.85]),
    (60.0, 2.0, 45.0, 180.0, [1315.27, 2722.73, 6114.63]),
    (60.0, 2.0, 20.0, 90.0, [2863.43, 5266.05, 9933.83]),
    (60.0, 2.0, 5.0, 135.0, [6411.67, 9919.89, 14663.2]),
    (60.0, 2.0, 35.0, 10.0, [3596.88, 5753.92, 10425.4]),
];

fn unit(elev_deg: f32, azim_deg: f32) -> Vec3A {
    let (e, a) = (elev_deg.to_radians(), azim_deg.to_radians());
    Vec3A::new(e.cos() * a.cos(), e.cos() * a.sin(), e.sin())
}

fn luminance(rgb: [f32; 3]) -> f32 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

#[test]
fn sky2_radiance_matches_luxcore_in_chosen_directions() {
    for (sun_elev, turbidity, elev, azim, lc) in LUXCORE_DIRECTIONS {
        let model = Sky2Model::new(unit(sun_elev, 0.0), turbidity, 0.0);
        let d = unit(elev, azim);
        let ours = model.srgb(d);
        for c in 0..3 {
            let rel = (ours[c] - lc[c]).abs() / lc[c];
            // LuxCore's value is a 0.5° camera's mean: up to 1 % off near the sun's halo.
            assert!(
                rel < 0.02,
                "sun {sun_elev}° T {turbidity} view ({elev}°, {azim}°): {ours:?} vs LuxCore {lc:?}"
            );
        }
        // What reaches luxfarm's film: the illuminant RGB of the model's XYZ, back to XYZ.
        let film_y = rgb_to_xyz(xyz_to_rgb(model.xyz(d)))[1];
        let rel = (film_y - luminance(lc)).abs() / luminance(lc);
        eprintln!("sun {sun_elev}° T {turbidity} view ({elev}°, {azim}°): film Y {film_y:.1} LuxCore Y {:.1} ({:+.2} %)", luminance(lc), 100.0 * (film_y / luminance(lc) - 1.0));
        assert!(rel < 0.03, "film Y {film_y} vs LuxCore {}", luminance(lc));
    }
}

/// The comparison scene (see scripts/luxcore_sky2_render.py): grey ground, camera 1 m up
/// looking level toward azimuth 135°, sky2 with the sun at 30° elevation and turbidity 3.
const SCENE: &str = r#"
LookAt 0 0 1  -0.70710678 0.70710678 1  0 0 1
Camera "perspective" "float fov" [90]
Film "fleximage" "integer xresolution" [128] "integer yresolution" [128]
PixelFilter "box" "float xwidth" [0.5] "float ywidth" [0.5]
Sampler "random" "integer pixelsamples" [16]
SurfaceIntegrator "path" "integer maxdepth" [1]
WorldBegin
LightSource "sky2" "vector sundir" [0.8660254 0 0.5] "float turbidity" [3]
Material "matte" "color Kd" [0.5 0.5 0.5]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point P" [-1000 -1000 0 1000 -1000 0 1000 1000 0 -1000 1000 0]
WorldEnd
"#;

/// LuxCore's 32-pixel block means of Y, rows from the top (256 spp).
#[rustfmt::skip]
const LUXCORE_BLOCKS: [f64; 16] = [
    3806.2, 3227.6, 3128.8, 3565.3,
    8509.2, 7289.9, 6383.0, 6455.5,
    2491.8, 2449.3, 2370.0, 2333.7,
    2165.5, 2161.9, 2163.7, 2162.5,
];

/// Luminance of the grey (0.5) ground under the sky alone: 0.5 · E / π with E the horizontal
/// illuminance, by midpoint quadrature of the model over the upper hemisphere.
fn ground_luminance() -> f64 {
    let model = Sky2Model::new(unit(30.0, 0.0), 3.0, 0.0);
    let (nt, np) = (400, 800);
    let mut e = 0.0f64;
    for i in 0..nt {
        let theta = (i as f64 + 0.5) / nt as f64 * std::f64::consts::FRAC_PI_2;
        for j in 0..np {
            let phi = (j as f64 + 0.5) / np as f64 * std::f64::consts::TAU;
            let w = Vec3A::new(
                (theta.sin() * phi.cos()) as f32,
                (theta.sin() * phi.sin()) as f32,
                theta.cos() as f32,
            );
            let y = rgb_to_xyz(xyz_to_rgb(model.xyz(w)))[1];
            let dw = theta.sin()
                * (std::f64::consts::FRAC_PI_2 / nt as f64)
                * (std::f64::consts::TAU / np as f64);
            e += f64::from(y) * theta.cos() * dw;
        }
    }
    0.5 * e / std::f64::consts::PI
}

/// The sky (rows 0–1) agrees with LuxCore within 3 %; the ground (rows 2–3) with the closed
/// form. LuxCore's own ground row just below the horizon (grazing views, 0.35°–11° down) is
/// 6–14 % brighter than its next row and than the closed form, for a Lambertian plane under
/// an infinitely distant sky whose radiance cannot depend on the distance; that row is
/// reported, not compared.
#[test]
fn sky2_scene_matches_luxcore_block_means() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("sky2.lxs");
    let desc = parse_text(SCENE, &path);
    let opts = SessionOptions {
        threads: 2,
        seed: 11,
        stream: 0,
    };
    let film = render(&desc, dir.path(), opts, 1);
    let ours = block_means(&film, 32);
    let ground = ground_luminance();
    eprintln!("ground luminance by quadrature: {ground:.1}");
    for (i, (a, b)) in ours.iter().zip(LUXCORE_BLOCKS).enumerate() {
        eprintln!(
            "block {i}: luxfarm {a:.1} LuxCore {b:.1} ({:+.2} %)",
            100.0 * (a / b - 1.0)
        );
        if i < 8 {
            assert!(
                (a - b).abs() < 0.03 * b,
                "sky block {i}: {a} vs LuxCore {b}"
            );
        } else {
            assert!(
                (a - ground).abs() < 0.03 * ground,
                "ground block {i}: {a} vs {ground}"
            );
        }
        if i >= 12 {
            assert!(
                (a - b).abs() < 0.03 * b,
                "ground block {i}: {a} vs LuxCore {b}"
            );
        }
    }
}
