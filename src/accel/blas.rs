//! One bottom-level structure: the shapes of the world (or of one object), a BVH over their
//! triangles and quadrics, closest-hit and any-hit queries, and hit geometry.
//!
//! With the 8-wide layout each leaf's triangles sit in SIMD packets of four
//! ([`super::tri4`]): leaves start at multiples of four slots, and slot `s` is lane `s % 4`
//! of packet `s / 4`. A packet's quadrics are tested one by one after its triangles (so on an
//! exactly equal distance a triangle wins over a quadric of the same packet).

use super::bvh::{padded, Bvh, BvhLayout, BvhOptions};
use super::bvh8::EMPTY_SLOT;
use super::tri4::{RayTri, Tri4, LANES};
use crate::geometry::frame::LocalGeometry;
use crate::geometry::is_unit;
use crate::shape::{triangle, Shape};
use glam::Vec3A;
use obvhs::aabb::Aabb;

/// A BVH leaf item: a triangle of a mesh, a whole quadric, or padding.
#[derive(Clone, Copy, Debug)]
enum Item {
    Tri { shape: u32, index: u32 },
    Quadric { shape: u32 },
    Empty,
}

/// Four slots' triangles for the SIMD test and the lanes that hold quadrics.
#[derive(Clone, Debug)]
struct Pack {
    tris: Tri4,
    quadrics: u32,
}

/// A hit found by traversal: distance (in the caller's ray parameter), the item slot and,
/// for a triangle, the barycentric coordinates the traversal's test found (so that
/// [`Blas::hit_geometry`] need not intersect the triangle again). The barycentrics are one
/// SIMD value, written and read whole: as three floats, the caller's 16-byte copy of a hit
/// read them back before their three 4-byte stores could be forwarded, a stall that cost
/// 1-2% of a Cornell render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlasHit {
    pub t: f32,
    pub slot: u32,
    pub b: Vec3A,
}

#[derive(Clone, Debug)]
pub struct Blas {
    pub shapes: Vec<Shape>,
    /// Primitive id reported for hits on each shape.
    pub prims: Vec<u32>,
    items: Vec<Item>,
    /// Triangle vertices per slot (layouts without packets; empty with them).
    verts: Vec<[Vec3A; 3]>,
    /// Per four slots (8-wide layout): their triangles as a SIMD packet.
    packs: Vec<Pack>,
    pub(crate) bvh: Bvh,
    pub lo: Vec3A,
    pub hi: Vec3A,
}

impl Blas {
    pub fn build(shapes: Vec<Shape>, prims: Vec<u32>, opts: BvhOptions) -> Blas {
        let mut items = Vec::new();
        let mut verts = Vec::new();
        let mut boxes = Vec::new();
        for (si, shape) in shapes.iter().enumerate() {
            match shape {
                Shape::Mesh(m) => {
                    for i in 0..m.tris.len() {
                        let v = m.vertices(i);
                        let lo = v[0].min(v[1]).min(v[2]);
                        let hi = v[0].max(v[1]).max(v[2]);
                        boxes.push(padded(lo, hi));
                        verts.push(v);
                        items.push(Item::Tri {
                            shape: si as u32,
                            index: i as u32,
                        });
                    }
                }
                Shape::Quadric(q) => {
                    let (lo, hi) = q.bounds();
                    boxes.push(padded(lo, hi));
                    verts.push([Vec3A::NAN; 3]);
                    items.push(Item::Quadric { shape: si as u32 });
                }
            }
        }
        let (lo, hi) = boxes.iter().fold(
            (Vec3A::splat(f32::INFINITY), Vec3A::splat(f32::NEG_INFINITY)),
            |(lo, hi), b: &Aabb| (lo.min(b.min), hi.max(b.max)),
        );
        let packed = opts.layout == BvhLayout::Bvh8;
        let (bvh, perm) = Bvh::build_aligned(&boxes, opts, if packed { LANES } else { 1 });
        let at = |i: u32| (i != EMPTY_SLOT).then_some(i as usize);
        let slot_items = perm
            .iter()
            .map(|&i| at(i).map_or(Item::Empty, |i| items[i]))
            .collect();
        let (verts, packs) = if packed {
            let packs = perm
                .chunks(LANES)
                .map(|c| Pack::new(c, &items, &verts))
                .collect();
            (Vec::new(), packs)
        } else {
            (
                perm.iter().map(|&i| verts[i as usize]).collect(),
                Vec::new(),
            )
        };
        Blas {
            shapes,
            prims,
            items: slot_items,
            verts,
            packs,
            bvh,
            lo,
            hi,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// The vertices of the triangle in `slot` (NaN for other items).
    fn tri_vertices(&self, slot: usize) -> [Vec3A; 3] {
        match self.packs.get(slot / LANES) {
            Some(p) => p.tris.vertices(slot % LANES),
            None => self.verts[slot],
        }
    }

    /// The distance of `slot`'s hit with 0 < t < t_max, or infinity (layouts without
    /// packets).
    #[inline(always)]
    fn item_t(&self, slot: usize, o: Vec3A, d: Vec3A, t_max: f32) -> f32 {
        match &self.items[slot] {
            Item::Tri { .. } => {
                triangle::intersect(&self.verts[slot], o, d, t_max).map_or(f32::INFINITY, |h| h.t)
            }
            Item::Quadric { shape } => self.quadric_t(*shape, o, d, t_max),
            Item::Empty => f32::INFINITY,
        }
    }

    #[inline(always)]
    fn quadric_t(&self, shape: u32, o: Vec3A, d: Vec3A, t_max: f32) -> f32 {
        match &self.shapes[shape as usize] {
            Shape::Quadric(q) => q.intersect_t(o, d, t_max).unwrap_or(f32::INFINITY),
            Shape::Mesh(_) => f32::INFINITY,
        }
    }

    /// Closest hit of `o + t d`, 0 < t < t_max (any direction length).
    #[inline]
    pub fn closest(&self, o: Vec3A, d: Vec3A, t_max: f32) -> Option<BlasHit> {
        let (dn, len) = unit_direction(d)?;
        let tm = t_max * len;
        // Barycentrics of the last accepted triangle hit: every hit reported is below the
        // traversal's current t_max, so the last one reported is the winner.
        let mut best = (u32::MAX, Vec3A::ZERO);
        let found = match &self.bvh {
            Bvh::Wide(w) if !self.packs.is_empty() => {
                let ray = RayTri::new(o, dn);
                w.closest_leaves(o, dn, tm, |first, count, tm| {
                    self.leaf_closest(&ray, first, count, tm, &mut best)
                })
            }
            _ => self.bvh.closest(o, dn, tm, |o, d, tm, slot| {
                self.item_hit(slot, o, d, tm, &mut best)
            }),
        };
        found.map(|(slot, t)| BlasHit {
            t: t / len,
            slot: slot as u32,
            b: if best.0 as usize == slot {
                best.1
            } else {
                Vec3A::NAN
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
        best: &mut (u32, Vec3A),
    ) -> f32 {
        match &self.items[slot] {
            Item::Tri { .. } => match triangle::intersect(&self.verts[slot], o, d, t_max) {
                Some(h) => {
                    *best = (slot as u32, Vec3A::from_array(h.b));
                    h.t
                }
                None => f32::INFINITY,
            },
            Item::Quadric { shape } => self.quadric_t(*shape, o, d, t_max),
            Item::Empty => f32::INFINITY,
        }
    }

    /// The closest hit in leaf slots `first..first + count` with t < t_max: packet by
    /// packet, its triangles and then its quadrics.
    #[inline(always)]
    fn leaf_closest(
        &self,
        ray: &RayTri,
        first: usize,
        count: usize,
        mut t_max: f32,
        best: &mut (u32, Vec3A),
    ) -> Option<(usize, f32)> {
        let mut hit = None;
        for k in first / LANES..(first + count).div_ceil(LANES) {
            let pack = &self.packs[k];
            if let Some(h) = pack.tris.closest(ray, t_max) {
                let slot = k * LANES + h.lane;
                t_max = h.t;
                *best = (slot as u32, Vec3A::from_array(h.b));
                hit = Some((slot, h.t));
            }
            if pack.quadrics != 0 {
                for lane in lanes(pack.quadrics) {
                    let slot = k * LANES + lane;
                    if let Item::Quadric { shape } = self.items[slot] {
                        let t = self.quadric_t(shape, ray.o, ray.d, t_max);
                        if t < t_max {
                            t_max = t;
                            hit = Some((slot, t));
                        }
                    }
                }
            }
        }
        hit
    }

    /// Whether leaf slots `first..first + count` have a hit with t < t_max.
    #[inline(always)]
    fn leaf_any(&self, ray: &RayTri, first: usize, count: usize, t_max: f32) -> bool {
        (first / LANES..(first + count).div_ceil(LANES)).any(|k| {
            let pack = &self.packs[k];
            pack.tris.any(ray, t_max)
                || lanes(pack.quadrics).any(|lane| match self.items[k * LANES + lane] {
                    Item::Quadric { shape } => self.quadric_t(shape, ray.o, ray.d, t_max) < t_max,
                    _ => false,
                })
        })
    }

    /// Whether anything is hit with 0 < t < t_max.
    #[inline]
    pub fn any(&self, o: Vec3A, d: Vec3A, t_max: f32) -> bool {
        let Some((dn, len)) = unit_direction(d) else {
            return false;
        };
        match &self.bvh {
            Bvh::Wide(w) if !self.packs.is_empty() => {
                let ray = RayTri::new(o, dn);
                w.any_leaves(o, dn, t_max * len, |first, count, tm| {
                    self.leaf_any(&ray, first, count, tm)
                })
            }
            _ => self.bvh.any(o, dn, t_max * len, |o, d, tm, slot| {
                self.item_t(slot, o, d, tm)
            }),
        }
    }

    /// Geometry of the hit found by [`Self::closest`] for the same ray, and its primitive id
    /// (a triangle's point comes from the hit's barycentrics, a quadric's from its distance).
    #[inline(always)]
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
            Item::Tri { shape, index } => {
                // Barycentrics from the traversal; re-intersect only if they were not kept.
                // The slot's stored vertices (its packet's, just tested and in cache, or
                // `verts` in the other layouts): the mesh's bit for bit.
                let v = self.tri_vertices(hit.slot as usize);
                let b = if hit.b.x.is_nan() {
                    triangle::intersect(&v, o, dn, tm)?.b
                } else {
                    hit.b.to_array()
                };
                let Shape::Mesh(m) = &self.shapes[*shape as usize] else {
                    return None;
                };
                Some((
                    m.geometry_of(*index as usize, v, b),
                    self.prims[*shape as usize],
                ))
            }
            Item::Empty => None,
            Item::Quadric { shape } => {
                let Shape::Quadric(q) = &self.shapes[*shape as usize] else {
                    return None;
                };
                // The traversal's distance (in the caller's units) locates the hit.
                let t = hit.t * len;
                if !(t > 0.0 && t.is_finite()) {
                    return None;
                }
                Some((q.geometry_at_t(o, dn, t), self.prims[*shape as usize]))
            }
        }
    }

    /// Packets, and those holding both triangles and quadrics (tests).
    #[cfg(test)]
    pub(crate) fn packet_counts(&self) -> (usize, usize) {
        let mixed = self
            .packs
            .iter()
            .filter(|p| p.quadrics != 0 && p.tris.lanes() != 0)
            .count();
        (self.packs.len(), mixed)
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

impl Pack {
    /// The packet of slots whose items are `perm`'s entries (source indices into `items`
    /// and `verts`, or [`EMPTY_SLOT`]).
    fn new(perm: &[u32], items: &[Item], verts: &[[Vec3A; 3]]) -> Pack {
        let mut tris = [None; LANES];
        let mut quadrics = 0;
        for (lane, &i) in perm.iter().enumerate() {
            match items.get(i as usize) {
                Some(Item::Tri { .. }) => tris[lane] = Some(verts[i as usize]),
                Some(Item::Quadric { .. }) => quadrics |= 1 << lane,
                _ => {}
            }
        }
        Pack {
            tris: Tri4::new(tris),
            quadrics,
        }
    }
}

/// The lanes set in `mask`, lowest first.
fn lanes(mask: u32) -> impl Iterator<Item = usize> {
    (0..LANES).filter(move |l| mask & (1 << l) != 0)
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
