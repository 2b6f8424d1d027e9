//! glass2 end to end: its index comes from the `fresnel` of the shape's Interior volume, a
//! float or a fresnel texture; with `dispersion` and a wavelength-dependent texture it splits
//! white light as glass with the same Cauchy coefficients does. Also the scene errors and
//! warnings around it, and the documentation's `cauchyB` spelling of glass's `cauchyb`.
//!
//! The prism setup is `render_dispersion.rs`'s: an orthographic camera looks down -z through a
//! glass prism at a narrow white emitting strip; the X and Z centroids of the film along x
//! tell where red and blue light pass.

mod render_util;

use luxfarm::film::Film;
use luxfarm::render::setup::Renderable;
use luxfarm::render::SessionOptions;
use render_util::*;
use std::path::Path;

const W: u32 = 96;

/// The prism scene: `defs` before the prism (textures, volumes), `prism` its material
/// statement and `inside` what precedes its shape (an Interior).
fn scene(defs: &str, prism: &str, inside: &str) -> String {
    format!(
        r#"LookAt -0.5 0 5  -0.5 0 0  0 1 0
Camera "orthographic" "float screenwindow" [-0.45 0.45 -0.01875 0.01875]
Film "fleximage" "integer xresolution" [{W}] "integer yresolution" [4]
PixelFilter "box"
Sampler "random" "integer pixelsamples" [64]
SurfaceIntegrator "path" "integer maxdepth" [8]
WorldBegin
{defs}
AttributeBegin
{prism}
{inside}
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

/// A glass2 prism inside the volume "v" defined by `defs`.
fn glass2_scene(defs: &str, dispersion: bool) -> String {
    scene(
        defs,
        &format!(r#"Material "glass2" "bool dispersion" ["{dispersion}"]"#),
        r#"Interior "v""#,
    )
}

const PATH: &str = "/tmp/render_glass2.lxs";

fn build(text: &str) -> Result<Renderable, String> {
    let desc = parse_text(text, Path::new(PATH));
    Renderable::build(&desc, Path::new("/tmp")).map_err(|e| e.to_string())
}

/// The film, whether the scene renders spectrally, and the build warnings.
fn render_scene(text: &str) -> (Film, bool, Vec<String>) {
    let built = build(text).expect("scene builds");
    let warnings = built.warnings.iter().map(|w| w.to_string()).collect();
    let opts = SessionOptions {
        threads: 2,
        seed: 5,
        stream: 0,
    };
    let desc = parse_text(text, Path::new(PATH));
    let film = render(&desc, Path::new("/tmp"), opts, 1);
    (film, built.world.spectral(), warnings)
}

const CAUCHY: &str =
    r#"Texture "ct" "fresnel" "cauchy" "float cauchya" [1.5] "float cauchyb" [0.05]"#;

#[test]
fn a_cauchy_texture_of_constant_index_renders_as_the_float_index() {
    let float = r#"MakeNamedVolume "v" "clear" "float fresnel" [1.665]"#;
    let (a, spectral_a, _) = render_scene(&glass2_scene(float, false));
    let tex = r#"Texture "c0" "fresnel" "cauchy" "float cauchya" [1.665] "float cauchyb" [0]
MakeNamedVolume "v" "clear" "texture fresnel" ["c0"]"#;
    let (b, spectral_b, warnings) = render_scene(&glass2_scene(tex, false));
    assert!(
        !spectral_a && !spectral_b,
        "no dispersion: the scene stays RGB"
    );
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(normalized_xyz(&a), normalized_xyz(&b));
    let (cx, cz, total) = centroids(&b);
    assert!(total > 0.0, "the strip is seen through the prism");
    assert!((cx - cz).abs() < 0.5, "X at {cx}, Z at {cz}");
    // dispersion on a constant index: no effect, a located warning.
    let (c, spectral_c, warnings) = render_scene(&glass2_scene(tex, true));
    assert!(!spectral_c);
    assert_eq!(normalized_xyz(&a), normalized_xyz(&c));
    assert!(
        warnings
            .iter()
            .any(|w| w.contains(PATH) && w.contains("dispersion\" has no effect")),
        "{warnings:?}"
    );
}

#[test]
fn a_dispersive_texture_without_dispersion_uses_the_mean_index_in_rgb() {
    let defs = format!("{CAUCHY}\nMakeNamedVolume \"v\" \"clear\" \"texture fresnel\" [\"ct\"]");
    let (film, spectral, warnings) = render_scene(&glass2_scene(&defs, false));
    assert!(!spectral, "without dispersion the scene stays RGB");
    assert!(warnings.is_empty(), "{warnings:?}");
    let (cx, cz, total) = centroids(&film);
    assert!(total > 0.0);
    assert!((cx - cz).abs() < 0.5, "X at {cx}, Z at {cz}");
}

#[test]
fn glass2_dispersion_puts_red_and_blue_where_glass_cauchyb_does() {
    let glass = scene(
        "",
        r#"Material "glass" "float index" [1.5] "float cauchyb" [0.05]"#,
        "",
    );
    let (g, spectral_g, _) = render_scene(&glass);
    let defs = format!("{CAUCHY}\nMakeNamedVolume \"v\" \"clear\" \"texture fresnel\" [\"ct\"]");
    let (g2, spectral_g2, warnings) = render_scene(&glass2_scene(&defs, true));
    assert!(spectral_g && spectral_g2, "both disperse: spectral paths");
    assert!(warnings.is_empty(), "{warnings:?}");
    let (gx, gz, gt) = centroids(&g);
    let (x2, z2, t2) = centroids(&g2);
    eprintln!("glass cauchyb: X {gx:.2} Z {gz:.2}; glass2 cauchy volume: X {x2:.2} Z {z2:.2}");
    assert!(gt > 0.0 && t2 > 0.0);
    assert!(
        (x2 - z2).abs() > 4.0,
        "glass2 separates red from blue: X {x2}, Z {z2}"
    );
    assert!((gx - x2).abs() < 0.5, "red: glass {gx}, glass2 {x2}");
    assert!((gz - z2).abs() < 0.5, "blue: glass {gz}, glass2 {z2}");
}

#[test]
fn a_missing_or_wrong_fresnel_texture_is_a_located_error() {
    let missing = r#"MakeNamedVolume "v" "clear" "texture fresnel" ["nope"]"#;
    let e = build(&glass2_scene(missing, false)).err().expect("refused");
    assert!(e.contains(&format!("{PATH}:")), "{e}");
    assert!(e.contains("no fresnel texture named \"nope\""), "{e}");
    let wrong = r#"Texture "f" "float" "constant" "float value" [1.5]
MakeNamedVolume "v" "clear" "texture fresnel" ["f"]"#;
    let e = build(&glass2_scene(wrong, false)).err().expect("refused");
    assert!(e.contains(&format!("{PATH}:")), "{e}");
    assert!(e.contains("\"f\" is a float texture"), "{e}");
    let bad = r#"MakeNamedVolume "v" "clear" "float fresnel" [-1]"#;
    let e = build(&glass2_scene(bad, false)).err().expect("refused");
    assert!(
        e.contains(&format!("{PATH}:")) && e.contains("positive index"),
        "{e}"
    );
}

#[test]
fn cauchy_capital_b_reads_as_cauchyb_with_a_warning() {
    let upper = scene(
        "",
        r#"Material "glass" "float index" [1.5] "float cauchyB" [0.05]"#,
        "",
    );
    let built = build(&upper).expect("builds");
    assert!(built.world.spectral(), "cauchyB disperses");
    let w: Vec<String> = built.warnings.iter().map(|w| w.to_string()).collect();
    assert!(
        w.iter()
            .any(|w| w.contains(PATH) && w.contains("\"cauchyB\" is read as \"cauchyb\"")),
        "{w:?}"
    );
    assert!(!w.iter().any(|w| w.contains("unused")), "{w:?}");
    // Both spellings: LuxRender's wins.
    let both = scene(
        "",
        r#"Material "roughglass" "float cauchyb" [0] "float cauchyB" [0.05]"#,
        "",
    );
    let built = build(&both).expect("builds");
    assert!(!built.world.spectral(), "cauchyb 0 wins");
    let w: Vec<String> = built.warnings.iter().map(|w| w.to_string()).collect();
    assert!(
        w.iter()
            .any(|w| w.contains(PATH) && w.contains("\"cauchyB\" is ignored")),
        "{w:?}"
    );
    assert!(!w.iter().any(|w| w.contains("unused")), "{w:?}");
}
