//! The medium a light's rays start in: LuxRender 1.x gives every `LightSource` the exterior
//! volume in effect at its statement. A point light inside an absorbing sphere (a null
//! boundary with `Interior "fog"`, the camera outside in vacuum) lights a matte square that
//! is no medium boundary; the light is declared with `Exterior "fog"`. Bidirectional light
//! subpaths must start in the fog — the first surface they meet (the square) tells nothing
//! about it — and so agree with the path tracer, whose shadow rays run from the square
//! through the fog to the light.
//!
//! The square is flat and nothing else scatters, so both integrators render the same set of
//! paths (light → square → camera) at any depth. Block means of independent runs are
//! compared with z-scores as in `transport_bidir.rs`.

mod transport_common;

use std::path::PathBuf;
use transport_common::*;

/// The scene with `setup` (Sampler and SurfaceIntegrator) and the light's `exterior` line.
fn scene(setup: &str, exterior: &str) -> String {
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
