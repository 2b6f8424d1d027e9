//! The medium a light's rays start in: LuxRender 1.x gives every `LightSource` the exterior
//! volume in effect at its statement. A point light inside an absorbing sphere (a null
//! boundary with `Interior "fog"`, the camera outside in vacuum) lights a matte square that
//! is no medium boundary; the light is declared with `Exterior "fog"`. Bidirectional light
//! subpaths must start in the fog — the first surface they meet (the square) tells nothing
//! about it — and so agree with the path tracer, whose shadow rays run from the square
//! through the fog to the light.
//!
//! The same holds for an area light whose shape is declared with `Exterior "fog"`: its rays
//! leave into the shape's exterior.
//!
//! The square is flat and nothing else scatters, so both integrators render the same set of
//! paths (light → square → camera) at any depth. Block means of independent runs are
//! compared with z-scores as in `transport_bidir.rs`.

mod transport_common;

use std::path::PathBuf;
use transport_common::*;

/// The scene with `setup` (Sampler and SurfaceIntegrator) and the light's `exterior` line.
fn scene(setup: &str, exterior: &str) -> String {
    scene_with(setup, exterior, "")
}

/// The scene with `before` written ahead of the point light.
fn scene_with(setup: &str, exterior: &str, before: &str) -> String {
    format!(
        "LookAt 0 -1.6 1.2  0 0 -0.3  0 0 1\n\
         Camera \"perspective\" \"float fov\" [40]\n\
         Film \"fleximage\" \"integer xresolution\" [24] \"integer yresolution\" [24]\n\
         {setup}\nVolumeIntegrator \"emission\"\nWorldBegin\n\
         MakeNamedVolume \"fog\" \"homogeneous\" \"color sigma_a\" [1.5 1.5 1.5] \
         \"color sigma_s\" [0 0 0]\n\
         AttributeBegin\nMaterial \"null\"\nInterior \"fog\"\n\
         Shape \"sphere\" \"float radius\" [1]\nAttributeEnd\n\
         AttributeBegin\nMaterial \"matte\" \"color Kd\" [0.7 0.7 0.7]\n\
         Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" \
         [-0.5 -0.5 -0.3  0.5 -0.5 -0.3  0.5 0.5 -0.3  -0.5 0.5 -0.3]\nAttributeEnd\n\
         {before}\n\
         AttributeBegin\n{exterior}\nLightSource \"point\" \"point from\" [0 0 0.3] \
         \"color L\" [2 2 2]\nAttributeEnd\n\
         WorldEnd\n"
    )
}

const PATH: &str = "Sampler \"random\" \"integer pixelsamples\" [16]\n\
     SurfaceIntegrator \"path\" \"integer maxdepth\" [4]";
const BIDIR: &str = "Sampler \"random\" \"integer pixelsamples\" [8]\n\
     SurfaceIntegrator \"bidirectional\" \"integer eyedepth\" [4] \"integer lightdepth\" [4]";

fn here() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Block means (6 × 6 pixel blocks) of `n` runs of `text`.
fn block_runs(text: &str, first: u64, n: u64) -> Vec<Vec<f64>> {
    let d = scene_text(text, &here());
    runs(&d, &here(), first, n, 1, 6)
}

#[test]
fn a_light_in_a_medium_starts_its_subpaths_there() {
    let exterior = "Exterior \"fog\"";
    let rp = block_runs(&scene(PATH, exterior), 0, 6);
    let rb = block_runs(&scene(BIDIR, exterior), 100, 6);
    assert_agree("light in fog bidir/path", &rp, &rb, 4.0, 0.0);
}

/// A sunsky (one statement, two lights: the sun and the sky) ahead of the point light: the
/// point light still starts its subpaths in the fog (the start media follow the built lights,
/// not the statements).
#[test]
fn a_sunsky_ahead_keeps_the_point_light_in_its_medium() {
    let exterior = "Exterior \"fog\"";
    let sunsky = "LightSource \"sunsky\" \"vector sundir\" [0.3 -0.4 1] \"float gain\" [0.0005]";
    // Ten runs a side: the sky seen through the fog is nearly noiseless, and six runs
    // estimate its blocks' spread too loosely for a z-score (|z| 4.3 on one block).
    let rp = block_runs(&scene_with(PATH, exterior, sunsky), 0, 10);
    let rb = block_runs(&scene_with(BIDIR, exterior, sunsky), 100, 10);
    assert_agree("sunsky and light in fog bidir/path", &rp, &rb, 4.0, 0.0);
}

/// A small downward-facing area lamp in place of the point light, its shape declared with
/// `Exterior "fog"`: its light subpaths start in the fog, as the path tracer's shadow rays
/// find it.
#[test]
fn an_area_light_starts_its_subpaths_in_its_shapes_exterior() {
    let lamp = |setup: &str| {
        scene(setup, "").replace(
            "LightSource \"point\" \"point from\" [0 0 0.3] \"color L\" [2 2 2]",
            "Exterior \"fog\"\nAreaLightSource \"area\" \"color L\" [12 12 12]\n\
             Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" \
             [-0.1 -0.1 0.3  -0.1 0.1 0.3  0.1 0.1 0.3  0.1 -0.1 0.3]",
        )
    };
    let (path, bidir) = (lamp(PATH), lamp(BIDIR));
    assert!(
        bidir.contains("AreaLightSource"),
        "the lamp replaced the point light"
    );
    let rp = block_runs(&path, 0, 6);
    let rb = block_runs(&bidir, 100, 6);
    assert_agree("area light in fog bidir/path", &rp, &rb, 4.0, 0.0);
}
