//! The old region `Volume` statement rendered end to end: an orthographic camera looks down -z
//! at a constant environment of radiance 1 through a region box that covers one half of the
//! image (x > 0) and is 2 units deep; each pixel's radiance is the box's transmittance along
//! its vertical ray, known in closed form:
//!
//! - `homogeneous`: exp(-2 sigma_a);
//! - `exponential` with `updir` 0 0 1: exp(-sigma_a · a (1 - e^(-2b)) / b) (height from the
//!   box's low corner);
//! - `volumegrid` 2×1×1 with values 0 and 1 across x: the density interpolated between voxel
//!   centres, exp(-2 sigma_a d(x)), averaged over each pixel's width;
//! - the statement's transform moves the box; pixels outside it see the environment
//!   unchanged; an oversized grid is a located error; an unknown region kind is warned about.

mod render_util;

use luxfarm::render::setup::Renderable;
use luxfarm::render::SessionOptions;
use luxfarm::spectrum::{rgb_to_xyz, Rgb};
use render_util::*;
use std::path::Path;

const RES: u32 = 8;

fn scene(region: &str) -> String {
    scene_with("single", region)
}

/// The scene with VolumeIntegrator `integrator` (`emission` attenuates by the marched
/// transmittance, without the noise of sampling scattering points).
fn scene_with(integrator: &str, region: &str) -> String {
    format!(
        r#"LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [-1 1 -1 1]
Film "fleximage" "integer xresolution" [{RES}] "integer yresolution" [{RES}]
PixelFilter "box"
Sampler "random" "integer pixelsamples" [16]
SurfaceIntegrator "path" "integer maxdepth" [4]
VolumeIntegrator "{integrator}"
WorldBegin
LightSource "infinite" "color L" [1 1 1]
AttributeBegin
{region}
AttributeEnd
WorldEnd
"#
    )
}

/// Y of each image column relative to the environment's, and the build's warnings.
fn columns(region: &str) -> (Vec<f64>, Vec<String>) {
    columns_with("single", region)
}

fn columns_with(integrator: &str, region: &str) -> (Vec<f64>, Vec<String>) {
    let desc = parse_text(
        &scene_with(integrator, region),
        Path::new("/tmp/render_region_volume.lxs"),
    );
    let warnings = Renderable::build(&desc, Path::new("/tmp"))
        .expect("scene builds")
        .warnings
        .into_iter()
        .map(|d| d.to_string())
        .collect();
    let opts = SessionOptions {
        threads: 2,
        seed: 7,
        stream: 0,
    };
    let film = render(&desc, Path::new("/tmp"), opts, 1);
    let white = f64::from(rgb_to_xyz(Rgb::WHITE)[1]);
    let xyz = normalized_xyz(&film);
    let mut col = vec![0.0; RES as usize];
    for (i, p) in xyz.iter().enumerate() {
        col[i % RES as usize] += p[1] / white / RES as f64;
    }
    (col, warnings)
}

fn check(name: &str, got: &[f64], want: impl Fn(usize) -> f64) {
    check_within(name, got, want, 0.01)
}

/// `got` within the relative tolerance `tol` of `want` per column.
fn check_within(name: &str, got: &[f64], want: impl Fn(usize) -> f64, tol: f64) {
    eprintln!("{name}: {got:.4?}");
    for (i, g) in got.iter().enumerate() {
        let w = want(i);
        assert!(
            (g - w).abs() < tol * w.max(0.1),
            "{name} column {i}: {g} vs {w}"
        );
    }
}

const BOX: &str = r#""point p0" [0 -2 -1] "point p1" [2 2 1]"#;

#[test]
fn a_homogeneous_region_absorbs_along_its_depth_only() {
    let (c, w) = columns(&format!(
        r#"Volume "homogeneous" {BOX} "color sigma_a" [0.5 0.5 0.5]"#
    ));
    assert!(w.iter().all(|w| !w.contains("Volume")), "{w:?}");
    check(
        "homogeneous",
        &c,
        |i| if i < 4 { 1.0 } else { (-1.0f64).exp() },
    );
    // The statement's transform places the box: moved to x < 0.
    let (c, _) = columns(&format!(
        r#"Translate -2 0 0
Volume "homogeneous" {BOX} "color sigma_a" [0.5 0.5 0.5]"#
    ));
    check(
        "translated",
        &c,
        |i| if i < 4 { (-1.0f64).exp() } else { 1.0 },
    );
}

#[test]
fn an_exponential_region_thins_with_height_from_its_low_corner() {
    let (c, _) = columns_with(
        "emission",
        &format!(
            r#"Volume "exponential" {BOX} "color sigma_a" [0.5 0.5 0.5] "float a" [1] "float b" [1]
  "vector updir" [0 0 1] "float stepsize" [0.01]"#
        ),
    );
    let t = (-0.5 * (1.0 - (-2.0f64).exp())).exp();
    check("exponential", &c, |i| if i < 4 { 1.0 } else { t });
}

#[test]
fn a_volumegrid_region_interpolates_its_density() {
    let (c, _) = columns_with(
        "emission",
        r#"Volume "volumegrid" "point p0" [-2 -2 -1] "point p1" [2 2 1] "color sigma_a" [1 1 1]
  "integer nx" [2] "integer ny" [1] "integer nz" [1] "float density" [0 1] "float stepsize" [0.01]"#,
    );
    // Pixel i spans x in [-1 + i/4, -1 + (i+1)/4]; d(x) = clamp((x + 1) / 2, 0, 1).
    let want = |i: usize| {
        let n = 64;
        (0..n)
            .map(|k| {
                let x = -1.0 + (i as f64 + (k as f64 + 0.5) / n as f64) / 4.0;
                (-2.0 * ((x + 1.0) / 2.0).clamp(0.0, 1.0)).exp()
            })
            .sum::<f64>()
            / n as f64
    };
    // 2%: the transmittance varies by up to a quarter across a pixel, which its 128 random
    // sample positions average with about 1% noise.
    check_within("volumegrid", &c, want, 0.02);
}

#[test]
fn region_problems_are_reported_where_they_are() {
    let desc = parse_text(
        &scene(
            r#"Volume "volumegrid" "integer nx" [100000] "integer ny" [100000] "integer nz" [100000] "float density" [1]"#,
        ),
        Path::new("/tmp/render_region_big.lxs"),
    );
    let err = Renderable::build(&desc, Path::new("/tmp"))
        .err()
        .expect("refused")
        .to_string();
    assert!(err.contains("/tmp/render_region_big.lxs:11:1"), "{err}");
    assert!(err.contains("more than"), "{err}");
    let (c, w) = columns(r#"Volume "smoke" "color sigma_a" [1 1 1]"#);
    assert!(
        w.iter().any(|w| w.contains(":11:1") && w.contains("smoke")),
        "{w:?}"
    );
    check("unknown region kind (not rendered)", &c, |_| 1.0);
    // A grid whose values do not match its size is dropped with a warning, as LuxRender does.
    let (c, w) = columns(
        r#"Volume "volumegrid" "integer nx" [2] "float density" [1] "color sigma_a" [1 1 1]"#,
    );
    assert!(w.iter().any(|w| w.contains("dropped")), "{w:?}");
    check("mismatched grid", &c, |_| 1.0);
}

/// A `cloud` region in the default box [0, 1]³: its hemisphere (centre (0.5, 0.5, 0.33),
/// radius 0.5, density 1 near the centre) darkens the columns over x > 0 it covers, and
/// leaves the half x < 0 untouched.
#[test]
fn a_cloud_region_darkens_what_it_covers() {
    let (c, w) = columns_with(
        "emission",
        r#"Volume "cloud" "color sigma_a" [20 20 20] "float turbulence" [0] "float stepsize" [0.01]"#,
    );
    assert!(w.iter().all(|w| !w.contains("cloud")), "{w:?}");
    eprintln!("cloud: {c:.4?}");
    assert!(c[..4].iter().all(|v| (v - 1.0).abs() < 1e-3), "{c:?}");
    assert!(c[4..].iter().any(|v| *v < 0.8), "{c:?}");
}

/// Past `MAX_REGIONS` region volumes the rest are ignored with a located warning (every ray
/// is clipped against each region): 256 thin absorbing slabs x in [k/256, (k + 1)/256] darken
/// the half x > 0, and a 257th box over x < 0 is left out.
#[test]
fn regions_past_the_limit_are_ignored_with_a_warning() {
    assert_eq!(luxfarm::volume::MAX_REGIONS, 256);
    let mut text = String::new();
    for k in 0..256 {
        let (x0, x1) = (k as f32 / 256.0, (k + 1) as f32 / 256.0);
        text += &format!(
            "Volume \"homogeneous\" \"point p0\" [{x0} -1 -1] \"point p1\" [{x1} 1 1] \
             \"color sigma_a\" [1 1 1]\n"
        );
    }
    text += "Volume \"homogeneous\" \"point p0\" [-1 -1 -1] \"point p1\" [0 1 1] \
             \"color sigma_a\" [1 1 1]\n";
    let (c, w) = columns_with("emission", &text);
    let extra = w
        .iter()
        .filter(|w| w.contains("more than 256 region volumes"))
        .collect::<Vec<_>>();
    assert_eq!(extra.len(), 1, "{w:?}");
    assert!(extra[0].contains(":267:1"), "{}", extra[0]);
    // Depth 2 of sigma_a 1 over x > 0; nothing over x < 0.
    check("the first 256 regions", &c, |i| {
        if i >= RES as usize / 2 {
            (-2.0f64).exp()
        } else {
            1.0
        }
    });
}
