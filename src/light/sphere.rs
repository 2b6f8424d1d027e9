//! `LightSource "sphere"`: a spherical emitter (mental ray's sphere area light) centred on
//! `point from` ([0 0 0]) with `float radius` (1); the outside emits. Seen from outside,
//! directions are sampled uniformly in the cone the sphere subtends (every sample lands on
//! the visible cap); from inside, points uniformly by area.

use super::primshape::{quadratic, solid_angle_pdf, Crossings, LightShape, PrimPoint};
use crate::geometry::frame::coordinate_system;
use crate::lxs::ParamSet;
use crate::sampling::uniform_sphere;
use glam::{Mat4, Vec2, Vec3A};
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug)]
pub struct Sphere {
    center: Vec3A,
    radius: f32,
}

/// The cone a sphere subtends from outside: sin²θmax and 1 − cosθmax (without cancellation).
struct Cone {
    sin2_max: f32,
    one_minus_cos: f32,
}

impl Sphere {
    pub fn new(center: Vec3A, radius: f32) -> Result<Sphere, String> {
        if !(radius > 0.0 && radius.is_finite() && center.is_finite()) {
            return Err(format!("sphere needs a positive radius, got {radius}"));
        }
        Ok(Sphere { center, radius })
    }

    /// The subtended cone from `r`, or `None` when `r` is inside (or on) the sphere.
    fn cone(&self, r: Vec3A) -> Option<Cone> {
        let dc2 = (self.center - r).length_squared();
        let r2 = self.radius * self.radius;
        if dc2 <= r2 * 1.0001 {
            return None;
        }
        let sin2_max = r2 / dc2;
        let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
        Some(Cone {
            sin2_max,
            one_minus_cos: sin2_max / (1.0 + cos_max),
        })
    }

    fn area_pdf(&self) -> f32 {
        1.0 / self.area()
    }
}

/// Reads `from` and `radius` and places the sphere in the world (a non-uniform scale gives
/// the sphere of the same volume).
pub fn build(p: &ParamSet, l2w: Mat4) -> Result<Sphere, String> {
    let from = Vec3A::from_array(p.point("from").unwrap_or([0.0; 3]));
    let r = p.float_or("radius", 1.0);
    let det = glam::Mat3::from_mat4(l2w).determinant().abs();
    Sphere::new(l2w.transform_point3a(from), r * det.cbrt())
}

impl LightShape for Sphere {
    fn area(&self) -> f32 {
        4.0 * PI * self.radius * self.radius
    }

    fn sample(&self, r: Vec3A, u: Vec2) -> Option<(PrimPoint, f32)> {
        let Some(cone) = self.cone(r) else {
            let n = uniform_sphere(u);
            let q = PrimPoint {
                p: self.center + n * self.radius,
                n,
            };
            let pdf = solid_angle_pdf(self.area_pdf(), r, &q);
            return (pdf > 0.0 && pdf.is_finite()).then_some((q, pdf));
        };
        let wc = self.center - r;
        let dc = wc.length();
        let axis = wc / dc;
        let one_minus_cos_t = u.x * cone.one_minus_cos;
        let cos_t = 1.0 - one_minus_cos_t;
        let sin2_t = one_minus_cos_t * (1.0 + cos_t);
        let sin_t = sin2_t.max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let (s, t) = coordinate_system(axis);
        let dir = s * (sin_t * phi.cos()) + t * (sin_t * phi.sin()) + axis * cos_t;
        // Distance to the near side along dir (the discriminant is ≥ 0 inside the cone).
        let r2 = self.radius * self.radius;
        let tau = dc * cos_t - (r2 - dc * dc * sin2_t.min(cone.sin2_max)).max(0.0).sqrt();
        let p = r + dir * tau;
        let q = PrimPoint {
            p,
            n: (p - self.center).normalize_or(-axis),
        };
        let pdf = 1.0 / (2.0 * PI * cone.one_minus_cos);
        (pdf.is_finite() && pdf > 0.0).then_some((q, pdf))
    }

    fn pdf(&self, r: Vec3A, q: &PrimPoint) -> f32 {
        match self.cone(r) {
            None => solid_angle_pdf(self.area_pdf(), r, q),
            // Cone sampling reaches the near side only.
            Some(cone) if q.n.dot(r - q.p) > 0.0 => 1.0 / (2.0 * PI * cone.one_minus_cos),
            Some(_) => 0.0,
        }
    }

    fn intersect(&self, o: Vec3A, d: Vec3A, t_max: f32) -> Crossings {
        let mut out = Crossings::default();
        let oc = (o - self.center).as_dvec3();
        let dd = d.as_dvec3();
        let r = f64::from(self.radius);
        let Some((t0, t1)) = quadratic(dd.dot(dd), 2.0 * oc.dot(dd), oc.dot(oc) - r * r) else {
            return out;
        };
        for t in [t0, t1] {
            let t = t as f32;
            if t > 0.0 && t < t_max {
                let p = o + d * t;
                let n = (p - self.center).normalize_or_zero();
                out.push(t, PrimPoint { p, n });
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cone_samples_hit_the_near_side_with_consistent_pdfs() {
        let s = Sphere::new(Vec3A::new(0.0, 0.0, 5.0), 1.0).unwrap();
        let r = Vec3A::ZERO;
        for i in 0..36 {
            let u = Vec2::new((i % 6) as f32 / 6.0 + 0.05, (i / 6) as f32 / 6.0 + 0.05);
            let (q, pdf) = s.sample(r, u).unwrap();
            assert!(((q.p - s.center).length() - 1.0).abs() < 1e-4);
            assert!(q.n.dot(r - q.p) > 0.0, "near side");
            let c = s.intersect(r, q.p - r, 2.0);
            let (t, qq) = *c.first().unwrap();
            assert!((t - 1.0).abs() < 1e-3);
            assert!((s.pdf(r, &qq) - pdf).abs() < 1e-4 * pdf);
            // The far crossing is never sampled.
            let far = c.iter().nth(1).unwrap().1;
            assert_eq!(s.pdf(r, &far), 0.0);
        }
        // Solid angle of the cone: 2π(1 − cos θmax) with sin θmax = 1/5.
        let cone = s.cone(r).unwrap();
        let want = 1.0 - (1.0f32 - 0.04).sqrt();
        assert!((cone.one_minus_cos - want).abs() < 1e-6);
    }

    #[test]
    fn inside_the_sphere_points_are_sampled_by_area() {
        let s = Sphere::new(Vec3A::ZERO, 2.0).unwrap();
        let (q, pdf) = s
            .sample(Vec3A::new(0.5, 0.0, 0.0), Vec2::new(0.3, 0.7))
            .unwrap();
        assert!((s.pdf(Vec3A::new(0.5, 0.0, 0.0), &q) - pdf).abs() < 1e-4 * pdf);
    }
}
