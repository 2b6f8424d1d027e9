//! `LightSource "disc"`: a flat round emitter (mental ray's disc area light) centred on
//! `point from` ([0 0 0]) with `normal normal` ([0 0 1], the front side) and `float radius`
//! (1). Points are sampled uniformly by area (concentric mapping).

use super::primshape::{plane_crossing, solid_angle_pdf, Crossings, LightShape, PrimPoint};
use crate::geometry::frame::coordinate_system;
use crate::lxs::ParamSet;
use crate::sampling::concentric_disc;
use glam::{Mat4, Vec2, Vec3A};
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug)]
pub struct Disc {
    center: Vec3A,
    n: Vec3A,
    s: Vec3A,
    t: Vec3A,
    radius: f32,
}

impl Disc {
    /// The disc at `center` facing `normal` (any length) with `radius` (world space).
    pub fn new(center: Vec3A, normal: Vec3A, radius: f32) -> Result<Disc, String> {
        let n = normal.normalize_or_zero();
        if n == Vec3A::ZERO || !(radius > 0.0 && radius.is_finite()) || !center.is_finite() {
            return Err(format!(
                "disc needs a non-zero normal and a positive radius, got normal {normal} radius {radius}"
            ));
        }
        let (s, t) = coordinate_system(n);
        Ok(Disc {
            center,
            n,
            s,
            t,
            radius,
        })
    }
}

/// Reads `from`, `normal`, `radius` and places the disc in the world. Under a non-uniform
/// scale the radius becomes the one of the disc of the same area.
pub fn build(p: &ParamSet, l2w: Mat4) -> Result<Disc, String> {
    let from = Vec3A::from_array(p.point("from").unwrap_or([0.0; 3]));
    let n = Vec3A::from_array(p.normal("normal").unwrap_or([0.0, 0.0, 1.0]));
    let r = p.float_or("radius", 1.0);
    let (s, t) = coordinate_system(n.normalize_or_zero());
    let ws = l2w.transform_vector3a(s);
    let wt = l2w.transform_vector3a(t);
    let cross = ws.cross(wt);
    Disc::new(
        l2w.transform_point3a(from),
        cross,
        r * cross.length().sqrt(),
    )
}

impl LightShape for Disc {
    fn area(&self) -> f32 {
        PI * self.radius * self.radius
    }

    fn sample(&self, r: Vec3A, u: Vec2) -> Option<(PrimPoint, f32)> {
        let d = concentric_disc(u) * self.radius;
        let q = PrimPoint {
            p: self.center + d.x * self.s + d.y * self.t,
            n: self.n,
        };
        let pdf = solid_angle_pdf(1.0 / self.area(), r, &q);
        (pdf > 0.0 && pdf.is_finite()).then_some((q, pdf))
    }

    fn pdf(&self, r: Vec3A, q: &PrimPoint) -> f32 {
        solid_angle_pdf(1.0 / self.area(), r, q)
    }

    fn intersect(&self, o: Vec3A, d: Vec3A, t_max: f32) -> Crossings {
        let mut out = Crossings::default();
        if let Some(t) = plane_crossing(self.center, self.n, o, d, t_max) {
            let p = o + d * t;
            if (p - self.center).length_squared() <= self.radius * self.radius {
                out.push(t, PrimPoint { p, n: self.n });
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_lie_on_the_disc_and_pdfs_agree() {
        let d = Disc::new(Vec3A::new(0.0, 0.0, 2.0), -Vec3A::Z, 0.5).unwrap();
        let r = Vec3A::new(0.1, 0.0, 0.0);
        for i in 0..25 {
            let u = Vec2::new((i % 5) as f32 / 5.0 + 0.1, (i / 5) as f32 / 5.0 + 0.1);
            let (q, pdf) = d.sample(r, u).unwrap();
            assert!((q.p - d.center).length() <= 0.5 + 1e-6);
            let c = d.intersect(r, q.p - r, 2.0);
            let (_, qq) = *c.first().unwrap();
            assert!((d.pdf(r, &qq) - pdf).abs() < 1e-3 * pdf);
        }
        assert!(d
            .intersect(Vec3A::new(0.6, 0.0, 0.0), Vec3A::Z, 10.0)
            .is_empty());
        assert!(Disc::new(Vec3A::ZERO, Vec3A::Z, 0.0).is_err());
    }
}
