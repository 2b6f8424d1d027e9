//! LuxRender 1.x's light strategies (`lightstrategy`, and the lights' `importance`): every
//! strategy renders the image of `all` within noise, with the direct-lighting and the path
//! integrators and bidirectional's light paths, on a floor lit by two area lights and a point
//! light of unequal power and importance. A light whose importance is 0 is never drawn by the
//! importance-weighted strategies: a point light then lights nothing (as in LuxRender), while
//! an area light is still reached by the BSDF-sampled rays luxfarm traces from every surface
//! (LuxRender traces them only from surfaces with a non-diffuse component).

mod transport_common;

use std::path::Path;
use transport_common::*;

/// Block means (4 × 4 pixels, every buffer: bidirectional splats light paths into the light
/// buffer) of two passes of `text` on `stream`.
fn blocks(text: &str, stream: u64) -> Vec<f64> {
    let desc = scene_text(text, Path::new("/tmp/luxfarm-strategies.lxs"));
    block_means(&render(&desc, Path::new("/tmp"), stream, 2), 4)
}

fn rmse(a: &[f64], b: &[f64]) -> f64 {
    let se: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
    (se / a.len().max(1) as f64).sqrt()
}

/// `other` matches `a` about as well as `a2` (the same scene as `a` on another stream)
/// does: an RMS difference of at most 1.6 times the stream-to-stream noise plus 1 % of the
/// mean, on an image that is not black.
fn assert_within_noise(a: &[f64], a2: &[f64], other: &[f64], what: &str) {
    let (noise, diff) = (rmse(a, a2), rmse(a, other));
    let mean = a.iter().sum::<f64>() / a.len() as f64;
    assert!(mean > 0.0, "{what}: black image");
    assert!(
        diff <= 1.6 * noise + 0.01 * mean,
        "{what}: difference {diff:.5} vs noise {noise:.5} (mean {mean:.4})"
    );
}

/// The scene with `integrator` (a SurfaceIntegrator statement) and the point light's and
/// first area light's `importance`.
fn scene(integrator: &str, point_importance: f32, area_importance: f32) -> String {
    format!(
        r#"LookAt 0 -5 5  0 0 0  0 0 1
Camera "perspective" "float fov" [45]
Film "fleximage" "integer xresolution" [24] "integer yresolution" [24]
PixelFilter "box" "float xwidth" [0.5] "float ywidth" [0.5]
Sampler "random" "integer pixelsamples" [16]
{integrator}
WorldBegin
LightSource "point" "point from" [1.5 0.5 1.5] "color L" [3 3 3] "float importance" [{point_importance}]
AttributeBegin
AreaLightSource "area" "color L" [4 4 4] "float importance" [{area_importance}]
Shape "trianglemesh" "integer indices" [0 2 1 0 3 2] "point P" [-2 -0.5 2  -1 -0.5 2  -1 0.5 2  -2 0.5 2]
AttributeEnd
AttributeBegin
AreaLightSource "area" "color L" [1 0.6 0.3] "float importance" [3]
Shape "trianglemesh" "integer indices" [0 2 1 0 3 2] "point P" [0 1 2.5  2 1 2.5  2 3 2.5  0 3 2.5]
AttributeEnd
Material "matte" "color Kd" [0.7 0.7 0.7]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point P" [-4 -4 0  4 -4 0  4 4 0  -4 4 0]
WorldEnd
"#
    )
}

const DIRECT: &str =
    r#"SurfaceIntegrator "directlighting" "integer maxdepth" [1] "string lightstrategy" ["{}"]"#;
const PATH: &str =
    r#"SurfaceIntegrator "path" "integer maxdepth" [3] "string lightstrategy" ["{}"]"#;
const BIDIR: &str = r#"SurfaceIntegrator "bidirectional" "integer eyedepth" [3] "integer lightdepth" [3] "string lightpathstrategy" ["{}"]"#;

const STRATEGIES: [&str; 7] = [
    "one",
    "auto",
    "importance",
    "powerimp",
    "allpowerimp",
    "autopowerimp",
    "logpowerimp",
];

#[test]
fn every_strategy_renders_the_image_of_all() {
    for integrator in [DIRECT, PATH, BIDIR] {
        let with = |s: &str| scene(&integrator.replace("{}", s), 0.5, 2.0);
        let all = blocks(&with("all"), 0);
        for s in STRATEGIES {
            // The strategy's own stream-to-stream noise: picking one light of three is
            // noisier than lighting with all.
            let (b, b2) = (blocks(&with(s), 2), blocks(&with(s), 3));
            let what = format!("{} {s}", integrator.split('"').nth(1).unwrap_or(""));
            assert_within_noise(&b, &b2, &all, &what);
        }
    }
}

#[test]
fn importance_zero_drops_a_point_light_but_not_an_area_light() {
    let direct = |s: &str| DIRECT.replace("{}", s);
    let all = scene(&direct("all"), 1.0, 1.0);
    let (ba, ba2) = (blocks(&all, 0), blocks(&all, 1));
    // The point light at importance 0 under "importance": as if it were not there.
    let (dark, dark2) = (
        blocks(&scene(&direct("importance"), 0.0, 1.0), 2),
        blocks(&scene(&direct("importance"), 0.0, 1.0), 3),
    );
    let without =
        scene(&direct("all"), 1.0, 1.0).replace(r#""color L" [3 3 3]"#, r#""color L" [0 0 0]"#);
    assert_within_noise(
        &dark,
        &dark2,
        &blocks(&without, 0),
        "point light at importance 0",
    );
    // And that is a visible change: the point light does light the floor.
    assert!(rmse(&ba, &blocks(&without, 0)) > 3.0 * rmse(&ba, &ba2));
    // The area light at importance 0: still there through BSDF sampling.
    let (a0, a02) = (
        blocks(&scene(&direct("importance"), 1.0, 0.0), 2),
        blocks(&scene(&direct("importance"), 1.0, 0.0), 3),
    );
    assert_within_noise(&a0, &a02, &ba, "area light at importance 0");
}
