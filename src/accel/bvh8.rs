//! An uncompressed 8-wide BVH collapsed from an obvhs binary BVH: each node holds its eight
//! children's boxes as f32 SoA lanes, two groups of four, so two SIMD slab tests cover all
//! eight (no dequantisation as in the CWBVH). A wide node means few levels: rendering the
//! Cornell benchmark, closest-hit rays visit 2.86 nodes and shadow rays 1.98, against 5.25
//! and 3.84 in a 4-wide tree of the same design, and traversal cost is mostly the control
//! flow of each visit. Closest-hit traversal tests a node's hit leaves nearest first (lowest
//! lane first among equal entry distances), skipping those whose box starts beyond the
//! current hit, then descends into the nearest inner child, leaves the others on the stack
//! nearest-last and culls entries farther than the current hit.
//!
//! Robustness: primitive boxes are padded (see [`super::bvh::padded`]), the reciprocal
//! direction is finite (tiny components map to ±1e20 with the sign of the component, so
//! `(bound - o) * inv` is never NaN), and exit distances are widened by 1 + 2γ(3) (through
//! a widened copy of the reciprocal, see [`Slab::far_scale`]) as pbrt widens them, so
//! rounding in the slab test can only make boxes look bigger.

use crate::geometry::transform::gamma;
use arrayvec::ArrayVec;
use glam::{Vec3A, Vec4};
use obvhs::bvh2::Bvh2;

/// Child slot of a node: an inner node, a leaf (slot range), or nothing.
const EMPTY: u32 = u32::MAX;

/// Permutation entry of a padding slot (see [`Bvh8::from_bvh2`]).
pub const EMPTY_SLOT: u32 = u32::MAX;

/// Children per node.
const WIDTH: usize = 8;

#[derive(Clone, Debug)]
#[repr(C, align(64))]
struct Node8 {
    /// `b[0]` the children's minima, `b[1]` their maxima, per axis; lanes 0-3, then 4-7.
    b: [[[Vec4; 2]; 3]; 2],
    /// Inner child: node index; leaf child: first slot; empty: [`EMPTY`].
    child: [u32; WIDTH],
    /// 0 for an inner (or empty) child, else the leaf's primitive count (obvhs caps leaves
    /// at 255 primitives).
    count: [u16; WIDTH],
    /// The lanes holding leaves, as a bit mask (`count[lane] != 0`).
    leaves: u8,
}

/// An 8-wide BVH; slots index the permutation [`Bvh8::from_bvh2`] returns.
#[derive(Clone, Debug, Default)]
pub struct Bvh8 {
    nodes: Vec<Node8>,
    /// Stack entries a traversal can need: at most 7 wait per level above the node being
    /// visited, and an any-hit visit pushes up to 8 before popping one.
    stack: usize,
}

/// Traversals whose stack fits this use an uninitialised array on the thread's stack
/// ([`ArrayVec`]: zeroing a 64-entry array per ray cost 1.2% of a Cornell render's
/// instructions); deeper trees a Vec.
const STACK: usize = 64;

/// A traversal stack: a fixed array for trees up to [`STACK`] entries deep, else a Vec.
trait TraversalStack<T> {
    fn push(&mut self, v: T);
    fn pop(&mut self) -> Option<T>;
}

impl<T, const N: usize> TraversalStack<T> for ArrayVec<T, N> {
    #[inline(always)]
    fn push(&mut self, v: T) {
        // In bounds: the tree's `stack` bound chose this capacity.
        ArrayVec::push(self, v)
    }

    #[inline(always)]
    fn pop(&mut self) -> Option<T> {
        ArrayVec::pop(self)
    }
}

impl<T> TraversalStack<T> for Vec<T> {
    #[inline(always)]
    fn push(&mut self, v: T) {
        Vec::push(self, v)
    }

    #[inline(always)]
    fn pop(&mut self) -> Option<T> {
        Vec::pop(self)
    }
}

/// Per-ray constants of the slab test.
struct Slab {
    o: [Vec4; 3],
    inv: [Vec4; 3],
    /// `inv` widened by 1 + 2γ(3) for the exit distances (see [`Slab::far_scale`]).
    inv_far: [Vec4; 3],
    /// Per axis: whether the near plane is the box's maximum (the direction is negative).
    near_is_max: [bool; 3],
}

impl Slab {
    fn new(o: Vec3A, d: Vec3A) -> Slab {
        let inv = |x: f32| {
            if x.abs() > 1e-20 {
                1.0 / x
            } else if x.is_sign_negative() {
                -1e20
            } else {
                1e20
            }
        };
        let i = Vec3A::new(inv(d.x), inv(d.y), inv(d.z));
        let f = i * Slab::far_scale();
        Slab {
            o: [Vec4::splat(o.x), Vec4::splat(o.y), Vec4::splat(o.z)],
            inv: [Vec4::splat(i.x), Vec4::splat(i.y), Vec4::splat(i.z)],
            inv_far: [Vec4::splat(f.x), Vec4::splat(f.y), Vec4::splat(f.z)],
            near_is_max: [i.x < 0.0, i.y < 0.0, i.z < 0.0],
        }
    }

    /// The widening of exit distances: the exit is computed with the reciprocal scaled by
    /// s = fl(1 + 2γ(3)) = 1 + 6u (u = 2⁻²⁴, half an ulp of 1). Entry and exit use the same
    /// rounded reciprocal, so a box the ray truly crosses keeps entry ≤ exit as long as s
    /// covers the other roundings: the entry's difference and product (up to (1 + u)²) and
    /// the exit's difference, product and scaled reciprocal (down to (1 − u)³), i.e.
    /// s ≥ (1 + u)² / (1 − u)³ ≈ 1 + 5u, which 1 + 6u is. (pbrt's order, scaling the
    /// computed exit, rests on the same margin.) Boxes can only look bigger.
    fn far_scale() -> f32 {
        1.0 + 2.0 * gamma(3)
    }

    /// Entry distances of the four boxes of `node`'s lane group `g` and the mask of those
    /// the ray crosses within [0, t_max]. Planes are read from the node in place.
    #[inline(always)]
    fn test_group(&self, node: &Node8, g: usize, t_max: f32) -> (Vec4, u32) {
        let mut t0 = Vec4::ZERO;
        let mut t1 = Vec4::splat(t_max);
        for a in 0..3 {
            let near_max = self.near_is_max[a];
            let near = node.b[usize::from(near_max)][a][g];
            let far = node.b[usize::from(!near_max)][a][g];
            t0 = t0.max((near - self.o[a]) * self.inv[a]);
            t1 = t1.min((far - self.o[a]) * self.inv_far[a]);
        }
        (t0, t0.cmple(t1).bitmask())
    }
}

impl Bvh8 {
    /// Collapses `b`. Leaves get new slots: each starts at a multiple of `align` and takes
    /// a multiple of `align` slots (so a caller can keep leaf primitives in SIMD packets of
    /// that width). Returns the tree and its permutation: slot `i` is primitive `perm[i]` of
    /// the source's boxes, or [`EMPTY_SLOT`] for padding.
    pub fn from_bvh2(b: &Bvh2, align: usize) -> (Bvh8, Vec<u32>) {
        let mut c = Collapse {
            src: b,
            align: align.max(1),
            out: Bvh8::default(),
            perm: Vec::new(),
        };
        let Some(root) = b.nodes.first() else {
            return (c.out, c.perm);
        };
        let depth = if root.prim_count > 0 {
            let mut n = Node8::empty();
            let first = c.leaf(root.first_index, root.prim_count);
            n.set(0, root.aabb.min, root.aabb.max, first, root.prim_count);
            c.out.nodes.push(n);
            1
        } else {
            c.emit(0).1
        };
        c.out.stack = (WIDTH - 1) * depth + 1;
        (c.out, c.perm)
    }

    /// Closest hit along `o + t d`, 0 < t < t_max: `f(slot, t_max)` returns the distance of
    /// a hit with `t < t_max` or infinity. Returns the winning slot and distance.
    #[inline]
    pub fn closest(
        &self,
        o: Vec3A,
        d: Vec3A,
        t_max: f32,
        mut f: impl FnMut(usize, f32) -> f32,
    ) -> Option<(usize, f32)> {
        self.closest_leaves(o, d, t_max, |first, count, mut t_max| {
            let mut best = None;
            for slot in first..first + count {
                let t = f(slot, t_max);
                if t < t_max {
                    t_max = t;
                    best = Some((slot, t));
                }
            }
            best
        })
    }

    /// As [`Self::closest`], a leaf at a time: `leaf(first, count, t_max)` returns the
    /// leaf's closest hit with `t < t_max` (slot and distance), if any. Leaves are called
    /// nearest first within a node, and not at all once a hit lies before their box.
    #[inline]
    pub fn closest_leaves(
        &self,
        o: Vec3A,
        d: Vec3A,
        t_max: f32,
        leaf: impl FnMut(usize, usize, f32) -> Option<(usize, f32)>,
    ) -> Option<(usize, f32)> {
        if self.nodes.is_empty() {
            return None;
        }
        if self.stack <= STACK {
            self.closest_in(&mut ArrayVec::<_, STACK>::new(), o, d, t_max, leaf)
        } else {
            self.closest_in(&mut Vec::with_capacity(self.stack), o, d, t_max, leaf)
        }
    }

    #[inline(always)]
    fn closest_in(
        &self,
        stack: &mut impl TraversalStack<(u32, f32)>,
        o: Vec3A,
        d: Vec3A,
        t_max: f32,
        mut leaf: impl FnMut(usize, usize, f32) -> Option<(usize, f32)>,
    ) -> Option<(usize, f32)> {
        let slab = Slab::new(o, d);
        let mut best: Option<(usize, f32)> = None;
        let mut t_max = t_max;
        let mut next = Some(0u32);
        loop {
            let ni = match next.take() {
                Some(ni) => ni,
                None => loop {
                    let Some((ni, t_in)) = stack.pop() else {
                        return best;
                    };
                    if t_in <= t_max {
                        break ni;
                    }
                },
            };
            let node = &self.nodes[ni as usize];
            let (t0, mask) = node.test(&slab, t_max);
            // Leaves first, nearest first, each skipped once a nearer hit lies before its
            // box (a ray through a closed mesh crosses the boxes of its far side too); then
            // inner children far to near. The hit lanes split into the two by mask, without
            // a branch per lane.
            let leaf_lanes = u32::from(node.leaves);
            let mut inner = ArrayVec::<(u32, f32), WIDTH>::new();
            for lane in lanes(mask & !leaf_lanes) {
                inner.push((node.child[lane], t0[lane]));
            }
            let mut leaves = ArrayVec::<(u32, f32), WIDTH>::new();
            for lane in lanes(mask & leaf_lanes) {
                leaves.push((lane as u32, t0[lane]));
            }
            sort_near_to_far(&mut leaves);
            for &(lane, t_in) in leaves.iter() {
                if t_in > t_max {
                    break;
                }
                let (first, count) = (node.child[lane as usize], node.count[lane as usize]);
                if let Some(hit) = leaf(first as usize, count as usize, t_max) {
                    t_max = hit.1;
                    best = Some(hit);
                }
            }
            sort_far_to_near(&mut inner);
            let Some((nearest, t_near)) = inner.pop() else {
                continue;
            };
            for &entry in &inner {
                // At most 7 entries per level are left behind (see `stack`).
                stack.push(entry);
            }
            if t_near <= t_max {
                next = Some(nearest);
            }
        }
    }

    /// Whether `f(slot, t_max) < t_max` for any primitive whose box the ray crosses.
    #[inline]
    pub fn any(
        &self,
        o: Vec3A,
        d: Vec3A,
        t_max: f32,
        mut f: impl FnMut(usize, f32) -> f32,
    ) -> bool {
        self.any_leaves(o, d, t_max, |first, count, t_max| {
            (first..first + count).any(|slot| f(slot, t_max) < t_max)
        })
    }

    /// As [`Self::any`], a leaf at a time: `leaf(first, count, t_max)` says whether the
    /// leaf has a hit with `t < t_max`.
    #[inline]
    pub fn any_leaves(
        &self,
        o: Vec3A,
        d: Vec3A,
        t_max: f32,
        leaf: impl FnMut(usize, usize, f32) -> bool,
    ) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        if self.stack <= STACK {
            self.any_in(&mut ArrayVec::<_, STACK>::new(), o, d, t_max, leaf)
        } else {
            self.any_in(&mut Vec::with_capacity(self.stack), o, d, t_max, leaf)
        }
    }

    #[inline(always)]
    fn any_in(
        &self,
        stack: &mut impl TraversalStack<u32>,
        o: Vec3A,
        d: Vec3A,
        t_max: f32,
        mut leaf: impl FnMut(usize, usize, f32) -> bool,
    ) -> bool {
        let slab = Slab::new(o, d);
        stack.push(0);
        while let Some(ni) = stack.pop() {
            let node = &self.nodes[ni as usize];
            let (_, mut mask) = node.test(&slab, t_max);
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let count = node.count[lane];
                if count == 0 {
                    stack.push(node.child[lane]);
                    continue;
                }
                if leaf(node.child[lane] as usize, count as usize, t_max) {
                    return true;
                }
            }
        }
        false
    }
}

/// The set bits of `mask`, lowest first.
#[inline(always)]
fn lanes(mut mask: u32) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        let lane = (mask != 0).then(|| mask.trailing_zeros() as usize);
        mask &= mask.wrapping_sub(1);
        lane
    })
}

/// Sorts (lane or child, entry distance) pairs near to far, equal distances kept in their
/// given (lane) order, so ties are broken as the lane-order loop before the sort broke them.
#[inline(always)]
fn sort_near_to_far(v: &mut [(u32, f32)]) {
    insertion_sort(v, |a, b| a > b);
}

/// Sorts (child, entry distance) pairs far to near, ties in their given order.
#[inline(always)]
fn sort_far_to_near(v: &mut [(u32, f32)]) {
    insertion_sort(v, |a, b| a < b);
}

/// Stable insertion sort by entry distance (a node's hit children are usually two or
/// three): an entry moves before its predecessor while `out_of_order(predecessor, entry)`.
#[inline(always)]
fn insertion_sort(v: &mut [(u32, f32)], out_of_order: impl Fn(f32, f32) -> bool) {
    for i in 1..v.len() {
        let mut j = i;
        while j > 0 && out_of_order(v[j - 1].1, v[j].1) {
            v.swap(j - 1, j);
            j -= 1;
        }
    }
}

/// State of [`Bvh8::from_bvh2`].
struct Collapse<'a> {
    src: &'a Bvh2,
    align: usize,
    out: Bvh8,
    perm: Vec<u32>,
}

impl Collapse<'_> {
    /// Gives the source leaf `first..first + count` its aligned slots; returns the first.
    fn leaf(&mut self, first: u32, count: u32) -> u32 {
        let at = self.perm.len();
        let slot = u32::try_from(at).expect("more than 2^32 BVH slots");
        let (first, count) = (first as usize, count as usize);
        self.perm
            .extend_from_slice(&self.src.primitive_indices[first..first + count]);
        self.perm
            .resize(at + count.div_ceil(self.align) * self.align, EMPTY_SLOT);
        slot
    }

    /// Emits the 8-wide node for inner node `i` of the source and its subtree (children expanded
    /// widest first); returns its index and the subtree's depth in 8-wide nodes.
    fn emit(&mut self, i: usize) -> (u32, usize) {
        let b = self.src;
        let first = b.nodes[i].first_index as usize;
        let mut kids = vec![first, first + 1];
        while kids.len() < WIDTH {
            let widest = kids
                .iter()
                .enumerate()
                .filter(|(_, &k)| b.nodes[k].prim_count == 0)
                .max_by(|a, c| {
                    let area = |k: usize| b.nodes[k].aabb.half_area();
                    area(*a.1).total_cmp(&area(*c.1))
                })
                .map(|(j, _)| j);
            let Some(j) = widest else {
                break;
            };
            let k = kids.remove(j);
            let f = b.nodes[k].first_index as usize;
            kids.insert(j, f + 1);
            kids.insert(j, f);
        }
        let at = self.out.nodes.len();
        self.out.nodes.push(Node8::empty());
        let mut depth = 1;
        for (lane, &k) in kids.iter().enumerate() {
            let n = &b.nodes[k];
            let (child, count) = if n.prim_count > 0 {
                (self.leaf(n.first_index, n.prim_count), n.prim_count)
            } else {
                let (c, dd) = self.emit(k);
                depth = depth.max(dd + 1);
                (c, 0)
            };
            self.out.nodes[at].set(lane, n.aabb.min, n.aabb.max, child, count);
        }
        (at as u32, depth)
    }
}

impl Node8 {
    fn empty() -> Node8 {
        Node8 {
            b: [[[Vec4::INFINITY; 2]; 3], [[Vec4::NEG_INFINITY; 2]; 3]],
            child: [EMPTY; 8],
            count: [0; 8],
            leaves: 0,
        }
    }

    /// Sets child `lane`: its box, and its node index or slot range.
    fn set(&mut self, lane: usize, lo: Vec3A, hi: Vec3A, child: u32, count: u32) {
        let (g, l) = (lane / 4, lane % 4);
        for a in 0..3 {
            self.b[0][a][g][l] = lo[a];
            self.b[1][a][g][l] = hi[a];
        }
        self.child[lane] = child;
        self.count[lane] = u16::try_from(count).expect("a BVH leaf of over 65535 primitives");
        if count != 0 {
            self.leaves |= 1 << lane;
        }
    }

    /// Entry distances of the eight children and the mask of those hit within [0, t_max].
    #[inline(always)]
    fn test(&self, slab: &Slab, t_max: f32) -> ([f32; 8], u32) {
        let (lo_t, lo_mask) = slab.test_group(self, 0, t_max);
        let (hi_t, hi_mask) = slab.test_group(self, 1, t_max);
        let mut t = [0.0f32; 8];
        t[..4].copy_from_slice(&lo_t.to_array());
        t[4..].copy_from_slice(&hi_t.to_array());
        (t, lo_mask | hi_mask << 4)
    }
}

#[cfg(test)]
mod tests {
    use crate::accel::bvh::{padded, BuildQuality, Bvh, BvhLayout, BvhOptions};
    use crate::accel::tests::fixtures::Rng;
    use glam::Vec3A;
    use obvhs::aabb::Aabb;

    /// Entry distance of the ray into box `b` if it is in (0, t_max), else infinity.
    fn box_t(b: &Aabb, o: Vec3A, d: Vec3A, t_max: f32) -> f32 {
        let (mut t0, mut t1) = (0.0f32, t_max);
        for a in 0..3 {
            let (lo, hi) = ((b.min[a] - o[a]) / d[a], (b.max[a] - o[a]) / d[a]);
            t0 = t0.max(lo.min(hi));
            t1 = t1.min(lo.max(hi));
        }
        if t0 <= t1 && t0 > 0.0 && t0 < t_max {
            t0
        } else {
            f32::INFINITY
        }
    }

    #[test]
    fn closest_and_any_match_brute_force() {
        let mut rng = Rng::new(5);
        for (n, leaf) in [(1, 2), (7, 1), (300, 2), (2000, 4)] {
            let boxes: Vec<Aabb> = (0..n)
                .map(|i| {
                    let c = rng.in_box(Vec3A::splat(-10.0), Vec3A::splat(10.0));
                    let s = [0.01, 0.3, 2.0][i % 3];
                    padded(c - s, c + s)
                })
                .collect();
            let opts = BvhOptions {
                layout: BvhLayout::Bvh8,
                quality: BuildQuality::Medium,
                max_prims_per_leaf: leaf,
            };
            let (bvh, perm) = Bvh::build(&boxes, opts);
            let prim = |slot: usize| &boxes[perm[slot] as usize];
            for _ in 0..2000 {
                let o = rng.in_box(Vec3A::splat(-12.0), Vec3A::splat(12.0));
                let d = rng.direction();
                let t_max = 5.0 + 20.0 * rng.f32();
                let brute = (0..n)
                    .map(|s| (s, box_t(prim(s), o, d, t_max)))
                    .filter(|h| h.1 < t_max)
                    .min_by(|a, b| a.1.total_cmp(&b.1));
                let got = bvh.closest(o, d, t_max, |o, d, tm, s| box_t(prim(s), o, d, tm));
                assert_eq!(got.map(|h| h.1), brute.map(|h| h.1), "n {n}");
                let any = bvh.any(o, d, t_max, |o, d, tm, s| box_t(prim(s), o, d, tm));
                assert_eq!(any, brute.is_some(), "n {n}");
            }
        }
    }

    /// Leaves built for packets of four start at multiples of four slots and are padded
    /// with [`super::EMPTY_SLOT`]; every primitive has exactly one slot, and queries (which
    /// see padding as misses) match brute force.
    #[test]
    fn aligned_leaves_start_at_multiples_of_the_packet_width() {
        use super::EMPTY_SLOT;
        let mut rng = Rng::new(8);
        let n = 500;
        let boxes: Vec<Aabb> = (0..n)
            .map(|_| {
                let c = rng.in_box(Vec3A::splat(-10.0), Vec3A::splat(10.0));
                padded(c - 0.3, c + 0.3)
            })
            .collect();
        for leaf in [1, 3, 4, 8] {
            let opts = BvhOptions {
                layout: BvhLayout::Bvh8,
                quality: BuildQuality::Medium,
                max_prims_per_leaf: leaf,
            };
            let (bvh, perm) = Bvh::build_aligned(&boxes, opts, 4);
            let Bvh::Wide(wide) = &bvh else {
                panic!("expected the 8-wide layout");
            };
            assert_eq!(perm.len() % 4, 0);
            let mut leaves = 0;
            for node in &wide.nodes {
                for lane in (0..8).filter(|&l| node.count[l] > 0) {
                    let (first, count) = (node.child[lane] as usize, node.count[lane] as usize);
                    assert_eq!(first % 4, 0, "leaf {leaf}");
                    assert!(count <= leaf as usize);
                    let end = (first + count).div_ceil(4) * 4;
                    assert!(perm[first..first + count].iter().all(|&i| i != EMPTY_SLOT));
                    assert!(perm[first + count..end].iter().all(|&i| i == EMPTY_SLOT));
                    leaves += 1;
                }
            }
            assert!(leaves >= n / leaf as usize);
            let mut seen: Vec<u32> = perm.iter().copied().filter(|&i| i != EMPTY_SLOT).collect();
            seen.sort_unstable();
            assert_eq!(seen, (0..n as u32).collect::<Vec<_>>());
            let prim_t = |slot: usize, o, d, tm| match perm[slot] {
                EMPTY_SLOT => f32::INFINITY,
                i => box_t(&boxes[i as usize], o, d, tm),
            };
            for _ in 0..1000 {
                let o = rng.in_box(Vec3A::splat(-12.0), Vec3A::splat(12.0));
                let d = rng.direction();
                let brute = (0..n)
                    .map(|i| box_t(&boxes[i], o, d, 30.0))
                    .filter(|t| *t < 30.0)
                    .min_by(f32::total_cmp);
                let got = bvh.closest(o, d, 30.0, |o, d, tm, s| prim_t(s, o, d, tm));
                assert_eq!(got.map(|h| h.1), brute, "leaf {leaf}");
                let any = bvh.any(o, d, 30.0, |o, d, tm, s| prim_t(s, o, d, tm));
                assert_eq!(any, brute.is_some());
            }
        }
    }

    /// Boxes in a geometric progression along x give a deep, chain-like tree: deep enough
    /// that traversal takes its heap stack, which must give the same answers.
    #[test]
    fn deep_trees_use_a_heap_stack_with_the_same_results() {
        let boxes: Vec<Aabb> = (0..400)
            .map(|i| {
                let x = 1.08f32.powi(i);
                padded(Vec3A::new(x, -1.0, -1.0), Vec3A::new(x * 1.1, 1.0, 1.0))
            })
            .collect();
        let opts = BvhOptions {
            layout: BvhLayout::Bvh8,
            quality: BuildQuality::Medium,
            max_prims_per_leaf: 1,
        };
        let (bvh, perm) = Bvh::build(&boxes, opts);
        let Bvh::Wide(wide) = &bvh else {
            panic!("expected the 8-wide layout");
        };
        assert!(
            wide.stack > super::STACK,
            "tree too shallow: {}",
            wide.stack
        );
        let prim = |slot: usize| &boxes[perm[slot] as usize];
        let mut rng = Rng::new(9);
        for _ in 0..500 {
            let o = Vec3A::new(-1.0, 0.2 * rng.f32() - 0.1, 0.2 * rng.f32() - 0.1);
            let d = (Vec3A::X + 0.001 * rng.direction()).normalize();
            let brute = (0..boxes.len())
                .map(|s| (s, box_t(prim(s), o, d, f32::INFINITY)))
                .filter(|h| h.1.is_finite())
                .min_by(|a, b| a.1.total_cmp(&b.1));
            let got = bvh.closest(o, d, f32::INFINITY, |o, d, tm, s| box_t(prim(s), o, d, tm));
            assert_eq!(got.map(|h| h.1), brute.map(|h| h.1));
            let far = 1e30;
            let any = bvh.any(o, d, far, |o, d, tm, s| box_t(prim(s), o, d, tm));
            assert_eq!(any, brute.is_some());
        }
    }
}
