//! `LightSource "rectangle"`: a flat parallelogram emitter (mental ray's rectangle area light)
//! centred on `point from` ([0 0 0]) and spanned by the full edge vectors `vector edgeu`
//! ([1 0 0]) and `vector edgev` ([0 1 0]); its front side (the one that emits unless
//! `twosided`) faces edgeu × edgev. Points are sampled uniformly by area.

use super::primshape::{plane_crossing, solid_angle_pdf, Crossings, LightShape, PrimPoint};
use crate::lxs::ParamSet;
use glam::{Mat4, Vec2, Vec3A};

#[derive(Clone, Copy, Debug)]
pub struct Rectangle {
    center: Vec3A,
    u: Vec3A,
    v: Vec3A,
    n: Vec3A,
    /// Dual basis: (p − center)·du and ·dv are p's coordinates along u and v.
    du: Vec3A,
    dv: Vec3A,
    area: f32,
}

impl Rectangle {
    /// The rectangle centred on `center` with edges `u`, `v` (world space).
    pub fn new(center: Vec3A, u: Vec3A, v: Vec3A) -> Result<Rectangle, String> {
        let cross = u.cross(v);
        let area = cross.length();
        if !(area > 0.0 && area.is_finite() && center.is_finite()) {
            return Err(format!(
                "rectangle edges {u} and {v} do not span a rectangle (zero or non-finite area)"
            ));
        }
        let n = cross / area;
        let vn = v.cross(n);
        let nu = n.cross(u);
        Ok(Rectangle {
            center,
            u,
            v,
            n,
            du: vn / u.dot(vn),
            dv: nu / v.dot(nu),
            area,
        })
    }
}

/// Reads `from`, `edgeu`, `edgev` and places the rectangle in the world.
pub fn build(p: &ParamSet, l2w: Mat4) -> Result<Rectangle, String> {
    let from = Vec3A::from_array(p.point("from").unwrap_or([0.0; 3]));
    let u = Vec3A::from_array(p.vector("edgeu").unwrap_or([1.0, 0.0, 0.0]));
    let v = Vec3A::from_array(p.vector("edgev").unwrap_or([0.0, 1.0, 0.0]));
    Rectangle::new(
        l2w.transform_point3a(from),
        l2w.transform_vector3a(u),
        l2w.transform_vector3a(v),
    )
}

impl LightShape for Rectangle {
    fn area(&self) -> f32 {
        self.area
    }

    fn sample(&self, r: Vec3A, u: Vec2) -> Option<(PrimPoint, f32)> {
        let q = PrimPoint {
            p: self.center + (u.x - 0.5) * self.u + (u.y - 0.5) * self.v,
            n: self.n,
        };
        let pdf = solid_angle_pdf(1.0 / self.area, r, &q);
        (pdf > 0.0 && pdf.is_finite()).then_some((q, pdf))
    }

    fn pdf(&self, r: Vec3A, q: &PrimPoint) -> f32 {
        solid_angle_pdf(1.0 / self.area, r, q)
    }

    fn intersect(&self, o: Vec3A, d: Vec3A, t_max: f32) -> Crossings {
        let mut out = Crossings::default();
        if let Some(t) = plane_crossing(self.center, self.n, o, d, t_max) {
            let w = o + d * t - self.center;
            if w.dot(self.du).abs() <= 0.5 && w.dot(self.dv).abs() <= 0.5 {
                out.push(
                    t,
                    PrimPoint {
                        p: o + d * t,
                        n: self.n,
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
    fn parallelogram_bounds_and_sampling() {
        // A sheared parallelogram: edges (2, 0, 0) and (1, 1, 0), centred at z = 1.
        let r = Rectangle::new(
            Vec3A::new(0.0, 0.0, 1.0),
            Vec3A::new(2.0, 0.0, 0.0),
            Vec3A::new(1.0, 1.0, 0.0),
        )
        .unwrap();
        assert!((r.area() - 2.0).abs() < 1e-6);
        assert_eq!(r.n, Vec3A::Z);
        // The corner (1.5, 0.5) is inside, (−1.4, 0.45) too, (1.4, −0.45) is not.
        let hit = |x: f32, y: f32| {
            !r.intersect(Vec3A::new(x, y, 0.0), Vec3A::Z, f32::INFINITY)
                .is_empty()
        };
        assert!(hit(1.49, 0.49) && hit(-1.4, -0.45) && !hit(1.4, -0.45));
        // Samples land inside and the pdf agrees with pdf().
        for i in 0..16 {
            let u = Vec2::new((i % 4) as f32 / 4.0 + 0.1, (i / 4) as f32 / 4.0 + 0.1);
            let (q, pdf) = r.sample(Vec3A::ZERO, u).unwrap();
            let c = r.intersect(Vec3A::ZERO, q.p, 2.0);
            let (t, qq) = *c.first().unwrap();
            assert!((t - 1.0).abs() < 1e-5);
            assert!((r.pdf(Vec3A::ZERO, &qq) - pdf).abs() < 1e-4 * pdf);
        }
        assert!(Rectangle::new(Vec3A::ZERO, Vec3A::X, Vec3A::X).is_err());
    }
}
