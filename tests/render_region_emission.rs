//! Region volumes rendered end to end: their emission `Le`, and several regions at once.
//!
//! - An orthographic camera looks down -z through an emitting homogeneous region 2 units
//!   deep with nothing else in the scene: every pixel sees Le·(1 − e^(−2σa))/σa (Le·2
//!   without absorption), with every volume integrator, in path, directlighting and
//!   bidirectional (which adds it along its eye subpath). The emission along a segment is
//!   computed in closed form, so the image is exact (no noise).
//! - Two overlapping scattering, emitting regions and the three disjoint regions of the same
//!   summed coefficients (the parts covered by one, by both, by the other) render the same
//!   block means within noise: path tracing with multiple scattering, lit by an environment
//!   and by the regions' emission, six independent runs a side compared by z-scores; and
//!   bidirectional renders the overlapping regions as path does (same comparison).

mod transport_common;

use luxfarm::render::setup::Renderable;
use luxfarm::spectrum::{rgb_to_xyz, Rgb};
use std::path::{Path, PathBuf};
use transport_common::*;

fn here() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The camera looking down -z over [-1, 1]² at `res`², `setup` (Sampler, integrators), and
/// `world` between WorldBegin and WorldEnd.
fn scene(res: u32, setup: &str, world: &str) -> String {
    format!(
        "LookAt 0 0 5  0 0 0  0 1 0\n\
         Camera \"orthographic\" \"float screenwindow\" [-1 1 -1 1]\n\
         Film \"fleximage\" \"integer xresolution\" [{res}] \"integer yresolution\" [{res}]\n\
         PixelFilter \"box\"\n{setup}\nWorldBegin\n{world}\nWorldEnd\n"
    )
}

/// Y of every pixel relative to a white of radiance 1.
fn pixels(text: &str) -> Vec<f64> {
    let desc = scene_text(text, &here().join("region_emission.lxs"));
    let white = f64::from(rgb_to_xyz(Rgb::WHITE)[1]);
    luminance(&render(&desc, &here(), 0, 1))
        .into_iter()
        .map(|y| y / white)
        .collect()
}

/// The emitting box: 4 × 4 wide (covering the view, or only x > 0 when `half`), 2 deep.
fn emitter(sigma_a: f32, le: f32, half: bool) -> String {
    let x0 = if half { 0.0 } else { -2.0 };
    format!(
        "Volume \"homogeneous\" \"point p0\" [{x0} -2 -1] \"point p1\" [2 2 1] \
         \"color sigma_a\" [{sigma_a} {sigma_a} {sigma_a}] \"color Le\" [{le} {le} {le}]"
    )
}

/// The emitting box rendered with surface integrator `si` and volume integrator `vi`: every
/// pixel is the closed form, and only the covered columns shine when the box covers x > 0.
fn box_shines_its_closed_form(si: &str, vi: &str) {
    let setup = format!(
        "Sampler \"random\" \"integer pixelsamples\" [2]\n\
         SurfaceIntegrator \"{si}\"\nVolumeIntegrator \"{vi}\""
    );
    for (sigma, le) in [(0.5f32, 0.8f32), (0.0, 0.8), (3.0, 2.0)] {
        let want = if sigma > 0.0 {
            f64::from(le) * (1.0 - (-2.0 * f64::from(sigma)).exp()) / f64::from(sigma)
        } else {
            f64::from(le) * 2.0
        };
        let got = pixels(&scene(8, &setup, &emitter(sigma, le, false)));
        let mean = got.iter().sum::<f64>() / got.len() as f64;
        eprintln!("{si}/{vi} sigma {sigma} Le {le}: mean {mean:.6} vs {want:.6}");
        assert!(
            (mean - want).abs() < 1e-3 * want,
            "{si}/{vi} sigma {sigma}: mean {mean} vs {want}"
        );
        for (i, g) in got.iter().enumerate() {
            assert!(
                (g - want).abs() < 1e-3 * want,
                "{si}/{vi} sigma {sigma}: pixel {i} {g} vs {want}"
            );
        }
    }
    // Only the half x > 0 covered: the other columns stay black.
    let got = pixels(&scene(8, &setup, &emitter(0.5, 0.8, true)));
    let want = 0.8 * (1.0 - (-1.0f64).exp()) / 0.5;
    for (i, g) in got.iter().enumerate() {
        let w = if i % 8 < 4 { 0.0 } else { want };
        assert!(
            (g - w).abs() < 1e-3 * want,
            "{si}/{vi} half: pixel {i} {g} vs {w}"
        );
    }
}

#[test]
fn an_emitting_box_shines_its_closed_form() {
    let setups = [
        ("path", "emission"),
        ("path", "single"),
        ("path", "multi"),
        ("directlighting", "emission"),
        ("directlighting", "single"),
    ];
    for (si, vi) in setups {
        box_shines_its_closed_form(si, vi);
    }
}

/// Bidirectional adds the emission along its eye subpath, with no warning about it.
#[test]
fn bidirectional_renders_region_emission_in_closed_form() {
    for vi in ["emission", "single", "multi"] {
        box_shines_its_closed_form("bidirectional", vi);
    }
    let setup = "SurfaceIntegrator \"bidirectional\"";
    let text = scene(4, setup, &emitter(0.5, 0.8, false));
    let desc = scene_text(&text, Path::new("/tmp/region_bidir.lxs"));
    let warnings: Vec<String> = Renderable::build(&desc, Path::new("/tmp"))
        .expect("scene builds")
        .warnings
        .into_iter()
        .map(|d| d.to_string())
        .collect();
    assert!(warnings.is_empty(), "{warnings:?}");
}

/// The overlapping regions' coefficients: A over x in [-1, 0.5], B over [-0.5, 1] (both
/// −1..1 in y and z).
const A: (&str, &str, &str) = ("0.2 0.3 0.1", "0.8 0.5 0.6", "0.3 0.2 0.1");
const B: (&str, &str, &str) = ("0.1 0.1 0.4", "0.4 0.9 0.5", "0.1 0.3 0.2");
/// A + B.
const AB: (&str, &str, &str) = ("0.3 0.4 0.5", "1.2 1.4 1.1", "0.4 0.5 0.3");

fn region(x0: f32, x1: f32, c: (&str, &str, &str)) -> String {
    format!(
        "Volume \"homogeneous\" \"point p0\" [{x0} -1 -1] \"point p1\" [{x1} 1 1] \
         \"color sigma_a\" [{}] \"color sigma_s\" [{}] \"color Le\" [{}] \"float g\" [0.3]\n",
        c.0, c.1, c.2
    )
}

/// Block means of six runs (streams from `first`) of `world` with surface integrator
/// `integrator` (`path` of depth 8, or bidirectional with subpaths of as many vertices)
/// and multiple scattering.
fn block_runs(integrator: &str, world: &str, first: u64) -> Vec<Vec<f64>> {
    let surface = match integrator {
        "path" => "SurfaceIntegrator \"path\" \"integer maxdepth\" [8]",
        _ => "SurfaceIntegrator \"bidirectional\" \"integer eyedepth\" [9] \"integer lightdepth\" [9]",
    };
    let setup = format!(
        "Sampler \"random\" \"integer pixelsamples\" [8]\n{surface}\nVolumeIntegrator \"multi\""
    );
    let text = scene(16, &setup, world);
    let desc = scene_text(&text, &here().join("region_overlap.lxs"));
    runs(&desc, &here(), first, 6, 1, 4)
}

#[test]
fn overlapping_regions_render_as_their_sums() {
    let env = "LightSource \"infinite\" \"color L\" [0.5 0.5 0.5]\n";
    let overlapping = format!("{env}{}{}", region(-1.0, 0.5, A), region(-0.5, 1.0, B));
    let disjoint = format!(
        "{env}{}{}{}",
        region(-1.0, -0.5, A),
        region(-0.5, 0.5, AB),
        region(0.5, 1.0, B)
    );
    let a = block_runs("path", &overlapping, 0);
    let b = block_runs("path", &disjoint, 100);
    assert_agree("overlapping/disjoint regions", &a, &b, 4.0, 0.0);
    let c = block_runs("bidirectional", &overlapping, 200);
    assert_agree("overlapping regions, bidirectional/path", &c, &a, 4.0, 0.0);
}
