//! One bottom-level structure: the shapes of the world (or of one object), a BVH over their
//! triangles and quadrics, closest-hit and any-hit queries, and hit geometry.

use super::bvh::{padded, Bvh, BvhOptions};
use crate::geometry::frame::LocalGeometry;
use crate::geometry::is_unit;
use crate::shape::{triangle, Shape};
use glam::Vec3A;
use obvhs::aabb::Aabb;

/// A BVH leaf item: a triangle (vertices inline for the hot loop) or a whole quadric.
#[derive(Clone, Debug)]
enum Item {
    Tri {
        v: [Vec3A; 3],
        shape: u32,
        index: u32,
    },
    Quadric {
        shape: u32,
    },
}

/// A hit found by traversal: distance (in the caller's ray parameter), the item slot and,
/// for a triangle, the barycentric coordinates the traversal's test found (so that
/// [`Blas::hit_geometry`] need not intersect the triangle again).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlasHit {
    pub t: f32,
    pub slot: u32,
    pub b: [f32; 3],
}

#[derive(Clone, Debug)]
pub struct Blas {
    pub shapes: Vec<Shape>,
    /// Primitive id reported for hits on each shape.
    pub prims: Vec<u32>,
    items: Vec<Item>,
    pub(crate) bvh: Bvh,
    pub lo: Vec3A,
    pub hi: Vec3A,
}

impl Blas {
    pub fn build(shapes: Vec<Shape>, prims: Vec<u32>, opts: BvhOptions) -> Blas {
        let mut items = Vec::new();
        let mut boxes = Vec::new();
        for (si, shape) in shapes.iter().enumerate() {
            match shape {
                Shape::Mesh(m) => {
                    for i in 0..m.tris.len() {
                        let v = m.vertices(i);
                        let lo = v[0].min(v[1]).min(v[2]);
                        let hi = v[0].max(v[1]).max(v[2]);
                        boxes.push(padded(lo, hi));
                        items.push(Item::Tri {
                            v,
                            shape: si as u32,
                            index: i as u32,
                        });
                    }
                }
                Shape::Quadric(q) => {
                    let (lo, hi) = q.bounds();
                    boxes.push(padded(lo, hi));
                    items.push(Item::Quadric { shape: si as u32 });
                }
            }
        }
        let (lo, hi) = boxes.iter().fold(
            (Vec3A::splat(f32::INFINITY), Vec3A::splat(f32::NEG_INFINITY)),
            |(lo, hi), b: &Aabb| (lo.min(b.min), hi.max(b.max)),
        );
        let (bvh, perm) = Bvh::build(&boxes, opts);
        let items = perm.iter().map(|&i| items[i as usize].clone()).collect();
        Blas {
            shapes,
            prims,
            items,
            bvh,
            lo,
            hi,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    #[inline(always)]
    fn item_t(&self, slot: usize, o: Vec3A, d: Vec3A, t_max: f32) -> f32 {
        match &self.items[slot] {
            Item::Tri { v, .. } => {
                triangle::intersect(v, o, d, t_max).map_or(f32::INFINITY, |h| h.t)
            }
            Item::Quadric { shape } => match &self.shapes[*shape as usize] {
                Shape::Quadric(q) => q.intersect_t(o, d, t_max).unwrap_or(f32::INFINITY),
                Shape::Mesh(_) => f32::INFINITY,
            },
        }
    }

    /// Closest hit of `o + t d`, 0 < t < t_max (any direction length).
    #[inline]
    pub fn closest(&self, o: Vec3A, d: Vec3A, t_max: f32) -> Option<BlasHit> {
        let (dn, len) = unit_direction(d)?;
        let tm = t_max * len;
        // Barycentrics of the last accepted triangle hit: every hit `item_t` reports is
        // below the traversal's current t_max, so the last one reported is the winner.
        let mut best = (u32::MAX, [0.0f32; 3]);
        let found = self.bvh.closest(o, dn, tm, |o, d, tm, slot| {
            self.item_hit(slot, o, d, tm, &mut best)
        });
        found.map(|(slot, t)| BlasHit {
            t: t / len,
            slot: slot as u32,
            b: if best.0 as usize == slot {
                best.1
            } else {
                [f32::NAN; 3]
            },
        })
    }

    /// As [`Self::item_t`], recording a triangle hit's slot and barycentrics in `best`.
    #[inline(always)]
    fn item_hit(
        &self,
        slot: usize,
        o: Vec3A,
        d: Vec3A,
        t_max: f32,
        best: &mut (u32, [f32; 3]),
    ) -> f32 {
        match &self.items[slot] {
            Item::Tri { v, .. } => match triangle::intersect(v, o, d, t_max) {
                Some(h) => {
                    *best = (slot as u32, h.b);
                    h.t
                }
                None => f32::INFINITY,
            },
            Item::Quadric { shape } => match &self.shapes[*shape as usize] {
                Shape::Quadric(q) => q.intersect_t(o, d, t_max).unwrap_or(f32::INFINITY),
                Shape::Mesh(_) => f32::INFINITY,
            },
        }
    }

    /// Whether anything is hit with 0 < t < t_max.
    #[inline]
    pub fn any(&self, o: Vec3A, d: Vec3A, t_max: f32) -> bool {
        let Some((dn, len)) = unit_direction(d) else {
            return false;
        };
        self.bvh.any(o, dn, t_max * len, |o, d, tm, slot| {
            self.item_t(slot, o, d, tm)
        })
    }

    /// Geometry of the hit found by [`Self::closest`] for the same ray, and its primitive id
    /// (a triangle's point comes from the hit's barycentrics).
    pub fn hit_geometry(
        &self,
        hit: BlasHit,
        o: Vec3A,
        d: Vec3A,
        t_max: f32,
    ) -> Option<(LocalGeometry, u32)> {
        let (dn, len) = unit_direction(d)?;
        let tm = t_max * len;
        match self.items.get(hit.slot as usize)? {
            Item::Tri { v, shape, index } => {
                // Barycentrics from the traversal; re-intersect only if they were not kept.
                let b = if hit.b[0].is_nan() {
                    triangle::intersect(v, o, dn, tm)?.b
                } else {
                    hit.b
                };
                let Shape::Mesh(m) = &self.shapes[*shape as usize] else {
                    return None;
                };
                Some((m.geometry(*index as usize, b), self.prims[*shape as usize]))
            }
            Item::Quadric { shape } => {
                let Shape::Quadric(q) = &self.shapes[*shape as usize] else {
                    return None;
                };
                let (_, g) = q.intersect(o, dn, tm)?;
                Some((g, self.prims[*shape as usize]))
            }
        }
    }

    pub fn triangle_count(&self) -> usize {
        self.shapes.iter().map(Shape::triangle_count).sum()
    }

    pub fn quadric_count(&self) -> usize {
        self.shapes
            .iter()
            .filter(|s| matches!(s, Shape::Quadric(_)))
            .count()
    }
}

/// The unit direction of `d` and the factor between the caller's ray parameter and distance:
/// the length of `d`, or exactly 1 when `d` is unit to within a few roundings (taken as unit
/// as it is, which skips a square root and a division for most rays); None when `d` has no
/// usable length.
#[inline(always)]
pub(crate) fn unit_direction(d: Vec3A) -> Option<(Vec3A, f32)> {
    if is_unit(d) {
        return Some((d, 1.0));
    }
    let len = d.length();
    (len > 0.0 && len.is_finite()).then(|| (d / len, len))
}
