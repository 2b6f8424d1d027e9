//! Surface interactions: what a ray hit, with local differential geometry and the error
//! bound used to spawn secondary rays robustly.

use super::ray::Ray;
use glam::{Vec2, Vec3A};

/// Shading frame (may differ from the geometric one: interpolated normals, bump mapping).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Shading {
    pub n: Vec3A,
    pub dpdu: Vec3A,
    pub dpdv: Vec3A,
}

/// A point on a surface (or a light) with the conservative absolute error of its coordinates.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Interaction {
    pub p: Vec3A,
    pub p_error: Vec3A,
    /// Geometric normal, already flipped for ReverseOrientation / handedness.
    pub n: Vec3A,
    pub time: f32,
}

/// What a shape knows about a hit beyond its geometry, for the textures that read it
/// (`hitpointcolor`, `hitpointalpha`, `hitpointgrey`, `harlequin`): the interpolated vertex
/// colour and alpha of a mesh (white and 1 when the mesh has none, as LuxRender returns) and
/// the index of the face within its shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HitData {
    pub color: [f32; 3],
    pub alpha: f32,
    pub face: u32,
}

impl Default for HitData {
    fn default() -> HitData {
        HitData {
            color: [1.0; 3],
            alpha: 1.0,
            face: 0,
        }
    }
}

/// The full record of a ray hit.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfaceInteraction {
    pub it: Interaction,
    /// Direction back toward the ray origin, normalized.
    pub wo: Vec3A,
    pub uv: Vec2,
    pub dpdu: Vec3A,
    pub dpdv: Vec3A,
    pub shading: Shading,
    /// Ray parameter of the hit.
    pub t: f32,
    /// Index of the primitive in the scene's primitive table (material, area light, ...).
    pub prim: u32,
    /// Vertex colour, alpha and face index at the hit.
    pub hit: HitData,
}

/// Moves `p` out of its error box along the normal, on the side of `w`, then rounds away
/// from `p` so the offset point is strictly outside the box (pbrt's method).
pub fn offset_ray_origin(p: Vec3A, p_error: Vec3A, n: Vec3A, w: Vec3A) -> Vec3A {
    let d = n.abs().dot(p_error);
    let mut offset = n * d;
    if w.dot(n) < 0.0 {
        offset = -offset;
    }
    let mut po = p + offset;
    for i in 0..3 {
        if offset[i] > 0.0 {
            po[i] = po[i].next_up();
        } else if offset[i] < 0.0 {
            po[i] = po[i].next_down();
        }
    }
    po
}

impl Interaction {
    /// A ray leaving this point in direction `d`.
    pub fn spawn_ray(&self, d: Vec3A) -> Ray {
        Ray {
            o: offset_ray_origin(self.p, self.p_error, self.n, d),
            d,
            t_max: f32::INFINITY,
            time: self.time,
        }
    }

    /// A ray from this point toward `other`, stopping just short of it (shadow rays).
    pub fn spawn_ray_to(&self, other: &Interaction) -> Ray {
        let o = offset_ray_origin(self.p, self.p_error, self.n, other.p - self.p);
        let target = offset_ray_origin(other.p, other.p_error, other.n, o - other.p);
        Ray {
            o,
            d: target - o,
            t_max: 1.0 - SHADOW_EPSILON,
            time: self.time,
        }
    }
}

/// Fraction of a shadow ray's length left unchecked at its far end.
pub const SHADOW_EPSILON: f32 = 0.0001;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offset_leaves_error_box_at_any_scale() {
        for scale in [1e-4f32, 1.0, 1e5] {
            let p = Vec3A::new(1.0, 2.0, 3.0) * scale;
            let err = p.abs() * (3.0 * f32::EPSILON);
            let n = Vec3A::Z;
            let o = offset_ray_origin(p, err, n, Vec3A::Z);
            assert!(o.z - p.z > err.z, "scale {scale}");
            let o = offset_ray_origin(p, err, n, -Vec3A::Z);
            assert!(p.z - o.z > err.z, "scale {scale}");
        }
    }
}
