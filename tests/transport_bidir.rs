//! Bidirectional path tracing converges to the same image as the path tracer: 32×32-pixel
//! block means of independent renders agree within the standard errors the runs measure,
//! on the Cornell box (area light, glass sphere), on LuxRender TestSuite scenes, and on a
//! small scene of several emitters around a translucent cube.
//!
//! Both integrators must estimate the same set of paths. The path tracer with `maxdepth` D
//! builds every path of up to D + 2 vertices (camera and light included: D scattering
//! vertices lit directly, or D + 1 hits whose last is an emitter); bidirectional with
//! `eyedepth` E and `lightdepth` L builds every path of up to E + L vertices. So the path
//! tracer's depth here is E + L − 2: with a shallower path tracer the comparison measures
//! the light of the longer paths, which is not small wherever light is trapped (a closed
//! room of bright walls, a translucent cube whose reflectance keeps 90 % of the light inside).

mod transport_common;

use transport_common::*;

/// Both integrators over the same paths (up to 32 vertices, `maxdepth` = 16 + 16 − 2);
/// Russian roulette (unbiased) keeps the paths short.
const PATH: &str = "Sampler \"random\" \"integer pixelsamples\" [4]\nSurfaceIntegrator \"path\" \"integer maxdepth\" [30]";

/// Cornell with the random and sobol samplers (metropolis: `transport_mlt`).
#[test]
fn cornell_bidirectional_matches_path() {
    let (p, dir) = scene("cornell/cornell.lxs", PATH, 64, 64);
    // Twelve path runs: standard errors taken from six runs are themselves uncertain enough
    // (Student's t, five degrees of freedom) that |z| passes 4 by chance now and then.
    let rp = runs(&p, &dir, 0, 12, 2, 32);
    for (i, sampler) in ["random", "sobol"].iter().enumerate() {
        let (b, _) = scene("cornell/cornell.lxs", &bidir_with(sampler), 64, 64);
        let rb = runs(&b, &dir, 100 * (i as u64 + 1), 6, 2, 32);
        assert_agree(&format!("cornell bidir+{sampler}/path"), &rp, &rb, 4.0, 0.0);
    }
}

/// Bidirectional with `sampler` (`pixelsamples` 2, its other parameters at their defaults).
fn bidir_with(sampler: &str) -> String {
    format!(
        "Sampler \"{sampler}\" \"integer pixelsamples\" [2]\nSurfaceIntegrator \"bidirectional\" \"integer eyedepth\" [16] \"integer lightdepth\" [16]"
    )
}

/// The path tracer's block means on a TestSuite scene, then bidirectional's with the random,
/// sobol and metropolis samplers, each against them (independent streams per run).
fn each_sampler_matches_path(rel: &str, w: u32, h: u32, name: &str) {
    let (p, dir) = scene(rel, PATH, w, h);
    let rp = runs(&p, &dir, 0, 6, 2, 32);
    for (i, sampler) in ["random", "sobol", "metropolis"].iter().enumerate() {
        let (b, _) = scene(rel, &bidir_with(sampler), w, h);
        let rb = runs(&b, &dir, 100 * (i as u64 + 1), 6, 2, 32);
        assert_agree(&format!("{name} bidir+{sampler}/path"), &rp, &rb, 4.0, 0.0);
    }
}

/// LuxRender's own bidirectional regression scene (matte box, blackbody area light),
/// bidirectional with each sampler against path.
#[test]
fn testsuite_bidirectional_simple_each_sampler_matches_path() {
    let rel = "testsuite/core_regression_tests/tests/integrators/bidirectional/simple/default.lxs";
    each_sampler_matches_path(rel, 64, 64, "simple");
}

/// Matte translucent surfaces (light carried through transmission, where the adjoint
/// handling of shading normals matters), bidirectional with each sampler against path.
///
/// This scene once looked like a bidirectional bias (10-25 % brighter, z up to 6.7) while
/// the path tracer ran with `maxdepth` 16: that path tracer misses the paths of 19 to 32
/// vertices, and here they carry that much light. The four translucent cubes sit on the
/// emitting cubes, and the Kr 0.9 of tralu3 and tralu4 (not energy conserving) keeps 90 %
/// of the light inside at each bounce, so after 16 bounces 0.9¹⁶ ≈ 19 % is still in the
/// cube. Hence the earlier observations: `lightdepth` 1 or 2 (paths of at most 17 or 18
/// vertices; the path tracer's reach 18) agreed, and so did the scene with the cubes not
/// emitting (little light reaches the translucent cubes; path at 16 and at 30 differ by
/// 1 % there). With equal path sets both agree (max |z| 0.42 on these settings); a path
/// tracer at `maxdepth` 64 agrees with bidirectional too (max |z| 1.75).
#[test]
fn testsuite_mattetranslucent_each_sampler_matches_path() {
    let rel = "testsuite/mattetranslucent/mattetranslucenttest.lxs";
    each_sampler_matches_path(rel, 64, 48, "mattetranslucent");
}

/// A closed grey room (camera inside) with two emitting cubes side by side (light subpaths
/// from one land on the other, whose surfaces scatter with the default material), a
/// one-sided emitting quad under the ceiling facing down (its back lit by the room), and a
/// translucent cube (Kr 0.6, Kt 0.3), all at 32 × 32.
fn emitters_scene(setup: &str) -> String {
    let quad = "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" \
                [-0.5 0.2 1.7  -0.5 1.2 1.7  0.5 1.2 1.7  0.5 0.2 1.7]";
    format!(
        "LookAt 0 -1.9 0  0 1 0  0 0 1\n\
         Camera \"perspective\" \"float fov\" [70]\n\
         Film \"fleximage\" \"integer xresolution\" [32] \"integer yresolution\" [32]\n\
         {setup}\nWorldBegin\n\
         AttributeBegin\nMaterial \"matte\" \"color Kd\" [0.5 0.5 0.5]\n{room}\nAttributeEnd\n\
         AttributeBegin\nAreaLightSource \"area\" \"color L\" [1 1 1] \"float power\" [0]\n{a}\nAttributeEnd\n\
         AttributeBegin\nAreaLightSource \"area\" \"color L\" [1 0.8 0.6] \"float power\" [0]\n{b}\nAttributeEnd\n\
         AttributeBegin\nAreaLightSource \"area\" \"color L\" [0.5 0.5 0.5] \"float power\" [0]\n{quad}\nAttributeEnd\n\
         AttributeBegin\nMaterial \"mattetranslucent\" \"color Kr\" [0.6 0.6 0.6] \"color Kt\" [0.3 0.3 0.3]\n\
         {tralu}\nAttributeEnd\nWorldEnd\n",
        room = box_mesh([0.0, 0.0, 0.0], [2.0; 3]),
        a = box_mesh([-0.5, 1.0, 0.6], [0.3; 3]),
        b = box_mesh([0.3, 1.0, 0.6], [0.3; 3]),
        tralu = box_mesh([0.0, 0.8, -0.8], [0.6; 3]),
    )
}

/// Several emitters (light subpaths meeting other emitters, one-sided emission seen from
/// behind) and a translucent cube, the case the TestSuite scene above exercises, small:
/// bidirectional (eye and light depth 8) against path at the same path set (`maxdepth` 14).
#[test]
fn several_emitters_and_translucent_cube_bidirectional_matches_path() {
    let here = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let path = emitters_scene(
        "Sampler \"random\" \"integer pixelsamples\" [8]\n\
         SurfaceIntegrator \"path\" \"integer maxdepth\" [14]",
    );
    let bidir = emitters_scene(
        "Sampler \"random\" \"integer pixelsamples\" [4]\n\
         SurfaceIntegrator \"bidirectional\" \"integer eyedepth\" [8] \"integer lightdepth\" [8]",
    );
    let (p, b) = (scene_text(&path, &here), scene_text(&bidir, &here));
    let rp = runs(&p, &here, 0, 8, 1, 16);
    let rb = runs(&b, &here, 100, 8, 1, 16);
    assert_agree("emitters bidir/path", &rp, &rb, 4.0, 0.0);
}
