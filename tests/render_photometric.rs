//! The lights of issue 17 in one small scene of our own, rendered end to end through the
//! scene's confined files, with the path tracer and with bidirectional path tracing (which
//! starts light subpaths on each of them): a `sunsky2`, a `point` light with an IES profile
//! (flipped to face down), a `goniometric` light with a lat-long map and a `projection` light
//! throwing a two-colour slide on the floor. Every film is finite, without rejected samples,
//! and lit; no light is refused or left without emission sampling.

mod render_util;
mod transport_common;

use luxfarm::render::{Session, SessionOptions};
use luxfarm::spectrum::{rgb_to_xyz, Rgb};
use render_util::*;

const IES: &str = "IESNA:LM-63-2002\n[TEST] downlight\nTILT=NONE\n1 1000 1 3 1 1 2 0.1 0.1 0\n\
1.0 1.0 20\n0 45 90\n0\n800 500 0\n";

fn scene(integrator: &str) -> String {
    format!(
        r#"
LookAt 0 -5 3  0 0 0.3  0 0 1
Camera "perspective" "float fov" [60]
Film "fleximage" "integer xresolution" [32] "integer yresolution" [24]
PixelFilter "box"
Sampler "random" "integer pixelsamples" [4]
SurfaceIntegrator "{integrator}"
WorldBegin
AttributeBegin
LightSource "sunsky2" "vector sundir" [0.3 0.2 0.9] "float turbidity" [3] "float gain" [0.0002]
AttributeEnd
AttributeBegin
Translate -1 0 2
LightSource "point" "string iesname" ["lamp.ies"] "bool flipz" ["true"] "float gain" [0.01]
AttributeEnd
AttributeBegin
Translate 1 1 1.5
LightSource "goniometric" "string mapname" ["gonio.png"] "float gain" [0.5]
AttributeEnd
AttributeBegin
Translate 1 -1 2
Rotate 180 1 0 0
LightSource "projection" "string mapname" ["slide.png"] "float fov" [40] "float gain" [2]
AttributeEnd
Material "matte" "color Kd" [0.6 0.6 0.6]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point P" [-4 -4 0 4 -4 0 4 4 0 -4 4 0]
WorldEnd
"#
    )
}

fn write_files(dir: &std::path::Path) {
    std::fs::write(dir.join("lamp.ies"), IES).unwrap();
    let slide = image::RgbImage::from_fn(4, 2, |x, _| {
        if x < 2 {
            image::Rgb([255, 40, 40])
        } else {
            image::Rgb([40, 40, 255])
        }
    });
    slide.save(dir.join("slide.png")).unwrap();
    let gonio = image::RgbImage::from_fn(8, 4, |_, y| image::Rgb([200, 200, (60 * y) as u8]));
    gonio.save(dir.join("gonio.png")).unwrap();
}

#[test]
fn photometric_lights_render_with_path_and_bidirectional() {
    let dir = tempfile::tempdir().unwrap();
    write_files(dir.path());
    for integrator in ["path", "bidirectional"] {
        let path = dir.path().join("lights.lxs");
        let desc = parse_text(&scene(integrator), &path);
        let opts = SessionOptions {
            threads: 2,
            seed: 3,
            stream: 0,
        };
        let mut s = Session::new(&desc, dir.path(), opts).expect("scene builds");
        let lights = s.renderable().world.lights().len();
        assert_eq!(lights, 5, "sun, sky2, point, goniometric, projection");
        let warnings: Vec<String> = s.warnings().iter().map(|w| w.to_string()).collect();
        assert!(
            !warnings.iter().any(|w| w.contains("bidirectional")),
            "{integrator}: {warnings:?}"
        );
        let stats = s.render_pass();
        assert!(stats.complete);
        assert_eq!(stats.rejected, 0, "{integrator}: NaN/Inf/negative samples");
        let film = s.take_film();
        let xyz = normalized_xyz(&film);
        assert!(xyz.iter().flatten().all(|v| v.is_finite() && *v >= 0.0));
        let lit = xyz.iter().filter(|p| p[1] > 0.0).count();
        assert!(lit > xyz.len() * 9 / 10, "{integrator}: {lit} lit pixels");
    }
}

/// The irradiance at the origin of a white matte floor (Kd 1) lit by `light`, read as
/// `tests/light_irradiance.rs` reads it: an orthographic camera on a 1 cm patch, the
/// directlighting integrator (light and BSDF samples under MIS), E = π·Y/Y(white).
fn irradiance_at_origin(light: &str, dir: &std::path::Path) -> f64 {
    let text = format!(
        r#"LookAt 5 0 5  0 0 0  0 0 1
Camera "orthographic" "float screenwindow" [-0.005 0.005 -0.005 0.005]
Film "fleximage" "integer xresolution" [4] "integer yresolution" [4]
PixelFilter "box"
Sampler "random" "integer pixelsamples" [64]
SurfaceIntegrator "directlighting" "string lightstrategy" ["all"] "integer maxdepth" [0]
WorldBegin
Material "matte" "color Kd" [1 1 1]
Shape "trianglemesh" "point P" [-10 -10 0  10 -10 0  10 10 0  -10 10 0] "integer indices" [0 1 2 0 2 3]
{light}
WorldEnd
"#
    );
    let desc = parse_text(&text, &dir.join("ies.lxs"));
    let opts = SessionOptions {
        threads: 2,
        seed: 5,
        stream: 0,
    };
    let film = render(&desc, dir, opts, 1);
    let xyz = normalized_xyz(&film);
    let y = xyz.iter().map(|p| p[1]).sum::<f64>() / xyz.len() as f64;
    std::f64::consts::PI * y / f64::from(rgb_to_xyz(Rgb::WHITE)[1])
}

/// The test profile's candela at vertical angle `v` degrees from nadir (800 at 0°, 500 at
/// 45°, 0 at 90°, linear between, nothing beyond 90°).
fn candela(v: f64) -> f64 {
    if v <= 45.0 {
        800.0 - 300.0 * v / 45.0
    } else if v <= 90.0 {
        500.0 * (90.0 - v) / 45.0
    } else {
        0.0
    }
}

fn assert_close(what: &str, got: f64, want: f64, tol: f64) {
    let err = (got - want).abs() / want;
    eprintln!("{what}: rendered {got:.4}, by hand {want:.4}, error {err:.4}");
    assert!(err < tol, "{what}: rendered {got}, by hand {want}");
}

/// A spot with an IES profile: on its axis the floor gets candela(0°)/d² = 800/4; 22.5° off
/// the axis (inside the 60° cone, past no falloff) candela(22.5°)·cos³/h² = 650·cos³(22.5°)/4;
/// with `flipz` the profile's nadir points back up and the axis gets nothing.
#[test]
fn ies_spot_light_irradiance_by_hand() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("lamp.ies"), IES).unwrap();
    let spot = |x: f64, extra: &str| {
        format!(
            "LightSource \"spot\" \"string iesname\" [\"lamp.ies\"] \"float coneangle\" [60] \
             \"point from\" [{x} 0 2] \"point to\" [{x} 0 0] {extra}"
        )
    };
    let on_axis = irradiance_at_origin(&spot(0.0, ""), dir.path());
    assert_close("spot on axis", on_axis, 800.0 / 4.0, 0.01);
    let a = 22.5f64.to_radians();
    let off = irradiance_at_origin(&spot(2.0 * a.tan(), ""), dir.path());
    assert_close(
        "spot 22.5° off axis",
        off,
        candela(22.5) * a.cos().powi(3) / 4.0,
        0.01,
    );
    let flipped = irradiance_at_origin(&spot(0.0, "\"bool flipz\" [\"true\"]"), dir.path());
    assert!(
        flipped.abs() < 1e-9,
        "flipped profile lights the axis: {flipped}"
    );
}

/// An area light with an IES profile (LuxRender's radiance L·π·f(ω)/∫f dω along the
/// leaving direction in the surface's frame): a 2 cm square at height 1 facing down, its
/// profile's nadir along the normal, gives E ≈ π·800/∫f × a²/h²; facing up, the floor sits
/// beyond the profile's 90° and gets nothing.
#[test]
fn ies_area_light_irradiance_by_hand() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("lamp.ies"), IES).unwrap();
    // ∫ f dω = 2π ∫ f(θ) sin θ dθ over 0..90°, midpoint rule.
    let n = 100_000;
    let integral: f64 = (0..n)
        .map(|i| {
            let t = (i as f64 + 0.5) / n as f64 * std::f64::consts::FRAC_PI_2;
            candela(t.to_degrees()) * t.sin()
        })
        .sum::<f64>()
        * std::f64::consts::FRAC_PI_2
        / n as f64
        * 2.0
        * std::f64::consts::PI;
    let a = 0.02f64;
    let square = |winding: &str| {
        format!(
            "AttributeBegin\nAreaLightSource \"area\" \"string iesname\" [\"lamp.ies\"] \
             \"float power\" [0]\nShape \"trianglemesh\" \"integer indices\" [{winding}] \
             \"point P\" [-0.01 -0.01 1  0.01 -0.01 1  0.01 0.01 1  -0.01 0.01 1]\nAttributeEnd"
        )
    };
    // Counter-clockwise seen from above is +z: reversed winding faces down.
    let down = irradiance_at_origin(&square("0 2 1 0 3 2"), dir.path());
    let want = std::f64::consts::PI * 800.0 / integral * a * a;
    assert_close("IES area light facing down", down, want, 0.015);
    let up = irradiance_at_origin(&square("0 1 2 0 2 3"), dir.path());
    assert!(up < want * 1e-3, "facing up: {up}");
}

/// Bidirectional path tracing starts light subpaths on an IES spot and an IES area light
/// (directions drawn from the profiles) and connects them: its image agrees with the path
/// tracer's (8-pixel block means of independent renders within the noise).
#[test]
fn ies_spot_and_area_lights_agree_between_path_and_bidirectional() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("lamp.ies"), IES).unwrap();
    let text = |integrator: &str| {
        format!(
            r#"LookAt 0 -4 2.5  0 0 0.5  0 0 1
Camera "perspective" "float fov" [60]
Film "fleximage" "integer xresolution" [24] "integer yresolution" [24]
PixelFilter "box"
Sampler "random" "integer pixelsamples" [8]
SurfaceIntegrator {integrator}
WorldBegin
LightSource "spot" "string iesname" ["lamp.ies"] "float coneangle" [50] "point from" [-0.8 0 2] "point to" [-0.5 0 0] "float gain" [0.002]
AttributeBegin
AreaLightSource "area" "string iesname" ["lamp.ies"] "float power" [0] "float gain" [4]
Shape "trianglemesh" "integer indices" [0 2 1 0 3 2] "point P" [0.6 -0.2 1.5  1.0 -0.2 1.5  1.0 0.2 1.5  0.6 0.2 1.5]
AttributeEnd
Material "matte" "color Kd" [0.7 0.7 0.7]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point P" [-3 -3 0  3 -3 0  3 3 0  -3 3 0]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point P" [-3 2 0  3 2 0  3 2 3  -3 2 3]
WorldEnd
"#
        )
    };
    let runs = |integrator: &str, first: u64| -> Vec<Vec<f64>> {
        let desc = parse_text(&text(integrator), &dir.path().join("ies.lxs"));
        (first..first + 6)
            .map(|stream| {
                let opts = SessionOptions {
                    threads: 2,
                    seed: 9,
                    stream,
                };
                let film = render(&desc, dir.path(), opts, 1);
                transport_common::block_means(&film, 8)
            })
            .collect()
    };
    let path = runs("\"path\" \"integer maxdepth\" [5]", 0);
    let bidir = runs(
        "\"bidirectional\" \"integer eyedepth\" [5] \"integer lightdepth\" [5]",
        100,
    );
    transport_common::assert_agree("IES lights: path vs bidirectional", &path, &bidir, 4.0, 0.0);
}

/// The scene-format document names the colour of point, spot, goniometric and projection
/// lights `I`; LuxRender 1.x reads `L`. `I` counts when there is no `L`, and `L` wins over it.
#[test]
fn a_point_light_takes_its_colour_from_i_when_l_is_absent() {
    let dir = tempfile::tempdir().expect("temp dir");
    let at = |params: &str| {
        irradiance_at_origin(
            &format!(
                "AttributeBegin\nTranslate 0 0 1\nLightSource \"point\" {params}\nAttributeEnd"
            ),
            dir.path(),
        )
    };
    let white = at("");
    assert_close("I = 3", at("\"color I\" [3 3 3]"), 3.0 * white, 0.01);
    assert_close(
        "L beside I",
        at("\"color L\" [1 1 1] \"color I\" [3 3 3]"),
        white,
        0.01,
    );
}
