//! Affine transforms kept in f64, applied to f32 geometry with conservative error bounds.
//!
//! Scene transforms arrive as `DMat4` (see `lxs::Xform`). Applying them in f64 and rounding
//! once to f32 keeps the error of a transformed point near half an ulp; the bound returned by
//! [`Transform::point_with_error`] covers that rounding plus the propagated input error, so the
//! robust ray offsets of `Interaction::spawn_ray` stay valid after a change of space.

use glam::{DMat3, DMat4, DVec3, Vec3A};

/// An invertible affine transform and its inverse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    pub m: DMat4,
    pub inv: DMat4,
}

/// Relative error of the f64 arithmetic, generously bounded (a few ulps of f64).
const F64_REL: f64 = 8.0 * f64::EPSILON;

impl Transform {
    pub const IDENTITY: Transform = Transform {
        m: DMat4::IDENTITY,
        inv: DMat4::IDENTITY,
    };

    /// `None` when the matrix is singular or not finite.
    pub fn new(m: DMat4) -> Option<Transform> {
        let det = DMat3::from_mat4(m).determinant();
        if !m.is_finite() || det == 0.0 || !det.is_finite() {
            return None;
        }
        let inv = m.inverse();
        inv.is_finite().then_some(Transform { m, inv })
    }

    pub fn inverse(&self) -> Transform {
        Transform {
            m: self.inv,
            inv: self.m,
        }
    }

    /// `self` applied after `first`.
    pub fn compose(&self, first: &Transform) -> Transform {
        Transform {
            m: self.m * first.m,
            inv: first.inv * self.inv,
        }
    }

    pub fn is_identity(&self) -> bool {
        self.m == DMat4::IDENTITY
    }

    /// Whether the linear part has a negative determinant (a mirror).
    pub fn swaps_handedness(&self) -> bool {
        DMat3::from_mat4(self.m).determinant() < 0.0
    }

    pub fn point(&self, p: DVec3) -> DVec3 {
        self.m.transform_point3(p)
    }

    pub fn vector(&self, v: DVec3) -> DVec3 {
        self.m.transform_vector3(v)
    }

    /// Normals transform with the inverse transpose.
    pub fn normal(&self, n: DVec3) -> DVec3 {
        DMat3::from_mat4(self.inv).transpose() * n
    }

    pub fn point_f32(&self, p: Vec3A) -> Vec3A {
        to_f32(self.point(to_f64(p)))
    }

    pub fn vector_f32(&self, v: Vec3A) -> Vec3A {
        to_f32(self.vector(to_f64(v)))
    }

    pub fn normal_f32(&self, n: Vec3A) -> Vec3A {
        to_f32(self.normal(to_f64(n)))
    }

    /// Transforms an f64 point known within `err` (absolute, per axis) and rounds it to f32;
    /// returns the f32 point and a conservative absolute bound on its error.
    pub fn point64_with_error(&self, p: DVec3, err: DVec3) -> (Vec3A, Vec3A) {
        let exact = self.point(p);
        let rounded = to_f32(exact);
        let lin = DMat3::from_mat4(self.m);
        let abs = DMat3::from_cols(lin.x_axis.abs(), lin.y_axis.abs(), lin.z_axis.abs());
        let t = self.m.w_axis.truncate().abs();
        let magnitude = abs * p.abs() + t;
        let bound =
            abs * err * (1.0 + F64_REL) + magnitude * F64_REL + (to_f64(rounded) - exact).abs();
        (rounded, error_floor(rounded, round_up(bound)))
    }

    /// [`Self::point64_with_error`] for an f32 point.
    pub fn point_with_error(&self, p: Vec3A, err: Vec3A) -> (Vec3A, Vec3A) {
        self.point64_with_error(to_f64(p), to_f64(err))
    }
}

pub fn to_f64(v: Vec3A) -> DVec3 {
    DVec3::new(v.x as f64, v.y as f64, v.z as f64)
}

pub fn to_f32(v: DVec3) -> Vec3A {
    Vec3A::new(v.x as f32, v.y as f32, v.z as f32)
}

/// Converts an f64 error bound to f32, rounding up.
pub fn round_up(v: DVec3) -> Vec3A {
    let up = |x: f64| {
        let f = x as f32;
        if (f as f64) < x {
            f.next_up()
        } else {
            f
        }
    };
    Vec3A::new(up(v.x), up(v.y), up(v.z))
}

/// Every error bound is at least one ulp of the point's largest coordinate: a point is never
/// claimed exact, so a spawned ray always leaves it.
pub fn error_floor(p: Vec3A, err: Vec3A) -> Vec3A {
    let floor = p.abs().max_element() * f32::EPSILON;
    err.max(Vec3A::splat(floor.max(f32::MIN_POSITIVE)))
}

/// pbrt's gamma(n): bound on the relative error of n chained f32 operations.
pub fn gamma(n: i32) -> f32 {
    let e = f32::EPSILON * 0.5 * n as f32;
    e / (1.0 - e)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_round_trip_and_handedness() {
        let m = DMat4::from_scale_rotation_translation(
            DVec3::new(2.0, -1.0, 0.5),
            glam::DQuat::from_rotation_z(0.3),
            DVec3::new(1.0, 2.0, 3.0),
        );
        let t = Transform::new(m).expect("invertible");
        assert!(t.swaps_handedness());
        let p = DVec3::new(0.3, -4.0, 2.0);
        assert!((t.inverse().point(t.point(p)) - p).length() < 1e-12);
        assert!(Transform::new(DMat4::ZERO).is_none());
    }

    #[test]
    fn point_error_bounds_the_rounding() {
        let t = Transform::new(DMat4::from_translation(DVec3::new(1e5, 0.1, -3.0))).unwrap();
        let p = Vec3A::new(0.123_456_7, 1e-3, 7.0);
        let (q, err) = t.point_with_error(p, Vec3A::ZERO);
        let exact = t.point(to_f64(p));
        for i in 0..3 {
            assert!(((q[i] as f64) - exact[i]).abs() <= err[i] as f64);
        }
    }
}
