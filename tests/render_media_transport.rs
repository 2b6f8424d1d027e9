//! Participating media in every integrator: bidirectional and directlighting against the
//! path tracer in a closed room filled with a scattering medium, and attenuation against
//! Beer–Lambert by hand.
//!
//! The room (a matte box, camera inside, an area light under the ceiling) is filled with the
//! medium "world" (the camera's and every unbounded space's), and holds a null sphere that
//! bounds a denser medium, so paths, shadow rays and connections cross medium boundaries.
//!
//! Which paths each integrator counts (a path has a vertex on the light, its scattering
//! vertices, and the camera):
//! - `path` with `maxdepth` D: paths of up to D + 2 vertices; with `single` at most one of
//!   them in a medium, with `multi` any number.
//! - `bidirectional` with `eyedepth` E and `lightdepth` L: paths of up to E + L vertices;
//!   each subpath may scatter in media `max_scatters` times (`single`: once). With L = 1
//!   (no light vertices beyond the light) every path's medium vertices come from the eye
//!   subpath; with E = 1 (light tracing) from the light subpath: in both cases at most one
//!   with `single`, the path tracer's set for D = E + L − 2.
//! - `directlighting` (no specular surfaces here): emission seen along the camera ray and
//!   direct light at its first scattering point, surface or medium — `path` with
//!   `maxdepth` 1 (one vertex lit, no bounce after it).
//!
//! Block means of independent runs are compared with z-scores as in `transport_bidir.rs`.

mod transport_common;

use std::path::PathBuf;
use transport_common::*;

/// The foggy room at 24 × 24 with `setup` (Sampler, SurfaceIntegrator, VolumeIntegrator).
fn fog_room(setup: &str) -> String {
    room(setup, WORLD_FOG)
}

/// The room's medium "world".
const WORLD_FOG: &str =
    "MakeNamedVolume \"world\" \"homogeneous\" \"color sigma_a\" [0.1 0.15 0.2] \
     \"color sigma_s\" [0.6 0.5 0.4] \"float g\" [0.5]";
/// A vacuum "world": only the sphere holds a medium.
const WORLD_VACUUM: &str = "MakeNamedVolume \"world\" \"clear\" \"color absorption\" [0 0 0]";

/// The area light under the ceiling (facing down, radiance 4).
const CEILING_LIGHT: &str = "AreaLightSource \"area\" \"color L\" [4 4 4] \"float power\" [0]\n\
     Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" \
     [-0.3 -0.3 0.95  -0.3 0.3 0.95  0.3 0.3 0.95  0.3 -0.3 0.95]";
/// A small area light inside the sphere (facing down, radiance 20).
const INNER_LIGHT: &str = "AreaLightSource \"area\" \"color L\" [20 20 20] \"float power\" [0]\n\
     Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" \
     [0.2 0.3 -0.4  0.2 0.5 -0.4  0.4 0.5 -0.4  0.4 0.3 -0.4]";

/// The room with `world` defining its medium "world", lit from the ceiling.
fn room(setup: &str, world: &str) -> String {
    room_lit(setup, world, CEILING_LIGHT)
}

/// The room with `world` defining its medium "world" and `light` its light.
fn room_lit(setup: &str, world: &str, light: &str) -> String {
    format!(
        "LookAt 0 -0.9 0  0 1 0  0 0 1\n\
         Camera \"perspective\" \"float fov\" [75]\n\
         Film \"fleximage\" \"integer xresolution\" [24] \"integer yresolution\" [24]\n\
         {setup}\nWorldBegin\n{world}\n\
         MakeNamedVolume \"dense\" \"homogeneous\" \"color sigma_a\" [0.3 0.3 0.3] \
         \"color sigma_s\" [2 2.5 3] \"float g\" [-0.3]\n\
         AttributeBegin\nMaterial \"matte\" \"color Kd\" [0.6 0.6 0.6]\n{room}\nAttributeEnd\n\
         AttributeBegin\n{light}\nAttributeEnd\n\
         AttributeBegin\nMaterial \"null\"\nInterior \"dense\"\nExterior \"world\"\n\
         Translate 0.3 0.4 -0.4\nShape \"sphere\" \"float radius\" [0.35]\nAttributeEnd\n\
         WorldEnd\n",
        room = box_mesh([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
    )
}

fn here() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Block means (6 × 6 pixel blocks) of `n` runs of the foggy room with `setup`.
fn fog_runs(setup: &str, first: u64, n: u64) -> Vec<Vec<f64>> {
    room_runs(&fog_room(setup), first, n)
}

fn room_runs(text: &str, first: u64, n: u64) -> Vec<Vec<f64>> {
    let d = scene_text(text, &here());
    runs(&d, &here(), first, n, 1, 6)
}

const PATH_MULTI: &str = "Sampler \"random\" \"integer pixelsamples\" [16]\n\
     SurfaceIntegrator \"path\" \"integer maxdepth\" [6]\nVolumeIntegrator \"multi\"";
const BIDIR_MULTI: &str = "Sampler \"random\" \"integer pixelsamples\" [8]\n\
     SurfaceIntegrator \"bidirectional\" \"integer eyedepth\" [4] \"integer lightdepth\" [4]\n\
     VolumeIntegrator \"multi\"";

/// Multiple scattering: bidirectional (eye and light depth 4: paths of up to 8 vertices)
/// against path at `maxdepth` 6 (the same paths).
#[test]
fn fog_room_bidirectional_multi_matches_path() {
    let rp = fog_runs(PATH_MULTI, 0, 6);
    let rb = fog_runs(BIDIR_MULTI, 100, 6);
    assert_agree("fog multi bidir/path", &rp, &rb, 4.0, 0.0);
}

/// The scene's setup warnings (none may say the integrator was replaced).
fn setup_warnings(text: &str) -> Vec<String> {
    let d = scene_text(text, &here());
    luxfarm::render::setup::Renderable::build(&d, here())
        .expect("scene builds")
        .warnings
        .into_iter()
        .map(|w| w.message)
        .collect()
}

#[test]
fn bidirectional_and_directlighting_keep_their_integrator_with_media() {
    for setup in [
        BIDIR_MULTI,
        "SurfaceIntegrator \"directlighting\"\nVolumeIntegrator \"single\"",
    ] {
        let w = setup_warnings(&fog_room(setup));
        assert!(
            !w.iter()
                .any(|m| m.contains("rendering with") || m.contains("media")),
            "{setup}: {w:?}"
        );
    }
}

const PATH_SINGLE: &str = "Sampler \"random\" \"integer pixelsamples\" [16]\n\
     SurfaceIntegrator \"path\" \"integer maxdepth\" [4]\nVolumeIntegrator \"single\"";

/// Single scattering, medium vertices from the eye subpath: bidirectional with `lightdepth`
/// 1 and `eyedepth` 6 against path at `maxdepth` 4 (paths of up to 6 vertices, at most one
/// in a medium).
#[test]
fn fog_room_bidirectional_single_eye_side_matches_path() {
    let bidir = "Sampler \"random\" \"integer pixelsamples\" [16]\n\
         SurfaceIntegrator \"bidirectional\" \"integer eyedepth\" [6] \"integer lightdepth\" [1]\n\
         VolumeIntegrator \"single\"";
    let rp = fog_runs(PATH_SINGLE, 0, 6);
    let rb = fog_runs(bidir, 100, 6);
    assert_agree("fog single eye bidir/path", &rp, &rb, 4.0, 0.0);
}

/// directlighting (single scattering along the eye ray) against path at `maxdepth` 1.
#[test]
fn fog_room_directlighting_matches_path_at_depth_one() {
    let dl = "Sampler \"random\" \"integer pixelsamples\" [16]\n\
         SurfaceIntegrator \"directlighting\"\nVolumeIntegrator \"single\"";
    let path = "Sampler \"random\" \"integer pixelsamples\" [16]\n\
         SurfaceIntegrator \"path\" \"integer maxdepth\" [1]\nVolumeIntegrator \"single\"";
    let rp = fog_runs(path, 0, 16);
    let rd = fog_runs(dl, 100, 16);
    assert_agree("fog directlighting/path", &rp, &rd, 4.0, 0.0);
}

/// A matte floor lit by a sharp distant light from straight above, seen from above by an
/// orthographic camera, with a null slab of thickness `d` holding the medium `ink` defines
/// between them: camera ray and shadow ray each cross the slab once.
fn slab_scene(setup: &str, ink: &str, d: f32) -> String {
    let floor = "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" \
                 [-5 -5 0  5 -5 0  5 5 0  -5 5 0]";
    format!(
        "LookAt 0 0 5  0 0 0  0 1 0\n\
         Camera \"orthographic\" \"float screenwindow\" [-0.5 0.5 -0.5 0.5]\n\
         Film \"fleximage\" \"integer xresolution\" [4] \"integer yresolution\" [4]\n\
         Sampler \"random\" \"integer pixelsamples\" [4]\n\
         {setup}\nWorldBegin\n\
         LightSource \"distant\" \"point from\" [0 0 1] \"point to\" [0 0 0] \"color L\" [1 1 1]\n\
         {ink}\n\
         AttributeBegin\nMaterial \"matte\" \"color Kd\" [0.5 0.5 0.5]\n{floor}\nAttributeEnd\n\
         AttributeBegin\nMaterial \"null\"\nInterior \"ink\"\n{slab}\nAttributeEnd\n\
         WorldEnd\n",
        slab = box_mesh([0.0, 0.0, 1.0 + d / 2.0], [3.0, 3.0, d / 2.0]),
    )
}

/// Mean luminance of a render.
fn mean_y(text: &str) -> f64 {
    let d = scene_text(text, &here());
    let y = luminance(&render(&d, &here(), 0, 1));
    y.iter().sum::<f64>() / y.len() as f64
}

/// With `emission` (attenuation only) the slab dims the floor by exp(-2·sigma_a·d), per
/// Beer–Lambert along the shadow ray and again along the camera ray, in directlighting and
/// bidirectional alike (a scattering coefficient only attenuates too).
#[test]
fn emission_only_slab_attenuates_by_beer_lambert() {
    let (a, s, d) = (0.4f32, 0.3f32, 0.75f32);
    let ink = format!(
        "MakeNamedVolume \"ink\" \"homogeneous\" \"color sigma_a\" [{a} {a} {a}] \
         \"color sigma_s\" [{s} {s} {s}]"
    );
    let want = (-2.0 * f64::from((a + s) * d)).exp();
    for integ in [
        "SurfaceIntegrator \"directlighting\"",
        "SurfaceIntegrator \"bidirectional\" \"integer eyedepth\" [3] \"integer lightdepth\" [3]",
        "SurfaceIntegrator \"path\" \"integer maxdepth\" [1]",
    ] {
        let setup = format!("{integ}\nVolumeIntegrator \"emission\"");
        let with = mean_y(&slab_scene(&setup, &ink, d));
        let vacuum = "MakeNamedVolume \"ink\" \"clear\" \"color absorption\" [0 0 0]";
        let without = mean_y(&slab_scene(&setup, vacuum, d));
        let ratio = with / without;
        eprintln!("{integ}: {with} / {without} = {ratio:.5}, Beer–Lambert {want:.5}");
        assert!(without > 0.0, "{integ}: black floor");
        assert!(
            (ratio - want).abs() < 0.01 * want,
            "{integ}: {ratio} vs {want}"
        );
    }
}

/// Multiple scattering with the medium only inside the sphere (the camera and the light in
/// vacuum): every medium vertex is reached across the sphere's boundary, and connections
/// enter and leave it. Ten runs a side: the path tracer's rare long paths through the sphere
/// make its block means heavy-tailed, and six runs underestimated their spread (a change of
/// the meshes' default uv, which only turns the walls' shading frames, gave one block
/// |z| = 4.07 at six runs; 2.75 at ten).
#[test]
fn sphere_bidirectional_multi_matches_path() {
    let rp = room_runs(&room(PATH_MULTI, WORLD_VACUUM), 0, 10);
    let rb = room_runs(&room(BIDIR_MULTI, WORLD_VACUUM), 100, 10);
    assert_agree("sphere multi bidir/path", &rp, &rb, 4.0, 0.0);
}

/// A light inside the medium: light subpaths start in the sphere's medium (found from the
/// sphere's boundary, the first surface their rays meet), so they are attenuated and scatter
/// before they leave it.
#[test]
fn light_inside_a_medium_bidirectional_multi_matches_path() {
    // The path tracer finds the small light inside the medium rarely: more samples.
    let path = PATH_MULTI.replace("[16]", "[64]");
    let rp = room_runs(&room_lit(&path, WORLD_VACUUM, INNER_LIGHT), 0, 6);
    let rb = room_runs(&room_lit(BIDIR_MULTI, WORLD_VACUUM, INNER_LIGHT), 100, 6);
    assert_agree("inner light multi bidir/path", &rp, &rb, 4.0, 0.0);
}
