//! Bump mapping as LuxRender 1.x computes it (`Material::Bump`): the `bumpmap` float texture
//! gives its derivatives (du, dv) with respect to the surface's (u, v) ([`FloatTex::duv`],
//! LuxRender's `GetDuv`: exact for image maps through their mapping, finite differences over
//! `bumpmapsampledistance` world units for procedural textures); the shading tangents become
//! dpdu + du·n and dpdv + dv·n, the shading normal their normalised cross product, turned to
//! the side of the original shading normal.
//!
//! Because du is a derivative per unit of u and dpdu is the surface's extent per unit of u,
//! the tilt du/|dpdu| depends on the texture's slope per unit length only: an image with
//! `uscale -32` on uvs spanning 1/32 has the same relief as with `uscale 1` on uvs spanning 1.
//!
//! The shading frame's dpdv is taken on the side of the surface's dpdv (LuxRender orients its
//! shading bitangent so); that keeps relief right on meshes with mirrored uvs.

use crate::geometry::{Shading, SurfaceInteraction};
use crate::texture::FloatTex;
use glam::Vec3A;

/// LuxRender's default `bumpmapsampledistance`.
pub const DEFAULT_DISTANCE: f32 = 0.001;

/// The hit with its shading frame bumped by `bump`; `distance` is the material's
/// `bumpmapsampledistance` (non-positive values take the default).
pub fn apply(bump: &FloatTex, distance: f32, si: &SurfaceInteraction) -> SurfaceInteraction {
    let delta = if distance > 0.0 && distance.is_finite() {
        distance
    } else {
        DEFAULT_DISTANCE
    };
    let mut frame = *si;
    let n = if si.shading.n == Vec3A::ZERO {
        si.it.n
    } else {
        si.shading.n
    };
    frame.shading.n = n;
    if frame.shading.dpdu == Vec3A::ZERO {
        frame.shading.dpdu = si.dpdu;
    }
    if frame.shading.dpdv == Vec3A::ZERO {
        frame.shading.dpdv = si.dpdv;
    }
    if frame.shading.dpdv.dot(si.dpdv) < 0.0 {
        frame.shading.dpdv = -frame.shading.dpdv;
    }
    let d = bump.duv(&frame, delta);
    if d == glam::Vec2::ZERO || !d.is_finite() {
        return *si;
    }
    let dpdu = frame.shading.dpdu + n * d.x;
    let dpdv = frame.shading.dpdv + n * d.y;
    let mut nn = dpdu.cross(dpdv).normalize_or_zero();
    if nn == Vec3A::ZERO || !nn.is_finite() {
        return *si;
    }
    if nn.dot(n) < 0.0 {
        nn = -nn;
    }
    let mut out = *si;
    out.shading = Shading { n: nn, dpdu, dpdv };
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::bilerp::BilerpTex;
    use crate::texture::mapping::Mapping2D;
    use crate::texture::tests::si_at;
    use crate::texture::uv::UvTex;
    use crate::texture::TexNode;
    use glam::Vec2;
    use std::sync::Arc;

    /// d = k·s with s = uscale·u: du = k·uscale; on a surface where u spans `extent` world
    /// units per unit (|dpdu| = extent), the normal tilts by k·uscale/extent.
    fn tilt(uscale: f32, extent: f32) -> Vec3A {
        let tex = FloatTex(Arc::new(TexNode::Scale(
            Arc::new(TexNode::Uv(UvTex {
                mapping: Mapping2D::Uv {
                    scale: Vec2::new(uscale, 1.0),
                    delta: Vec2::ZERO,
                },
            })),
            Arc::new(TexNode::Const(crate::spectrum::Rgb::splat(0.5))),
        )));
        let mut si = si_at(0.01, 0.25, Vec3A::ZERO);
        si.dpdu = Vec3A::X * extent;
        si.shading.dpdu = Vec3A::X * extent;
        apply(&tex, 0.001, &si).shading.n
    }

    #[test]
    fn relief_depends_on_slope_per_length_not_on_uv_scale() {
        // uscale 1 on uvs spanning 1 (extent 1) against uscale 32 on uvs spanning 1/32
        // (extent 32): the same tilt (the uv texture's fraction keeps the slope's sign).
        let a = tilt(1.0, 1.0);
        let b = tilt(32.0, 32.0);
        assert!((a - b).length() < 1e-3, "{a:?} vs {b:?}");
        let expect = Vec3A::new(-0.5, 0.0, 1.0).normalize();
        assert!((a - expect).length() < 1e-3, "{a:?}");
    }

    #[test]
    fn mirrored_uvs_keep_the_relief_direction() {
        // Height rising along +y in world space: with v running along −y, dh/dv < 0, and the
        // surface's dpdv points along −y; the bumped normal must lean toward −y either way.
        // Bilinear 0 → 1 along t, with t = −v: h = frac(−v), dh/dv = −1.
        let tex = FloatTex(Arc::new(TexNode::Bilerp(BilerpTex {
            mapping: Mapping2D::Uv {
                scale: Vec2::new(1.0, -1.0),
                delta: Vec2::ZERO,
            },
            v: [0.0, 1.0, 0.0, 1.0].map(crate::spectrum::Rgb::splat),
        })));
        let mut si = si_at(0.5, -0.3, Vec3A::ZERO);
        si.dpdv = -Vec3A::Y;
        // The shading frame as the shapes build it: dpdv = n × dpdu (here +y).
        si.shading.dpdv = Vec3A::Y;
        let n = apply(&tex, 0.001, &si).shading.n;
        assert!(n.y < -0.3 && n.z > 0.0, "{n:?}");
    }

    #[test]
    fn flat_textures_change_nothing() {
        let si = si_at(0.25, 0.25, Vec3A::ZERO);
        let flat = apply(&FloatTex::constant(0.3), 0.001, &si);
        assert_eq!(flat, si);
    }
}
