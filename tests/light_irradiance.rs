//! The irradiance the renderer produces under each area primitive (rectangle, disc, sphere,
//! cylinder, and an object: an area light on a mesh) and each falloff exponent k (0, 1, 2),
//! against values computed by hand.
//!
//! How the renderer's irradiance is read: a white matte floor (Kd 1, Lambertian) at z = 0 is
//! lit by one light; an orthographic camera looks at a 1 cm patch around the chosen point
//! (the irradiance is flat there to far better than the tolerance), with the directlighting
//! integrator (light samples and BSDF samples combined by MIS, so a wrong pdf would bias the
//! result). The film's Y is then E/π times the film Y of white: E = π·Y/Y(white).
//!
//! How the expected value is computed: E = ∫ L cosθ_l cosθ_r / d^k dA over the emitting side
//! of the light (the definition of the falloff exponent, see `luxfarm::light::falloff`), by a
//! fine midpoint rule in f64 written here, independent of the renderer. The quadrature is
//! itself checked against closed forms: the rectangle's corner formula and the sphere's
//! πLR²/D² for k = 2, and the disc on its axis for every k
//! (E = πL h²·(2/k)(h^−k − (h²+r²)^−k/2), πL h² ln(1 + r²/h²) at k = 0).

mod render_util;

use luxfarm::render::SessionOptions;
use luxfarm::spectrum::{rgb_to_xyz, Rgb};
use render_util::*;
use std::f64::consts::PI;
use std::path::Path;

/// A point of a light's surface for the quadrature: position, unit normal, area element.
type Element = ([f64; 3], [f64; 3], f64);

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// E at the origin (normal +z) from elements of radiance 1 under falloff exponent k.
fn irradiance(elements: impl Iterator<Item = Element>, k: f64) -> f64 {
    let mut e = 0.0;
    for (p, n, da) in elements {
        let d = dot(p, p).sqrt();
        let to_x = [-p[0] / d, -p[1] / d, -p[2] / d];
        let cos_l = dot(n, to_x);
        let cos_r = p[2] / d;
        if cos_l > 0.0 && cos_r > 0.0 {
            e += cos_l * cos_r / d.powf(k) * da;
        }
    }
    e
}

const N: usize = 600;

/// The rectangle centred at (0, 0, h) with sides a (x) and b (y), facing down.
fn rectangle(a: f64, b: f64, h: f64) -> impl Iterator<Item = Element> {
    (0..N * N).map(move |i| {
        let x = ((i % N) as f64 + 0.5) / N as f64 * a - a / 2.0;
        let y = ((i / N) as f64 + 0.5) / N as f64 * b - b / 2.0;
        ([x, y, h], [0.0, 0.0, -1.0], a * b / (N * N) as f64)
    })
}

/// The disc of radius r centred at (0, 0, h), facing down.
fn disc(r: f64, h: f64) -> impl Iterator<Item = Element> {
    (0..N * N).map(move |i| {
        let rho = ((i % N) as f64 + 0.5) / N as f64 * r;
        let phi = ((i / N) as f64 + 0.5) / N as f64 * 2.0 * PI;
        let da = rho * (r / N as f64) * (2.0 * PI / N as f64);
        ([rho * phi.cos(), rho * phi.sin(), h], [0.0, 0.0, -1.0], da)
    })
}

/// The sphere of radius r centred at (0, 0, h), outward normals.
fn sphere(r: f64, h: f64) -> impl Iterator<Item = Element> {
    (0..N * N).map(move |i| {
        let th = ((i % N) as f64 + 0.5) / N as f64 * PI;
        let phi = ((i / N) as f64 + 0.5) / N as f64 * 2.0 * PI;
        let n = [th.sin() * phi.cos(), th.sin() * phi.sin(), th.cos()];
        let da = r * r * th.sin() * (PI / N as f64) * (2.0 * PI / N as f64);
        ([r * n[0], r * n[1], h + r * n[2]], n, da)
    })
}

/// The side of the cylinder of radius r and length len along y, centred at (0, 0, h).
fn cylinder(r: f64, len: f64, h: f64) -> impl Iterator<Item = Element> {
    (0..N * N).map(move |i| {
        let y = ((i % N) as f64 + 0.5) / N as f64 * len - len / 2.0;
        let phi = ((i / N) as f64 + 0.5) / N as f64 * 2.0 * PI;
        let n = [phi.cos(), 0.0, phi.sin()];
        let da = r * (2.0 * PI / N as f64) * (len / N as f64);
        ([r * n[0], y, h + r * n[2]], n, da)
    })
}

/// Closed form: a rectangle of sides a, b at height h, the point below its centre (k = 2).
fn rectangle_closed(a: f64, b: f64, h: f64) -> f64 {
    let (x, y) = (a / 2.0, b / 2.0);
    let sx = (x * x + h * h).sqrt();
    let sy = (y * y + h * h).sqrt();
    4.0 * 0.5 * (x / sx * (y / sx).atan() + y / sy * (x / sy).atan())
}

/// Closed form: a disc of radius r at height h, on its axis, any k.
fn disc_closed(r: f64, h: f64, k: f64) -> f64 {
    if k == 0.0 {
        PI * h * h * (1.0 + r * r / (h * h)).ln()
    } else {
        PI * h * h * (2.0 / k) * (h.powf(-k) - (h * h + r * r).powf(-k / 2.0))
    }
}

#[test]
fn the_hand_computation_agrees_with_closed_forms() {
    let rel = |a: f64, b: f64| (a - b).abs() / b;
    let q = irradiance(rectangle(0.6, 0.4, 1.0), 2.0);
    assert!(rel(q, rectangle_closed(0.6, 0.4, 1.0)) < 1e-4, "{q}");
    for k in [0.0, 1.0, 2.0, 3.0] {
        let q = irradiance(disc(0.4, 1.0), k);
        assert!(rel(q, disc_closed(0.4, 1.0, k)) < 1e-4, "k {k}: {q}");
    }
    // A Lambertian sphere lights a point facing its centre as a point source would.
    let q = irradiance(sphere(0.3, 1.2), 2.0);
    assert!(rel(q, PI * 0.09 / 1.44) < 1e-3, "{q}");
}

/// The scene: a white matte floor, the light statements `light`, a camera looking at the
/// origin from direction (1, 0, 1).
fn scene(light: &str) -> String {
    format!(
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
    )
}

/// Renders the scene and returns π·Y/Y(white): the irradiance at the origin.
fn rendered_irradiance(light: &str) -> f64 {
    let path = Path::new("/tmp/light_irradiance.lxs");
    let desc = parse_text(&scene(light), path);
    let opts = SessionOptions {
        threads: 2,
        seed: 7,
        stream: 0,
    };
    let film = render(&desc, Path::new("/tmp"), opts, 1);
    let xyz = normalized_xyz(&film);
    let y = xyz.iter().map(|p| p[1]).sum::<f64>() / xyz.len() as f64;
    PI * y / f64::from(rgb_to_xyz(Rgb::WHITE)[1])
}

fn check(name: &str, light: &str, want: f64) {
    let got = rendered_irradiance(light);
    let err = (got - want).abs() / want;
    eprintln!("{name}: rendered {got:.5}, by hand {want:.5}, error {err:.4}");
    assert!(err < 0.015, "{name}: rendered {got}, by hand {want}");
}

const KS: [f64; 3] = [0.0, 1.0, 2.0];

#[test]
fn rectangle_irradiance_for_each_falloff_exponent() {
    for k in KS {
        let light = format!(
            r#"LightSource "rectangle" "point from" [0 0 1] "vector edgeu" [0.6 0 0]
  "vector edgev" [0 -0.4 0] "float falloffexponent" [{k}] "bool visible" ["false"]
  "integer nsamples" [4]"#
        );
        check(
            &format!("rectangle k={k}"),
            &light,
            irradiance(rectangle(0.6, 0.4, 1.0), k),
        );
    }
}

#[test]
fn disc_irradiance_for_each_falloff_exponent() {
    for k in KS {
        let light = format!(
            r#"LightSource "disc" "point from" [0 0 1] "normal normal" [0 0 -1]
  "float radius" [0.4] "float falloffexponent" [{k}] "integer nsamples" [4]"#
        );
        check(&format!("disc k={k}"), &light, disc_closed(0.4, 1.0, k));
    }
}

#[test]
fn sphere_irradiance_for_each_falloff_exponent() {
    for k in KS {
        let light = format!(
            r#"LightSource "sphere" "point from" [0 0 1.2] "float radius" [0.3]
  "float falloffexponent" [{k}] "integer nsamples" [4]"#
        );
        check(
            &format!("sphere k={k}"),
            &light,
            irradiance(sphere(0.3, 1.2), k),
        );
    }
}

#[test]
fn cylinder_irradiance_for_each_falloff_exponent() {
    for k in KS {
        let light = format!(
            r#"LightSource "cylinder" "point from" [0 0 1] "vector axis" [0 1 0]
  "float radius" [0.2] "float falloffexponent" [{k}] "integer nsamples" [8]"#
        );
        check(
            &format!("cylinder k={k}"),
            &light,
            irradiance(cylinder(0.2, 1.0, 1.0), k),
        );
    }
}

#[test]
fn object_light_irradiance_for_each_falloff_exponent() {
    // mental ray's `object` primitive is an area light on an instance's own geometry.
    for k in KS {
        let light = format!(
            r#"AttributeBegin
  AreaLightSource "area" "float power" [0] "color L" [1 1 1] "float falloffexponent" [{k}]
    "integer nsamples" [4]
  Shape "trianglemesh" "point P" [-0.3 -0.2 1  0.3 -0.2 1  0.3 0.2 1  -0.3 0.2 1]
    "integer indices" [0 2 1  0 3 2]
AttributeEnd"#
        );
        check(
            &format!("object k={k}"),
            &light,
            irradiance(rectangle(0.6, 0.4, 1.0), k),
        );
    }
}

#[test]
fn invisible_emitters_still_light_but_the_camera_does_not_see_them() {
    // Looking straight up at a disc light from the floor's height: visible, the camera sees
    // its radiance L = 2; invisible, it sees the black sky; either way it lights the floor.
    let looking_up = |visible: &str| {
        format!(
            r#"LookAt 0 0 0.5  0 0 1  0 1 0
Camera "orthographic" "float screenwindow" [-0.01 0.01 -0.01 0.01]
Film "fleximage" "integer xresolution" [2] "integer yresolution" [2]
Sampler "random" "integer pixelsamples" [4]
SurfaceIntegrator "path" "integer maxdepth" [2]
WorldBegin
LightSource "disc" "point from" [0 0 1] "normal normal" [0 0 -1] "float radius" [0.4]
  "color L" [2 2 2] "bool visible" ["{visible}"]
WorldEnd
"#
        )
    };
    let y = |text: String| {
        let desc = parse_text(&text, Path::new("/tmp/light_visible.lxs"));
        let film = render(&desc, Path::new("/tmp"), SessionOptions::default(), 1);
        let xyz = normalized_xyz(&film);
        xyz.iter().map(|p| p[1]).sum::<f64>() / xyz.len() as f64
    };
    let white = f64::from(rgb_to_xyz(Rgb::WHITE)[1]);
    let seen = y(looking_up("true")) / white;
    assert!((seen - 2.0).abs() < 1e-3, "visible disc: {seen}");
    assert_eq!(y(looking_up("false")), 0.0);
    let lit = rendered_irradiance(
        r#"LightSource "disc" "point from" [0 0 1] "normal normal" [0 0 -1] "float radius" [0.4]
  "bool visible" ["false"] "integer nsamples" [4]"#,
    );
    let want = disc_closed(0.4, 1.0, 2.0);
    assert!((lit - want).abs() < 0.015 * want, "{lit} vs {want}");
}
