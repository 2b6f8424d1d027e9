//! What the area primitives (rectangle, disc, sphere, cylinder) have in common as shapes:
//! a point with its normal, the crossings of a ray, and the [`LightShape`] interface each
//! primitive's file implements for [`super::primitive::PrimitiveLight`].
//!
//! ```text
//! LightShape::sample(r, u) --> point q on the surface + solid-angle density of r→q
//! LightShape::pdf(r, q)    --> that density for any q (MIS)
//! LightShape::intersect(ray) --> every crossing (the primitives are not scene geometry:
//!                               rays pass through them, so each crossing is an emitter hit)
//! ```

use glam::{Vec2, Vec3A};

/// A point on a primitive with its unit normal (outward, or the front side of a flat one).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PrimPoint {
    pub p: Vec3A,
    pub n: Vec3A,
}

/// The (at most two) points where a ray crosses a primitive, nearest first.
#[derive(Clone, Copy, Debug, Default)]
pub struct Crossings {
    len: usize,
    hits: [(f32, PrimPoint); 2],
}

impl Crossings {
    /// Adds a crossing at ray parameter `t` (ignored when two are already kept).
    pub fn push(&mut self, t: f32, q: PrimPoint) {
        if let Some(slot) = self.hits.get_mut(self.len) {
            *slot = (t, q);
            self.len += 1;
        }
        if self.len == 2 && self.hits[1].0 < self.hits[0].0 {
            self.hits.swap(0, 1);
        }
    }

    pub fn iter(&self) -> impl Iterator<Item = &(f32, PrimPoint)> {
        self.hits.iter().take(self.len)
    }

    pub fn first(&self) -> Option<&(f32, PrimPoint)> {
        self.iter().next()
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
}

/// The geometry of an area primitive, in world space.
pub trait LightShape {
    /// Surface area.
    fn area(&self) -> f32;
    /// A point for a light sample seen from `r`, with the solid-angle density of the
    /// direction from `r` to it (`None` when nothing can be sampled from there).
    fn sample(&self, r: Vec3A, u: Vec2) -> Option<(PrimPoint, f32)>;
    /// The solid-angle density with which [`Self::sample`] returns `q` from `r`.
    fn pdf(&self, r: Vec3A, q: &PrimPoint) -> f32;
    /// Every crossing of the ray `o + t d` with `0 < t < t_max`.
    fn intersect(&self, o: Vec3A, d: Vec3A, t_max: f32) -> Crossings;
}

/// An area density at `q` as a solid-angle density seen from `r` (0 when degenerate).
pub fn solid_angle_pdf(pdf_area: f32, r: Vec3A, q: &PrimPoint) -> f32 {
    let d = q.p - r;
    let d2 = d.length_squared();
    if d2 <= 0.0 {
        return 0.0;
    }
    let cos = q.n.dot(d).abs() / d2.sqrt();
    if cos > 0.0 && cos.is_finite() {
        pdf_area * d2 / cos
    } else {
        0.0
    }
}

/// The crossing of `o + t d` with the plane through `c` of unit normal `n`, if 0 < t < t_max.
pub fn plane_crossing(c: Vec3A, n: Vec3A, o: Vec3A, d: Vec3A, t_max: f32) -> Option<f32> {
    let dn = d.dot(n);
    if dn == 0.0 || !dn.is_finite() {
        return None;
    }
    let t = (c - o).dot(n) / dn;
    (t > 0.0 && t < t_max).then_some(t)
}

/// The roots of a t² + b t + c = 0 (a > 0), smaller first, computed without cancellation.
pub fn quadratic(a: f64, b: f64, c: f64) -> Option<(f64, f64)> {
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 || a == 0.0 {
        return None;
    }
    let root = disc.sqrt();
    let q = if b < 0.0 {
        -0.5 * (b - root)
    } else {
        -0.5 * (b + root)
    };
    let (t0, t1) = if q == 0.0 { (0.0, 0.0) } else { (q / a, c / q) };
    Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossings_keep_the_nearest_first() {
        let mut c = Crossings::default();
        assert!(c.is_empty());
        c.push(3.0, PrimPoint::default());
        c.push(1.0, PrimPoint::default());
        c.push(0.5, PrimPoint::default());
        let ts: Vec<f32> = c.iter().map(|h| h.0).collect();
        assert_eq!(ts, vec![1.0, 3.0]);
    }

    #[test]
    fn quadratic_roots_are_ordered_and_stable() {
        let (a, b) = quadratic(1.0, -3.0, 2.0).unwrap();
        assert!((a - 1.0).abs() < 1e-12 && (b - 2.0).abs() < 1e-12);
        let (a, b) = quadratic(1.0, -1e8, 1.0).unwrap();
        assert!((a - 1e-8).abs() < 1e-20 && (b - 1e8).abs() < 1.0);
        assert!(quadratic(1.0, 0.0, 1.0).is_none());
    }

    #[test]
    fn area_to_solid_angle() {
        let q = PrimPoint {
            p: Vec3A::new(0.0, 0.0, 2.0),
            n: -Vec3A::Z,
        };
        // d² / cos at distance 2 head-on: 4.
        assert!((solid_angle_pdf(1.0, Vec3A::ZERO, &q) - 4.0).abs() < 1e-6);
        assert_eq!(solid_angle_pdf(1.0, q.p, &q), 0.0);
    }
}
