//! Local frames: an orthonormal basis around a normal, and the assembly of a complete
//! [`SurfaceInteraction`] (geometric and shading frames) from what a shape computed.

use super::interaction::{HitData, Interaction, Shading, SurfaceInteraction};
use glam::{Vec2, Vec3A};

/// Two unit vectors completing `n` (unit) to a right-handed orthonormal basis (Duff et al.).
pub fn coordinate_system(n: Vec3A) -> (Vec3A, Vec3A) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let s = Vec3A::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let t = Vec3A::new(b, sign + n.y * n.y * a, -n.y);
    (s, t)
}

/// What a shape knows about a hit or a sampled point, in the space of the caller.
#[derive(Clone, Copy, Debug)]
pub struct LocalGeometry {
    pub p: Vec3A,
    pub p_error: Vec3A,
    /// Oriented geometric normal (unit).
    pub n: Vec3A,
    /// Interpolated shading normal (unit), when the shape has one; `n` agrees with it.
    pub ns: Option<Vec3A>,
    pub uv: Vec2,
    pub dpdu: Vec3A,
    pub dpdv: Vec3A,
    /// Vertex colour, alpha and face index (defaults for shapes without them).
    pub hit: HitData,
}

impl LocalGeometry {
    /// Replaces a degenerate (dpdu, dpdv) pair by a frame around `n`, keeping it tangent.
    pub fn fix_tangents(&mut self) {
        let c = self.dpdu.cross(self.dpdv);
        if c.length_squared() <= 0.0 || !c.is_finite() {
            let (s, t) = coordinate_system(self.n);
            self.dpdu = s;
            self.dpdv = t;
        }
    }

    /// The complete record of a ray hit.
    #[inline(always)]
    pub fn into_surface_interaction(
        mut self,
        wo: Vec3A,
        t: f32,
        prim: u32,
        time: f32,
    ) -> SurfaceInteraction {
        self.fix_tangents();
        let ns = self.ns.unwrap_or(self.n);
        let shading = shading_frame(ns, self.dpdu, self.dpdv);
        SurfaceInteraction {
            it: self.interaction(time),
            wo,
            uv: self.uv,
            dpdu: self.dpdu,
            dpdv: self.dpdv,
            shading,
            t,
            prim,
            hit: self.hit,
        }
    }

    pub fn interaction(&self, time: f32) -> Interaction {
        Interaction {
            p: self.p,
            p_error: self.p_error,
            n: self.n,
            time,
        }
    }
}

/// Shading frame around `ns`: dpdu projected onto the tangent plane, dpdv completing it.
fn shading_frame(ns: Vec3A, dpdu: Vec3A, dpdv: Vec3A) -> Shading {
    let ss = (dpdu - ns * ns.dot(dpdu)).normalize_or_zero();
    let (ss, ts) = if ss == Vec3A::ZERO {
        coordinate_system(ns)
    } else {
        (ss, ns.cross(ss))
    };
    let lu = dpdu.length();
    let lv = dpdv.length();
    Shading {
        n: ns,
        dpdu: ss * if lu > 0.0 { lu } else { 1.0 },
        dpdv: ts * if lv > 0.0 { lv } else { 1.0 },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_orthonormal() {
        for n in [Vec3A::Z, -Vec3A::Z, Vec3A::new(0.6, 0.0, 0.8), -Vec3A::X] {
            let (s, t) = coordinate_system(n);
            assert!(s.dot(n).abs() < 1e-6 && t.dot(n).abs() < 1e-6 && s.dot(t).abs() < 1e-6);
            assert!((s.cross(t) - n).length() < 1e-5);
        }
    }
}
