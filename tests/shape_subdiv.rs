//! Loop subdivision and displacement end to end, from scene text: a displaced plane moves by
//! the map times `dmscale` (with the texture named by a `Texture` statement), a
//! microdisplaced plane is the surface LuxRender ray traces for its map, hostile
//! `nlevels` is a located error, and a render of a subdivided icosahedron has a rounder
//! silhouette than its cage, measured against the disk of an analytic sphere of equal area.
//!
//! The render: an orthographic camera looks down -z at the emitting mesh (no other light, so a
//! pixel's luminance is the emitter's times the fraction of the pixel the mesh covers); the
//! disk that covers the same area is rasterised analytically, and the fraction of the image's
//! coverage that differs from the disk's measures how far the outline is from a circle.

mod render_util;

use luxfarm::render::setup::Renderable;
use luxfarm::render::SessionOptions;
use render_util::*;
use std::path::Path;

const PLANE: &str = r#"Shape "trianglemesh" "point P" [-1 -1 0  1 -1 0  1 1 0  -1 1 0]
  "integer quadindices" [0 1 2 3]"#;

fn world_scene(body: &str) -> String {
    format!(
        r#"LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic"
Film "fleximage" "integer xresolution" [8] "integer yresolution" [8]
WorldBegin
LightSource "infinite" "color L" [1 1 1]
{body}
WorldEnd
"#
    )
}

#[test]
fn a_displaced_plane_moves_by_the_map_times_dmscale() {
    let text = world_scene(&format!(
        r#"Texture "bump" "float" "constant" "float value" [0.5]
{PLANE} "integer nsubdivlevels" [3] "texture displacementmap" ["bump"] "float dmscale" [0.2]
  "bool dmsharpboundary" ["true"]"#
    ));
    let desc = parse_text(&text, Path::new("/tmp/shape_subdiv.lxs"));
    let r = Renderable::build(&desc, Path::new("/tmp")).expect("scene builds");
    let (lo, hi) = r.world.geometry().bounds();
    eprintln!("bounds {lo} .. {hi}");
    assert!(
        (lo.z - 0.1).abs() < 1e-5 && (hi.z - 0.1).abs() < 1e-5,
        "{lo} {hi}"
    );
    // A sharp boundary keeps the cage's square.
    assert!(
        (lo.x + 1.0).abs() < 1e-5 && (hi.y - 1.0).abs() < 1e-5,
        "{lo} {hi}"
    );
    // The older string form names the same texture.
    let text = text.replace(
        r#""texture displacementmap""#,
        r#""string displacementmap""#,
    );
    let desc = parse_text(&text, Path::new("/tmp/shape_subdiv.lxs"));
    let r = Renderable::build(&desc, Path::new("/tmp")).expect("scene builds");
    assert!((r.world.geometry().bounds().1.z - 0.1).abs() < 1e-5);
}

/// `subdivscheme "microdisplacement"` with a map that is u itself (a bilerp 0 → 1 along u)
/// on a plane whose u runs 0 → 0.5 along x (the bilerp repeats at u = 1): every grid point
/// rises by u · dmscale + dmoffset, so the surface rays hit is the tilted plane
/// z = 0.2 · (x + 1) / 4 − 0.05 (flat micro-triangles between points on one plane), for any
/// number of segments; a map value beyond 1 is clamped to 1, as in LuxRender.
#[test]
fn a_microdisplaced_plane_is_the_surface_its_map_describes() {
    use glam::Vec3A;
    use luxfarm::geometry::Ray;
    let body = |v11: f32, segments: u32| {
        format!(
            r#"Texture "u" "float" "bilerp" "float v00" [0] "float v10" [{v11}] "float v01" [0] "float v11" [{v11}]
{PLANE} "float uv" [0 0  0.5 0  0.5 1  0 1] "string subdivscheme" ["microdisplacement"]
  "integer nsubdivlevels" [{segments}] "texture displacementmap" ["u"]
  "float dmscale" [0.2] "float dmoffset" [-0.05]"#
        )
    };
    for segments in [1, 4, 7] {
        let desc = parse_text(&world_scene(&body(1.0, segments)), Path::new("/tmp/md.lxs"));
        let r = Renderable::build(&desc, Path::new("/tmp")).expect("scene builds");
        for (x, y) in [(-0.9, -0.8), (-0.3, 0.5), (0.2, -0.1), (0.77, 0.9)] {
            let ray = Ray::new(Vec3A::new(x, y, 5.0), Vec3A::new(0.0, 0.0, -1.0));
            let hit = r.world.intersect(&ray).expect("the plane is hit");
            let want = 0.2 * (x + 1.0) / 4.0 - 0.05;
            assert!(
                (hit.it.p.z - want).abs() < 1e-5,
                "{segments} segments at ({x}, {y}): z {} want {want}",
                hit.it.p.z
            );
        }
    }
    // A map reaching 3 is clamped to 1: the plane is lifted by the clamped value.
    let desc = parse_text(&world_scene(&body(6.0, 6)), Path::new("/tmp/md.lxs"));
    let r = Renderable::build(&desc, Path::new("/tmp")).expect("scene builds");
    let (lo, hi) = r.world.geometry().bounds();
    assert!(
        (lo.z + 0.05).abs() < 1e-5 && (hi.z - 0.15).abs() < 1e-5,
        "{lo} {hi}"
    );
}

/// With vertex normals (and `dmnormalsmooth` by default) the shading normal is LuxRender's:
/// the interpolated normal tilted by the map's raw (u, v) derivatives, dpdu + (∂map/∂u)·n.
/// Here dpdu = (4, 0, 0) (u = (x + 1) / 4), dpdv = (0, 2, 0) and ∂map/∂u = 1, so the normal is
/// normalize((4, 0, 1) × (0, 2, 0)) = normalize(−2, 0, 8), while the geometric normal is the
/// tilted plane's; `dmnormalsmooth false` leaves the flat micro-triangles' normal.
#[test]
fn a_microdisplaced_mesh_with_normals_is_shaded_as_luxrender_shades_it() {
    use glam::Vec3A;
    use luxfarm::geometry::Ray;
    let body = |smooth: bool| {
        format!(
            r#"Texture "u" "float" "bilerp" "float v00" [0] "float v10" [1] "float v01" [0] "float v11" [1]
{PLANE} "float uv" [0 0  0.5 0  0.5 1  0 1] "normal N" [0 0 1  0 0 1  0 0 1  0 0 1]
  "string subdivscheme" ["microdisplacement"] "integer nsubdivlevels" [5]
  "texture displacementmap" ["u"] "float dmscale" [0.2] "bool dmnormalsmooth" ["{smooth}"]"#
        )
    };
    let hit_at = |smooth: bool| {
        let desc = parse_text(&world_scene(&body(smooth)), Path::new("/tmp/md.lxs"));
        let r = Renderable::build(&desc, Path::new("/tmp")).expect("scene builds");
        let ray = Ray::new(Vec3A::new(0.3, -0.2, 5.0), Vec3A::new(0.0, 0.0, -1.0));
        r.world.intersect(&ray).expect("the plane is hit")
    };
    let tilted = Vec3A::new(-2.0, 0.0, 8.0).normalize();
    let flat = Vec3A::new(-0.05, 0.0, 1.0).normalize();
    let h = hit_at(true);
    assert!(
        (h.shading.n - tilted).length() < 1e-4,
        "shading {}",
        h.shading.n
    );
    assert!((h.it.n - flat).length() < 1e-4, "geometric {}", h.it.n);
    let h = hit_at(false);
    assert!(
        (h.shading.n - flat).length() < 1e-4,
        "flat shading {}",
        h.shading.n
    );
}

#[test]
fn hostile_nlevels_is_an_error_at_the_parameter() {
    let text = world_scene(&format!("{PLANE}\n  \"integer nlevels\" [30]"));
    let desc = parse_text(&text, Path::new("/tmp/shape_subdiv_hostile.lxs"));
    let err = Renderable::build(&desc, Path::new("/tmp"))
        .err()
        .expect("refused")
        .to_string();
    eprintln!("{err}");
    assert!(err.contains("/tmp/shape_subdiv_hostile.lxs:8:3"), "{err}");
    assert!(err.contains("30 levels"), "{err}");
}

const ICOSAHEDRON: &str = r#""point P" [
  -0.5257 0.8507 0  0.5257 0.8507 0  -0.5257 -0.8507 0  0.5257 -0.8507 0
  0 -0.5257 0.8507  0 0.5257 0.8507  0 -0.5257 -0.8507  0 0.5257 -0.8507
  0.8507 0 -0.5257  0.8507 0 0.5257  -0.8507 0 -0.5257  -0.8507 0 0.5257]
  "integer indices" [0 11 5  0 5 1  0 1 7  0 7 10  0 10 11  1 5 9  5 11 4  11 10 2  10 7 6
  7 1 8  3 9 4  3 4 2  3 2 6  3 6 8  3 8 9  4 9 5  2 4 11  6 2 10  8 6 7  9 8 1]"#;

const RES: u32 = 48;

/// Coverage per pixel of the icosahedron subdivided `levels` times, seen from above.
fn coverage(levels: u32) -> Vec<f64> {
    let text = format!(
        r#"LookAt 0.3 0.2 5  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [-1.2 1.2 -1.2 1.2]
Film "fleximage" "integer xresolution" [{RES}] "integer yresolution" [{RES}]
PixelFilter "box"
Sampler "random" "integer pixelsamples" [32]
SurfaceIntegrator "path" "integer maxdepth" [1]
WorldBegin
AttributeBegin
Rotate 20 1 0.3 0
AreaLightSource "area" "color L" [1 1 1]
Shape "loopsubdiv" "integer nlevels" [{levels}] {ICOSAHEDRON}
AttributeEnd
WorldEnd
"#
    );
    let desc = parse_text(&text, Path::new("/tmp/shape_subdiv_ico.lxs"));
    let opts = SessionOptions {
        threads: 2,
        seed: 3,
        stream: 0,
    };
    let film = render(&desc, Path::new("/tmp"), opts, 1);
    let y: Vec<f64> = normalized_xyz(&film).iter().map(|p| p[1]).collect();
    let full = y.iter().copied().fold(0.0, f64::max);
    assert!(full > 0.0, "the emitter is seen");
    y.iter().map(|v| v / full).collect()
}

/// Fraction of the coverage that differs from the centred disk of equal area (rasterised
/// with 8×8 samples per pixel).
fn misfit_to_disk(cov: &[f64]) -> f64 {
    let pixel = 2.4 / RES as f64;
    let total: f64 = cov.iter().sum();
    // Centre of the coverage (the mesh is not centred on the optical axis).
    let (mut cx, mut cy) = (0.0, 0.0);
    for (i, c) in cov.iter().enumerate() {
        cx += c * ((i as u32 % RES) as f64 + 0.5);
        cy += c * ((i as u32 / RES) as f64 + 0.5);
    }
    let (cx, cy) = (cx / total, cy / total);
    let r = (total / std::f64::consts::PI).sqrt();
    let mut misfit = 0.0;
    for (i, c) in cov.iter().enumerate() {
        let (px, py) = ((i as u32 % RES) as f64, (i as u32 / RES) as f64);
        let mut inside = 0;
        for s in 0..64 {
            let x = px + (s % 8) as f64 / 8.0 + 1.0 / 16.0 - cx;
            let y = py + (s / 8) as f64 / 8.0 + 1.0 / 16.0 - cy;
            inside += (x * x + y * y <= r * r) as u32;
        }
        misfit += (c - inside as f64 / 64.0).abs();
    }
    eprintln!(
        "radius {:.3} (world units), misfit {:.4}",
        r * pixel,
        misfit / total
    );
    misfit / total
}

#[test]
fn a_subdivided_icosahedron_has_a_rounder_silhouette_than_its_cage() {
    let cage = misfit_to_disk(&coverage(0));
    let smooth = misfit_to_disk(&coverage(3));
    eprintln!("silhouette misfit to a disk: cage {cage:.4}, 3 levels {smooth:.4}");
    assert!(smooth < 0.5 * cage, "cage {cage}, subdivided {smooth}");
}
