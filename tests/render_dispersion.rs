//! Dispersion end to end: a glass prism with `cauchyb` > 0 splits white light, one with
//! cauchyb = 0 does not and renders exactly as before (the scene stays RGB). The
//! non-dispersive prism has the dispersive one's index at 550 nm (1.665), so both see the strip.
//!
//! The setup: an orthographic camera looks down -z through a glass prism (a triangular
//! cross-section in x-z, extruded along y) at a narrow white emitting strip below it. Camera
//! rays refract at the prism's slanted face and its flat bottom and reach the plane of the
//! strip displaced along x by an amount that grows with the index; with n(λ) = index +
//! cauchyb/λ² blue light (higher index) is bent more than red, so the pixels that see the strip
//! in red and those that see it in blue differ. Per image column the film's X (long
//! wavelengths dominate it) and Z (short wavelengths) give two centroids along x: they differ
//! by several pixels with dispersion and coincide without. A dispersive glass inside a `mix`
//! material disperses as well.

mod render_util;

use luxfarm::film::Film;
use luxfarm::render::setup::Renderable;
use luxfarm::render::SessionOptions;
use render_util::*;
use std::path::Path;

const W: u32 = 96;

fn scene(glass: &str) -> String {
    scene_with(&format!(
        r#"MakeNamedMaterial "prism" "string type" ["glass"] {glass}"#
    ))
}

/// The scene with `materials` defining the named material "prism".
fn scene_with(materials: &str) -> String {
    // Prism: A(-1, z=0), B(1, 0), C(0, 1), y in [-2, 2]; outward normals by the right-hand rule.
    format!(
        r#"LookAt -0.5 0 5  -0.5 0 0  0 1 0
Camera "orthographic" "float screenwindow" [-0.45 0.45 -0.01875 0.01875]
Film "fleximage" "integer xresolution" [{W}] "integer yresolution" [4]
PixelFilter "box"
Sampler "random" "integer pixelsamples" [64]
SurfaceIntegrator "path" "integer maxdepth" [8]
WorldBegin
AttributeBegin
{materials}
NamedMaterial "prism"
Shape "trianglemesh" "point P" [-1 -2 0  1 -2 0  0 -2 1   -1 2 0  1 2 0  0 2 1]
  "integer indices" [0 1 2  3 5 4  0 4 1  0 3 4  1 5 2  1 4 5  2 3 0  2 5 3]
AttributeEnd
AttributeBegin
AreaLightSource "area" "color L" [1 1 1]
Shape "trianglemesh" "point P" [1.7 -3 -3  2.0 -3 -3  2.0 3 -3  1.7 3 -3]
  "integer indices" [0 1 2  0 2 3]
AttributeEnd
WorldEnd
"#
    )
}

fn render_scene(glass: &str) -> (Film, bool) {
    render_text(&scene(glass))
}

fn render_text(text: &str) -> (Film, bool) {
    let path = Path::new("/tmp/render_dispersion.lxs");
    let desc = parse_text(text, path);
    let spectral = Renderable::build(&desc, Path::new("/tmp"))
        .expect("scene builds")
        .world
        .spectral();
    let opts = SessionOptions {
        threads: 2,
        seed: 5,
        stream: 0,
    };
    (render(&desc, Path::new("/tmp"), opts, 1), spectral)
}

#[test]
fn a_dispersive_prism_separates_red_from_blue() {
    let (film, spectral) = render_scene(r#""float index" [1.5] "float cauchyb" [0.05]"#);
    assert!(spectral, "cauchyb > 0 switches the scene to spectral paths");
    let (cx, cz, total) = centroids(&film);
    eprintln!("cauchyb 0.05: X centroid {cx:.2} px, Z centroid {cz:.2} px (total {total:.3})");
    assert!(total > 0.0, "the strip is seen through the prism");
    assert!((cx - cz).abs() > 4.0, "X at {cx}, Z at {cz}");
}

/// A dispersive glass inside a `mix` (as exporters write glass blended with another
/// material) still makes the scene spectral and still splits the light: the hit's dispersion
/// is that of the component the mix picks.
#[test]
fn a_dispersive_glass_inside_a_mix_separates_red_from_blue() {
    let (film, spectral) = render_text(&scene_with(
        r#"MakeNamedMaterial "flint" "string type" ["glass"] "float index" [1.5] "float cauchyb" [0.05]
MakeNamedMaterial "crown" "string type" ["glass"] "float index" [1.5] "float cauchyb" [0.05]
MakeNamedMaterial "prism" "string type" ["mix"] "string namedmaterial1" ["flint"]
  "string namedmaterial2" ["crown"] "float amount" [0.5]"#,
    ));
    assert!(
        spectral,
        "a mix with a dispersive component switches to spectral paths"
    );
    let (cx, cz, total) = centroids(&film);
    eprintln!("mix of cauchyb 0.05 glasses: X centroid {cx:.2} px, Z centroid {cz:.2} px");
    assert!(total > 0.0, "the strip is seen through the prism");
    assert!((cx - cz).abs() > 4.0, "X at {cx}, Z at {cz}");
}

#[test]
fn without_dispersion_the_colours_coincide_and_the_scene_stays_rgb() {
    let (zero, spectral) = render_scene(r#""float index" [1.665] "float cauchyb" [0]"#);
    assert!(!spectral);
    let (plain, _) = render_scene(r#""float index" [1.665]"#);
    assert_eq!(normalized_xyz(&zero), normalized_xyz(&plain));
    let (cx, cz, total) = centroids(&zero);
    eprintln!("cauchyb 0: X centroid {cx:.2} px, Z centroid {cz:.2} px (total {total:.3})");
    assert!(total > 0.0, "the strip is seen through the prism");
    assert!((cx - cz).abs() < 0.5, "X at {cx}, Z at {cz}");
}

#[test]
fn index_at_550_nm_is_luxrenders() {
    // The TestSuite's dispersion scenes: index 1.5, cauchyb 0.05 → 1.665 at 550 nm.
    let n = 1.5 + luxfarm::material::glass::cauchy_shift(0.05, 550.0);
    assert!((n - 1.6653).abs() < 1e-3, "{n}");
}
