//! The arrays of a mesh shape in its target space, between the mesh plugin (`mesh.rs`) and
//! the steps that refine it (`loopsubdiv.rs`, `microdisplace.rs`), and the evaluation of a
//! displacement texture at a point of such a mesh.

use crate::geometry::{Interaction, Shading, SurfaceInteraction};
use crate::texture::FloatTex;
use glam::{DVec2, DVec3, Vec2, Vec3A};

/// The uv of every corner of a mesh without "uv": LuxRender 1.x's mesh triangles
/// (`MeshBaryTriangle`, `MeshWaldTriangle`, `MeshMicroDisplacementTriangle`) give each corner
/// (0.5, 0.5), so a uv-mapped texture reads one value there and the tangents come from the
/// normal alone.
pub const DEFAULT_UV: [Vec2; 3] = [Vec2::new(0.5, 0.5); 3];

/// The arrays of a mesh in its target space, as `mesh.rs` holds them.
#[derive(Clone, Debug)]
pub struct MeshArrays {
    pub p: Vec<Vec3A>,
    pub n: Option<Vec<Vec3A>>,
    pub uv: Option<Vec<Vec2>>,
    pub cols: Option<Vec<[f32; 3]>>,
    pub alphas: Option<Vec<f32>>,
    pub tris: Vec<[u32; 3]>,
}

/// The float texture at a point with normal `n`, uv and tangents `frame` (dpdu, dpdv).
pub(super) fn evaluate_in(
    map: &FloatTex,
    p: DVec3,
    n: DVec3,
    uv: DVec2,
    frame: (DVec3, DVec3),
) -> f64 {
    let n = n.as_vec3a();
    let (dpdu, dpdv) = (frame.0.as_vec3a(), frame.1.as_vec3a());
    let si = SurfaceInteraction {
        it: Interaction {
            p: p.as_vec3a(),
            n,
            ..Interaction::default()
        },
        wo: n,
        uv: uv.as_vec2(),
        dpdu,
        dpdv,
        shading: Shading { n, dpdu, dpdv },
        ..SurfaceInteraction::default()
    };
    map.eval(&si) as f64
}
