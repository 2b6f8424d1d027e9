//! `LightSource "cylinder"`: the side of a cylinder as an emitter (mental ray's cylinder
//! area light), centred on `point from` ([0 0 0]), running along `vector axis` ([0 0 1];
//! its length is the cylinder's height, centred on `from`) with `float radius` (1); the
//! outside emits, the caps are open. Seen from outside, points are sampled uniformly by area
//! over the part of the side that faces the reference point (the arc of angles whose outward
//! normal sees it); from inside, over the whole side. The back of the side is then never
//! light-sampled from outside: when it emits (`twosided`), BSDF sampling alone finds it,
//! which MIS weighs fully, so the estimate stays unbiased.

use super::primshape::{quadratic, solid_angle_pdf, Crossings, LightShape, PrimPoint};
use crate::geometry::frame::coordinate_system;
use crate::lxs::ParamSet;
use glam::{Mat4, Vec2, Vec3A};
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug)]
pub struct Cylinder {
    center: Vec3A,
    /// Unit axis.
    a: Vec3A,
    s: Vec3A,
    t: Vec3A,
    height: f32,
    radius: f32,
}

impl Cylinder {
    /// The cylinder centred on `center` whose axis vector (its height) is `axis`.
    pub fn new(center: Vec3A, axis: Vec3A, radius: f32) -> Result<Cylinder, String> {
        let height = axis.length();
        if !(height > 0.0
            && height.is_finite()
            && radius > 0.0
            && radius.is_finite()
            && center.is_finite())
        {
            return Err(format!(
                "cylinder needs a non-zero axis and a positive radius, got axis {axis} radius {radius}"
            ));
        }
        let a = axis / height;
        let (s, t) = coordinate_system(a);
        Ok(Cylinder {
            center,
            a,
            s,
            t,
            height,
            radius,
        })
    }
}

/// Reads `from`, `axis`, `radius` and places the cylinder in the world (under a non-uniform
/// scale across the axis the radius keeps the cross-section's area).
pub fn build(p: &ParamSet, l2w: Mat4) -> Result<Cylinder, String> {
    let from = Vec3A::from_array(p.point("from").unwrap_or([0.0; 3]));
    let axis = Vec3A::from_array(p.vector("axis").unwrap_or([0.0, 0.0, 1.0]));
    let r = p.float_or("radius", 1.0);
    let (s, t) = coordinate_system(axis.normalize_or(Vec3A::Z));
    let cross = l2w.transform_vector3a(s).cross(l2w.transform_vector3a(t));
    Cylinder::new(
        l2w.transform_point3a(from),
        l2w.transform_vector3a(axis),
        r * cross.length().sqrt(),
    )
}

/// The arc of the side facing a point outside: its middle angle and half-width.
struct Arc {
    phi0: f32,
    half: f32,
}

impl Cylinder {
    /// The facing arc seen from `r`, or `None` when `r` is inside (or on) the cylinder.
    fn arc(&self, r: Vec3A) -> Option<Arc> {
        let rel = r - self.center;
        let across = rel - self.a * rel.dot(self.a);
        let rho = across.length();
        if rho <= self.radius * 1.0001 {
            return None;
        }
        Some(Arc {
            phi0: across.dot(self.t).atan2(across.dot(self.s)),
            half: (self.radius / rho).clamp(-1.0, 1.0).acos(),
        })
    }

    /// Density by area of the sampled part (the arc, or the whole side).
    fn area_pdf(&self, arc: Option<&Arc>) -> f32 {
        match arc {
            Some(a) => 1.0 / (2.0 * a.half * self.radius * self.height),
            None => 1.0 / self.area(),
        }
    }
}

impl LightShape for Cylinder {
    fn area(&self) -> f32 {
        2.0 * PI * self.radius * self.height
    }

    fn sample(&self, r: Vec3A, u: Vec2) -> Option<(PrimPoint, f32)> {
        let arc = self.arc(r);
        let z = (u.x - 0.5) * self.height;
        let phi = match &arc {
            Some(a) => a.phi0 + (2.0 * u.y - 1.0) * a.half,
            None => 2.0 * PI * u.y,
        };
        let n = self.s * phi.cos() + self.t * phi.sin();
        let q = PrimPoint {
            p: self.center + self.a * z + n * self.radius,
            n,
        };
        let pdf = solid_angle_pdf(self.area_pdf(arc.as_ref()), r, &q);
        (pdf > 0.0 && pdf.is_finite()).then_some((q, pdf))
    }

    fn pdf(&self, r: Vec3A, q: &PrimPoint) -> f32 {
        let arc = self.arc(r);
        if arc.is_some() && q.n.dot(r - q.p) <= 0.0 {
            return 0.0;
        }
        solid_angle_pdf(self.area_pdf(arc.as_ref()), r, q)
    }

    fn intersect(&self, o: Vec3A, d: Vec3A, t_max: f32) -> Crossings {
        let mut out = Crossings::default();
        let a = self.a.as_dvec3();
        let oc = (o - self.center).as_dvec3();
        let dd = d.as_dvec3();
        // Components across the axis.
        let op = oc - a * oc.dot(a);
        let dp = dd - a * dd.dot(a);
        let r = f64::from(self.radius);
        let Some((t0, t1)) = quadratic(dp.dot(dp), 2.0 * op.dot(dp), op.dot(op) - r * r) else {
            return out;
        };
        for t in [t0, t1] {
            let tf = t as f32;
            if !(tf > 0.0 && tf < t_max) {
                continue;
            }
            let local = oc + dd * t;
            let z = local.dot(a);
            if z.abs() <= 0.5 * f64::from(self.height) {
                let n = (local - a * z).normalize_or_zero();
                out.push(
                    tf,
                    PrimPoint {
                        p: o + d * tf,
                        n: Vec3A::from(n.as_vec3()),
                    },
                );
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossings_and_samples() {
        let c = Cylinder::new(Vec3A::ZERO, Vec3A::new(0.0, 0.0, 2.0), 0.5).unwrap();
        assert!((c.area() - 2.0 * PI).abs() < 1e-5);
        // A ray across the axis meets both walls; above the top it misses.
        let hits = c.intersect(Vec3A::new(-3.0, 0.0, 0.5), Vec3A::X, 10.0);
        let ts: Vec<f32> = hits.iter().map(|h| h.0).collect();
        assert_eq!(ts.len(), 2);
        assert!((ts[0] - 2.5).abs() < 1e-5 && (ts[1] - 3.5).abs() < 1e-5);
        assert!((hits.first().unwrap().1.n - -Vec3A::X).length() < 1e-5);
        assert!(c
            .intersect(Vec3A::new(-3.0, 0.0, 1.5), Vec3A::X, 10.0)
            .is_empty());
        let r = Vec3A::new(3.0, 0.2, 0.1);
        for i in 0..16 {
            let u = Vec2::new((i % 4) as f32 / 4.0 + 0.1, (i / 4) as f32 / 4.0 + 0.1);
            let (q, pdf) = c.sample(r, u).unwrap();
            assert!(((q.p - q.p.dot(c.a) * c.a).length() - 0.5).abs() < 1e-5);
            assert!(q.n.dot(r - q.p) > 0.0, "only the facing side is sampled");
            assert!((c.pdf(r, &q) - pdf).abs() < 1e-5 * pdf);
        }
        // The back is never light-sampled from outside; from inside, all of the side is.
        let back = PrimPoint {
            p: Vec3A::new(-0.5, 0.0, 0.0),
            n: -Vec3A::X,
        };
        assert_eq!(c.pdf(r, &back), 0.0);
        assert!(c.pdf(Vec3A::new(0.1, 0.0, 0.0), &back) > 0.0);
    }
}
