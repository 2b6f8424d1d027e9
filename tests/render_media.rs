//! Participating media rendered end to end (path integrator), against values known in
//! closed form:
//!
//! - Beer–Lambert: a camera looks through the centre of a null-material sphere of radius R
//!   filled with an absorbing medium (`clear` absorption a, or `homogeneous` sigma_a a
//!   without scattering) at a constant environment; the radiance is exp(-2aR) times the
//!   environment's, per channel.
//! - White furnace: a sphere filled with a medium of albedo 1 (sigma_a 0, sigma_s > 0, with
//!   and without anisotropy) under a constant environment of radiance 1 with the `multi` volume
//!   integrator: in a uniform radiance field scattering neither adds nor removes light, so
//!   every pixel stays at the environment's radiance.
//! - Without media the scene renders exactly as before (a named medium that nothing
//!   references, or a vacuum one, changes nothing), and the media statements leave no
//!   "ignored" warning.

mod render_util;

use luxfarm::render::setup::Renderable;
use luxfarm::render::SessionOptions;
use luxfarm::spectrum::{rgb_to_xyz, Rgb};
use render_util::*;
use std::path::Path;

const R: f64 = 0.8;

/// A sphere of radius R at the origin, seen by an orthographic camera through its centre
/// region, under a constant environment of radiance 1; `world` goes inside WorldBegin before
/// the sphere, `shape_attrs` on the sphere.
fn scene(volume_integrator: &str, world: &str, shape_attrs: &str, spp: u32) -> String {
    format!(
        r#"LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [-0.02 0.02 -0.02 0.02]
Film "fleximage" "integer xresolution" [4] "integer yresolution" [4]
PixelFilter "box"
Sampler "random" "integer pixelsamples" [{spp}]
SurfaceIntegrator "path" "integer maxdepth" [256]
{volume_integrator}
WorldBegin
LightSource "infinite" "color L" [1 1 1]
{world}
AttributeBegin
Material "null"
{shape_attrs}
Shape "sphere" "float radius" [{R}]
AttributeEnd
WorldEnd
"#
    )
}

/// Mean weight-normalised XYZ over the film, and the render's warnings.
fn render_mean(text: &str) -> ([f64; 3], Vec<String>) {
    let path = Path::new("/tmp/render_media.lxs");
    let desc = parse_text(text, path);
    let warnings = Renderable::build(&desc, Path::new("/tmp"))
        .expect("scene builds")
        .warnings
        .into_iter()
        .map(|d| d.message)
        .collect();
    let opts = SessionOptions {
        threads: 2,
        seed: 11,
        stream: 0,
    };
    let film = render(&desc, Path::new("/tmp"), opts, 1);
    let xyz = normalized_xyz(&film);
    let mut m = [0.0; 3];
    for p in &xyz {
        for (acc, v) in m.iter_mut().zip(p) {
            *acc += v / xyz.len() as f64;
        }
    }
    (m, warnings)
}

fn white_xyz() -> [f64; 3] {
    rgb_to_xyz(Rgb::WHITE).map(f64::from)
}

fn check_ratio(name: &str, got: [f64; 3], want: f64, tol: f64) {
    let w = white_xyz();
    for (c, (g, wc)) in got.iter().zip(w).enumerate() {
        let ratio = g / wc;
        eprintln!("{name}: channel {c}: {ratio:.5}, expected {want:.5}");
        assert!(
            (ratio - want).abs() <= tol * want.max(1e-3),
            "{name}: channel {c}: {ratio} vs {want}"
        );
    }
}

#[test]
fn absorbing_sphere_follows_beer_lambert() {
    for (kind, param) in [("clear", "absorption"), ("homogeneous", "sigma_a")] {
        for a in [0.3, 1.2] {
            let world = format!(r#"MakeNamedVolume "ink" "{kind}" "color {param}" [{a} {a} {a}]"#);
            let text = scene(
                r#"VolumeIntegrator "multi""#,
                &world,
                r#"Interior "ink""#,
                4,
            );
            let (m, warnings) = render_mean(&text);
            assert!(
                !warnings.iter().any(|w| w.contains("ignored")),
                "{warnings:?}"
            );
            // The pixels cover |x|, |y| < 0.02: the chord differs from 2R by < 0.1 %.
            check_ratio(kind, m, (-2.0 * a * R).exp(), 0.01);
        }
    }
}

#[test]
fn absorption_is_per_channel() {
    let world = r#"MakeNamedVolume "ink" "clear" "color absorption" [0 3 0]"#;
    let text = scene("", world, r#"Interior "ink""#, 1);
    let (m, _) = render_mean(&text);
    // Green is absorbed (exp(-4.8) ≈ 0.008): the luminance drops well below white's, and the
    // colour leans to magenta (X and Z keep more than Y).
    let w = white_xyz();
    assert!(m[1] / w[1] < 0.5, "{m:?}");
    assert!(m[2] / w[2] > m[1] / w[1], "{m:?}");
}

#[test]
fn scattering_medium_of_albedo_one_conserves_energy_in_a_white_furnace() {
    for g in [0.0, 0.6] {
        let world = format!(
            r#"MakeNamedVolume "fog" "homogeneous" "color sigma_a" [0 0 0] "color sigma_s" [2 2 2] "float g" [{g}]"#
        );
        let text = scene(
            r#"VolumeIntegrator "multi""#,
            &world,
            r#"Interior "fog""#,
            256,
        );
        let (m, _) = render_mean(&text);
        check_ratio(&format!("furnace g={g}"), m, 1.0, 0.03);
    }
}

#[test]
fn emission_integrator_only_attenuates() {
    // With "emission" (LuxRender's default) the fog only absorbs: exp(-sigma_t·2R).
    let world =
        r#"MakeNamedVolume "fog" "homogeneous" "color sigma_a" [0 0 0] "color sigma_s" [1 1 1]"#;
    let text = scene(
        r#"VolumeIntegrator "emission""#,
        world,
        r#"Interior "fog""#,
        1,
    );
    let (m, _) = render_mean(&text);
    check_ratio("emission", m, (-2.0 * R).exp(), 0.01);
    // With "none" the medium is dropped.
    let text = scene(r#"VolumeIntegrator "none""#, world, r#"Interior "fog""#, 1);
    let (m, _) = render_mean(&text);
    check_ratio("none", m, 1.0, 0.01);
}

#[test]
fn vacuum_media_render_as_no_media() {
    // Clear, homogeneous, heterogeneous and exponential media whose coefficients are all
    // zero: no medium is built, so not even the marching of the last two costs anything.
    let vacua = [
        r#""clear" "float fresnel" [1] "color absorption" [0 0 0]"#,
        r#""homogeneous" "color sigma_a" [0 0 0] "color sigma_s" [0 0 0]"#,
        r#""heterogeneous" "color sigma_a" [0 0 0] "color sigma_s" [0 0 0] "float stepsize" [0.05]"#,
        r#""exponential" "color sigma_a" [0 0 0] "color sigma_s" [0 0 0] "float stepsize" [0.05]"#,
    ];
    let without = scene("", "", "", 2);
    let (b, _) = render_mean(&without);
    for v in vacua {
        let world = format!(r#"MakeNamedVolume "world" {v}"#);
        let with = scene(
            r#"VolumeIntegrator "multi""#,
            &world,
            r#"Exterior "world""#,
            2,
        );
        let (a, wa) = render_mean(&with);
        assert_eq!(a, b, "{v}");
        assert!(wa.is_empty(), "{v}: {wa:?}");
        let r = Renderable::build(
            &parse_text(&with, Path::new("/tmp/vacuum.lxs")),
            Path::new("/tmp"),
        )
        .expect("builds");
        assert!(r.world.media().is_none(), "{v}: a medium was built");
    }
}

#[test]
fn glass_transmission_enters_and_leaves_the_interior_medium() {
    // Glass of index 1 neither reflects nor bends: the ray enters the medium through the
    // BSDF's transmission and leaves it the same way.
    let world = r#"MakeNamedVolume "ink" "clear" "color absorption" [0.5 0.5 0.5]"#;
    let text = scene(r#"VolumeIntegrator "multi""#, world, r#"Interior "ink""#, 2).replace(
        r#"Material "null""#,
        r#"Material "glass" "float index" [1.0]"#,
    );
    let (m, _) = render_mean(&text);
    check_ratio("glass", m, (-2.0 * 0.5 * R).exp(), 0.01);
}

#[test]
fn bad_medium_parameters_are_located_errors() {
    let world = r#"MakeNamedVolume "ink" "homogeneous" "color sigma_a" [-1 0 0]"#;
    let text = scene("", world, r#"Interior "ink""#, 1);
    let desc = parse_text(&text, Path::new("/tmp/render_media.lxs"));
    let err = match Renderable::build(&desc, Path::new("/tmp")) {
        Ok(_) => panic!("a negative sigma_a must not build"),
        Err(e) => e.to_string(),
    };
    assert!(err.contains("render_media.lxs:10:"), "{err}");
    assert!(err.contains("sigma_a"), "{err}");
    let text = scene("", r#"MakeNamedVolume "ink" "fog""#, r#"Interior "ink""#, 1);
    let desc = parse_text(&text, Path::new("/tmp/render_media.lxs"));
    let err = Renderable::build(&desc, Path::new("/tmp"))
        .err()
        .map(|e| e.to_string());
    assert!(
        err.as_deref()
            .is_some_and(|e| e.contains(":10:") && e.contains("unknown volume")),
        "{err:?}"
    );
}
