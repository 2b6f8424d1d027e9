//! The path integrator's `maxdepth`, as LuxRender 1.x counts it: light is sampled at path
//! vertices 0..maxdepth-1 (vertex 0 is the camera ray's hit), and emission is still picked up
//! at vertex `maxdepth` after a specular bounce, which light sampling cannot reach. So a light
//! seen in a mirror shows at maxdepth 1, and a diffuse wall lit directly shows at maxdepth 1
//! and light bounced off another surface back to it at maxdepth 3.

mod render_util;

use luxfarm::render::SessionOptions;
use render_util::*;
use std::path::Path;

/// A camera at the origin looking down +y at a wall at y = 2 (a mirror or a matte white
/// wall); behind the camera, at y = -1, a 12 × 12 area light facing the wall (large, yet
/// small enough that sampling it by area has a light tail: a light spanning nearly the whole
/// hemisphere makes the direct-light estimate at the last vertex heavy-tailed).
fn scene(material: &str, maxdepth: u32) -> String {
    format!(
        r#"LookAt 0 0 0  0 1 0  0 0 1
Camera "perspective" "float fov" [30]
Film "fleximage" "integer xresolution" [8] "integer yresolution" [8]
PixelFilter "box" "float xwidth" [0.5] "float ywidth" [0.5]
Sampler "random" "integer pixelsamples" [64]
SurfaceIntegrator "path" "integer maxdepth" [{maxdepth}] "string rrstrategy" ["none"]
WorldBegin
AttributeBegin
{material}
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
  "point P" [-5 2 -5  5 2 -5  5 2 5  -5 2 5]
AttributeEnd
AttributeBegin
AreaLightSource "area" "color L" [1 1 1]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
  "point P" [-6 -1 -6  -6 -1 6  6 -1 6  6 -1 -6]
AttributeEnd
WorldEnd
"#
    )
}

/// Mean luminance (Y) over the image.
fn mean_y(text: &str) -> f64 {
    let path = Path::new("/tmp/luxfarm-path-depth.lxs");
    let desc = parse_text(text, path);
    let opts = SessionOptions {
        threads: 1,
        seed: 7,
        stream: 0,
    };
    let film = render(&desc, Path::new("/tmp"), opts, 1);
    let xyz = normalized_xyz(&film);
    xyz.iter().map(|p| p[1]).sum::<f64>() / xyz.len() as f64
}

/// The light's own luminance, seen directly by the camera turned around.
fn light_y() -> f64 {
    let text = scene(r#"Material "matte""#, 0).replace("0 1 0  0 0 1", "0 -1 0  0 0 1");
    mean_y(&text)
}

#[test]
fn a_light_seen_in_a_mirror_shows_at_maxdepth_1() {
    let mirror = r#"Material "mirror" "color Kr" [1 1 1]"#;
    let le = light_y();
    assert!(le > 0.0, "the light must be visible: {le}");
    assert_eq!(
        mean_y(&scene(mirror, 0)),
        0.0,
        "maxdepth 0: emitters seen directly only"
    );
    let seen = mean_y(&scene(mirror, 1));
    assert!(
        (seen / le - 1.0).abs() < 1e-3,
        "maxdepth 1: the mirror shows the light ({seen} against {le})"
    );
}

#[test]
fn a_matte_wall_gets_direct_light_at_maxdepth_1_and_nothing_at_0() {
    let matte = r#"Material "matte" "color Kd" [0.8 0.8 0.8]"#;
    assert_eq!(mean_y(&scene(matte, 0)), 0.0);
    let direct = mean_y(&scene(matte, 1));
    // A Lambertian wall lit by a uniform light of radiance L reflects Kd·L·F, F the form
    // factor from the wall point to the light: for the light's half-side a = 6 at distance
    // d = 3, averaged over the pixels' wall points, F = 0.830 (numerical integration over the
    // light; 0.831 at the centre by the closed form (2/π)·2·a/√(a²+d²)·atan(a/√(a²+d²))).
    let le = light_y();
    let ratio = direct / le;
    let want = 0.8 * 0.830;
    assert!(
        (ratio / want - 1.0).abs() < 0.08,
        "direct light on the wall: {direct} against Kd·L·F = {}",
        want * le
    );
    // Light the wall sends to the light's own (matte, 0.5) surface and back is a path of
    // four segments, whose light is sampled at vertex 2: it shows at maxdepth 3, not at 2.
    let at2 = mean_y(&scene(matte, 2));
    assert!((at2 / direct - 1.0).abs() < 0.06, "{at2} against {direct}");
    let at3 = mean_y(&scene(matte, 3));
    assert!(at3 > 1.2 * direct, "{at3} against {direct}");
}
