//! An uncompressed 4-wide BVH collapsed from an obvhs binary BVH: each node holds its four
//! children's boxes as f32 SoA lanes, so one SIMD slab test covers all four (no dequantisation
//! as in the CWBVH). Closest-hit traversal visits hit children nearest first and culls stack
//! entries farther than the current hit.
//!
//! Robustness: primitive boxes are padded (see [`super::bvh::padded`]), the reciprocal
//! direction is finite (tiny components map to ±1e20 with the sign of the component, so
//! `(bound - o) * inv` is never NaN), and the exit distance is widened by 1 + 2γ(3) as pbrt
//! does, so rounding in the slab test can only make boxes look bigger.

use crate::geometry::transform::gamma;
use glam::{Vec3A, Vec4};
use obvhs::bvh2::Bvh2;

/// Child slot of a node: an inner node, a leaf (slot range), or nothing.
const EMPTY: u32 = u32::MAX;

#[derive(Clone, Debug)]
#[repr(C, align(16))]
struct Node4 {
    /// `b[0]` the children's minima, `b[1]` their maxima, per axis, one child per lane.
    b: [[Vec4; 3]; 2],
    /// Inner child: node index; leaf child: first slot; empty: [`EMPTY`].
    child: [u32; 4],
    /// 0 for an inner (or empty) child, else the leaf's primitive count.
    count: [u32; 4],
}

/// A 4-wide BVH; slots are positions in the source BVH's `primitive_indices`.
#[derive(Clone, Debug, Default)]
pub struct Bvh4 {
    nodes: Vec<Node4>,
    /// Stack entries a traversal can need: at most 3 wait per level above the node being
    /// visited, and an any-hit visit pushes up to 4 before popping one.
    stack: usize,
}

/// Traversals whose stack fits this use an array on the thread's stack; deeper trees a Vec.
const STACK: usize = 64;

/// Per-ray constants of the slab test.
struct Slab {
    o: [Vec4; 3],
    inv: [Vec4; 3],
    /// Index (0: min, 1: max) of the near plane per axis.
    near: [usize; 3],
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
        let near = |v: f32| usize::from(v < 0.0);
        Slab {
            o: [Vec4::splat(o.x), Vec4::splat(o.y), Vec4::splat(o.z)],
            inv: [Vec4::splat(i.x), Vec4::splat(i.y), Vec4::splat(i.z)],
            near: [near(i.x), near(i.y), near(i.z)],
        }
    }

    /// Entry distances of the four children and the mask of those hit within [0, t_max].
    #[inline(always)]
    fn test(&self, n: &Node4, t_max: f32) -> (Vec4, u32) {
        let mut t0 = Vec4::ZERO;
        let mut t1 = Vec4::splat(t_max);
        for a in 0..3 {
            let near = (n.b[self.near[a]][a] - self.o[a]) * self.inv[a];
            let far = (n.b[1 - self.near[a]][a] - self.o[a]) * self.inv[a];
            t0 = t0.max(near);
            t1 = t1.min(far * (1.0 + 2.0 * gamma(3)));
        }
        (t0, t0.cmple(t1).bitmask())
    }
}

impl Bvh4 {
    /// Collapses `b` (slots keep their meaning).
    pub fn from_bvh2(b: &Bvh2) -> Bvh4 {
        let mut out = Bvh4::default();
        let Some(root) = b.nodes.first() else {
            return out;
        };
        let depth = if root.prim_count > 0 {
            out.nodes.push(Node4::leaf_root(b, 0));
            1
        } else {
            out.emit(b, 0).1
        };
        out.stack = 3 * depth + 1;
        out
    }

    /// Emits the 4-wide node for inner node `i` of `b` and its subtree; returns its index and
    /// the subtree's depth in 4-wide nodes.
    fn emit(&mut self, b: &Bvh2, i: usize) -> (u32, usize) {
        let first = b.nodes[i].first_index as usize;
        let mut kids = vec![first, first + 1];
        while kids.len() < 4 {
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
        let at = self.nodes.len();
        self.nodes.push(Node4::empty());
        let mut depth = 1;
        for (lane, &k) in kids.iter().enumerate() {
            let n = &b.nodes[k];
            let (child, count) = if n.prim_count > 0 {
                (n.first_index, n.prim_count)
            } else {
                let (c, dd) = self.emit(b, k);
                depth = depth.max(dd + 1);
                (c, 0)
            };
            let node = &mut self.nodes[at];
            for a in 0..3 {
                node.b[0][a][lane] = n.aabb.min[a];
                node.b[1][a][lane] = n.aabb.max[a];
            }
            node.child[lane] = child;
            node.count[lane] = count;
        }
        (at as u32, depth)
    }

    /// Closest hit along `o + t d`, 0 < t < t_max: `f(slot, t_max)` returns the distance of
    /// a hit with `t < t_max` or infinity. Returns the winning slot and distance.
    #[inline]
    pub fn closest(
        &self,
        o: Vec3A,
        d: Vec3A,
        t_max: f32,
        f: impl FnMut(usize, f32) -> f32,
    ) -> Option<(usize, f32)> {
        if self.nodes.is_empty() {
            return None;
        }
        if self.stack <= STACK {
            self.closest_in(&mut [(0, 0.0); STACK], o, d, t_max, f)
        } else {
            self.closest_in(&mut vec![(0, 0.0); self.stack], o, d, t_max, f)
        }
    }

    #[inline(always)]
    fn closest_in(
        &self,
        stack: &mut [(u32, f32)],
        o: Vec3A,
        d: Vec3A,
        t_max: f32,
        mut f: impl FnMut(usize, f32) -> f32,
    ) -> Option<(usize, f32)> {
        let slab = Slab::new(o, d);
        let mut best: Option<(usize, f32)> = None;
        let mut t_max = t_max;
        let mut sp = 0;
        // The node to visit next: the nearest inner child of the last node goes here directly,
        // the others wait on the stack with their entry distances.
        let mut next = Some(0u32);
        loop {
            let ni = match next.take() {
                Some(ni) => ni,
                None => loop {
                    if sp == 0 {
                        return best;
                    }
                    sp -= 1;
                    let (ni, t_in) = stack[sp];
                    if t_in <= t_max {
                        break ni;
                    }
                },
            };
            let node = &self.nodes[ni as usize];
            let (t0, mut mask) = slab.test(node, t_max);
            // Lanes read from an array (a by-index lane read of a vector compiles to a jump).
            let t0 = t0.to_array();
            // Leaves first (they may shrink t_max), then inner children far to near.
            let mut inner = [(0u32, 0f32); 4];
            let mut n_inner = 0;
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let count = node.count[lane];
                if count == 0 {
                    inner[n_inner] = (node.child[lane], t0[lane]);
                    n_inner += 1;
                    continue;
                }
                let first = node.child[lane];
                for slot in first..first + count {
                    let t = f(slot as usize, t_max);
                    if t < t_max {
                        t_max = t;
                        best = Some((slot as usize, t));
                    }
                }
            }
            if n_inner == 0 {
                continue;
            }
            far_to_near(&mut inner[..n_inner]);
            let (nearest, t_near) = inner[n_inner - 1];
            for &(c, t) in &inner[..n_inner - 1] {
                // In bounds: at most 3 entries per level are left behind (see `stack`).
                stack[sp] = (c, t);
                sp += 1;
            }
            if t_near <= t_max {
                next = Some(nearest);
            }
        }
    }

    /// Whether `f(slot, t_max) < t_max` for any primitive whose box the ray crosses.
    #[inline]
    pub fn any(&self, o: Vec3A, d: Vec3A, t_max: f32, f: impl FnMut(usize, f32) -> f32) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        if self.stack <= STACK {
            self.any_in(&mut [0; STACK], o, d, t_max, f)
        } else {
            self.any_in(&mut vec![0; self.stack], o, d, t_max, f)
        }
    }

    #[inline(always)]
    fn any_in(
        &self,
        stack: &mut [u32],
        o: Vec3A,
        d: Vec3A,
        t_max: f32,
        mut f: impl FnMut(usize, f32) -> f32,
    ) -> bool {
        let slab = Slab::new(o, d);
        stack[0] = 0;
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let node = &self.nodes[stack[sp] as usize];
            let (_, mut mask) = slab.test(node, t_max);
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let count = node.count[lane];
                if count == 0 {
                    stack[sp] = node.child[lane];
                    sp += 1;
                    continue;
                }
                let first = node.child[lane];
                for slot in first..first + count {
                    if f(slot as usize, t_max) < t_max {
                        return true;
                    }
                }
            }
        }
        false
    }
}

/// Sorts up to four (node, entry distance) pairs by decreasing distance, so that the last is
/// the nearest (visited next) and the others go on the stack nearest-last. Equal distances
/// come out in a fixed but unstable order; only two hits at exactly the same distance (two
/// coincident faces) can depend on it, and the choice is the same on every run.
#[inline(always)]
fn far_to_near(v: &mut [(u32, f32)]) {
    #[inline(always)]
    fn order(v: &mut [(u32, f32)], i: usize, j: usize) {
        if v[i].1 < v[j].1 {
            v.swap(i, j);
        }
    }
    match v.len() {
        2 => order(v, 0, 1),
        3 => {
            order(v, 0, 1);
            order(v, 1, 2);
            order(v, 0, 1);
        }
        4 => {
            order(v, 0, 1);
            order(v, 2, 3);
            order(v, 0, 2);
            order(v, 1, 3);
            order(v, 1, 2);
        }
        _ => {}
    }
}

impl Node4 {
    fn empty() -> Node4 {
        Node4 {
            b: [[Vec4::INFINITY; 3], [Vec4::NEG_INFINITY; 3]],
            child: [EMPTY; 4],
            count: [0; 4],
        }
    }

    /// A root whose only child is leaf node `i` of `b`.
    fn leaf_root(b: &Bvh2, i: usize) -> Node4 {
        let mut n = Node4::empty();
        let l = &b.nodes[i];
        for a in 0..3 {
            n.b[0][a][0] = l.aabb.min[a];
            n.b[1][a][0] = l.aabb.max[a];
        }
        n.child[0] = l.first_index;
        n.count[0] = l.prim_count;
        n
    }
}

#[cfg(test)]
mod tests {
    use crate::accel::bench::Rng;
    use crate::accel::bvh::{padded, BuildQuality, Bvh, BvhLayout, BvhOptions};
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
                layout: BvhLayout::Bvh4,
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
            layout: BvhLayout::Bvh4,
            quality: BuildQuality::Medium,
            max_prims_per_leaf: 1,
        };
        let (bvh, perm) = Bvh::build(&boxes, opts);
        let Bvh::Wide(wide) = &bvh else {
            panic!("expected the 4-wide layout");
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
