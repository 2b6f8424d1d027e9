//! Light tracing alone and the path tracer agree at the image border: camera samples are
//! drawn over the Film's sample extent (the image widened by the pixel filter's width), and
//! light paths reach the camera over the same extent (`luxfarm::render::extent`).
//!
//! Before, eye samples stayed inside the image (a border pixel's value was the filter-weighted
//! mean of the samples it had) while light paths were refused beyond it, so a border pixel of
//! the light buffer lacked the part of its filter footprint outside the image and came out
//! darker by that fraction: 12 % of an edge pixel under the default mitchell filter, 37.5 %
//! under a box filter of width 2 (half its footprint of four pixels lies beyond the edge,
//! less the half pixel inside), which this test uses so that 4 × 4-pixel blocks along a
//! brightly lit wall touching the image's edges show it well above the noise.

mod transport_common;

use transport_common::*;

/// A closed grey room, the camera inside looking at the far wall; an emitting panel on the
/// ceiling along the left wall, facing down and out of view, lights the left wall brightly where it meets the image's left and top edges; 32 × 32,
/// a box filter of width 2.
fn border_scene(setup: &str) -> String {
    let panel = "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" \
                 [-1.99 -1 1.99  -1.99 1.99 1.99  -0.5 1.99 1.99  -0.5 -1 1.99]";
    format!(
        "LookAt 0 -1.9 0  0 1 0  0 0 1\n\
         Camera \"perspective\" \"float fov\" [50]\n\
         Film \"fleximage\" \"integer xresolution\" [32] \"integer yresolution\" [32]\n\
         PixelFilter \"box\" \"float xwidth\" [2] \"float ywidth\" [2]\n\
         {setup}\nWorldBegin\n\
         AttributeBegin\nMaterial \"matte\" \"color Kd\" [0.6 0.6 0.6]\n{room}\nAttributeEnd\n\
         AttributeBegin\nAreaLightSource \"area\" \"color L\" [1 0.9 0.8] \"float power\" [0]\n\
         {panel}\nAttributeEnd\nWorldEnd\n",
        room = box_mesh([0.0, 0.0, 0.0], [2.0; 3]),
    )
}

/// Light tracing (bidirectional with `eyedepth` 1: every path is a light subpath joined to
/// the camera) against the path tracer over the same paths (`maxdepth` = lightdepth − 1),
/// in 4 × 4-pixel blocks: 28 of the 64 blocks lie on the border.
#[test]
fn light_tracing_matches_path_at_the_image_border() {
    let here = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let path = border_scene(
        "Sampler \"random\" \"integer pixelsamples\" [8]\n\
         SurfaceIntegrator \"path\" \"integer maxdepth\" [3]",
    );
    let light = border_scene(
        "Sampler \"random\" \"integer pixelsamples\" [8]\n\
         SurfaceIntegrator \"bidirectional\" \"integer eyedepth\" [1] \"integer lightdepth\" [4]",
    );
    let (p, l) = (scene_text(&path, &here), scene_text(&light, &here));
    // The path tracer's blocks on the wall under the panel (its light sampled by area from
    // points a hand's width away) are heavy-tailed: their means come out a few percent low
    // in most realizations, with a spread that a handful of runs underestimates (|z| 6.3 on
    // one block at six runs of 16 samples; still 2.6-3.2 at ten runs of 32, with either way
    // of picking the panel's triangle). Ten runs of 32 samples a pixel, and 3 % of a block's
    // mean allowed beside its noise: the border loss this test guards against is 37.5 %.
    let rp = runs(&p, &here, 0, 10, 4, 4);
    let rl = runs(&l, &here, 100, 10, 4, 4);
    assert_agree("border light/path", &rp, &rl, 4.0, 0.03);
}

/// The same room with a second emitting panel on the far wall, facing the camera and in
/// view. Light tracing alone reaches the camera from the panel only by joining the light
/// subpath's origin to the camera (the strategy s = t = 1, as LuxRender's bidirectional
/// joins it): without it the panel's pixels stay dark while the path tracer sees them lit.
#[test]
fn light_tracing_sees_an_emitter_in_view() {
    let here = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let with_panel = |setup: &str| {
        border_scene(setup).replace(
            "WorldEnd\n",
            "AttributeBegin\nAreaLightSource \"area\" \"color L\" [0.5 0.6 0.9] \"float power\" [0]\n\
             Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" \
             [-0.6 1.99 -0.5  0.6 1.99 -0.5  0.6 1.99 0.5  -0.6 1.99 0.5]\nAttributeEnd\nWorldEnd\n",
        )
    };
    let path = with_panel(
        "Sampler \"random\" \"integer pixelsamples\" [8]\n\
         SurfaceIntegrator \"path\" \"integer maxdepth\" [3]",
    );
    let light = with_panel(
        "Sampler \"random\" \"integer pixelsamples\" [8]\n\
         SurfaceIntegrator \"bidirectional\" \"integer eyedepth\" [1] \"integer lightdepth\" [4]",
    );
    let (p, l) = (scene_text(&path, &here), scene_text(&light, &here));
    let rp = runs(&p, &here, 0, 6, 2, 4);
    let rl = runs(&l, &here, 100, 6, 2, 4);
    assert_agree("emitter in view light/path", &rp, &rl, 4.0, 0.0);
}
