//! Thin wrapper over obvhs: build a BVH over padded primitive boxes with a chosen layout and
//! build quality, and traverse it for the closest or any hit (obvhs's traversal for its CWBVH
//! and BVH2 layouts, ours for the 8-wide one, [`super::bvh8`]).
//!
//! Rays handed to obvhs have a unit direction and an exact reciprocal (obvhs's own
//! `Ray::new` clamps tiny direction components to 1/ε, which shrinks slabs at small scales);
//! primitive boxes are padded by a relative margin so the f32 slab test stays conservative.

use super::bvh8::Bvh8;
use glam::Vec3A;
use obvhs::aabb::Aabb;
use obvhs::bvh2::builder::build_bvh2;
use obvhs::bvh2::Bvh2;
use obvhs::cwbvh::builder::build_cwbvh;
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray as BvhRay, RayHit};
use obvhs::BvhBuildParams;
use std::time::Duration;

/// Node layout used for traversal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BvhLayout {
    /// Compressed 8-wide BVH (SIMD node tests).
    Cwbvh,
    /// Binary BVH.
    Bvh2,
    /// Uncompressed 8-wide BVH collapsed from the binary one ([`super::bvh8`]).
    Bvh8,
}

/// obvhs build presets (PLOC search distance, reinsertion, spatial pre-splits).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BuildQuality {
    Fastest,
    Fast,
    Medium,
    Slow,
}

/// BVH construction options.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BvhOptions {
    pub layout: BvhLayout,
    pub quality: BuildQuality,
    /// Primitives per leaf (CWBVH clamps to 1..=3).
    pub max_prims_per_leaf: u32,
}

impl Default for BvhOptions {
    /// The fastest traversal measured by `luxfarm bench bvh` (see the accel module docs).
    fn default() -> Self {
        BvhOptions {
            layout: BvhLayout::Bvh8,
            quality: BuildQuality::Slow,
            max_prims_per_leaf: 4,
        }
    }
}

impl std::fmt::Display for BvhOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{:?}/{:?}/leaf{}",
            self.layout, self.quality, self.max_prims_per_leaf
        )
    }
}

impl BvhOptions {
    /// The configurations compared when the default was chosen (`luxfarm bench bvh --all`):
    /// each layout at three build qualities and its plausible leaf sizes (CWBVH holds at most
    /// 3 primitives per leaf).
    pub fn candidates() -> Vec<BvhOptions> {
        let mut v = Vec::new();
        for layout in [BvhLayout::Cwbvh, BvhLayout::Bvh2, BvhLayout::Bvh8] {
            for quality in [BuildQuality::Fast, BuildQuality::Medium, BuildQuality::Slow] {
                let leaves: &[u32] = match layout {
                    BvhLayout::Cwbvh => &[1, 3],
                    BvhLayout::Bvh2 => &[1, 4, 8],
                    BvhLayout::Bvh8 => &[1, 2, 4, 8],
                };
                for &max_prims_per_leaf in leaves {
                    v.push(BvhOptions {
                        layout,
                        quality,
                        max_prims_per_leaf,
                    });
                }
            }
        }
        v
    }

    fn params(&self) -> BvhBuildParams {
        let mut p = match self.quality {
            BuildQuality::Fastest => BvhBuildParams::fastest_build(),
            BuildQuality::Fast => BvhBuildParams::fast_build(),
            BuildQuality::Medium => BvhBuildParams::medium_build(),
            BuildQuality::Slow => BvhBuildParams::slow_build(),
        };
        // Spatial pre-splits need triangles; boxes of mixed primitives cannot be split.
        p.pre_split = false;
        p.max_prims_per_leaf = self.max_prims_per_leaf.max(1);
        p
    }
}

#[derive(Clone)]
pub enum Bvh {
    Empty,
    /// CWBVH and the power-of-two ray-parameter scale (see `ray_scale`).
    Cw(CwBvh, f32),
    Bin(Bvh2, f32),
    Wide(Bvh8),
}

/// obvhs's CWBVH node test clamps the entry distance to an absolute 1e-4, which would cull
/// everything in scenes smaller than that. Traversal therefore runs in a scaled ray parameter
/// t' = k t, with k a power of two (exact) mapping the scene's diagonal to about 2^20: the
/// clamp then covers 1e-10 of the scene, whatever its scale.
fn ray_scale(boxes: &[Aabb]) -> f32 {
    let (lo, hi) = boxes.iter().fold(
        (Vec3A::splat(f32::INFINITY), Vec3A::splat(f32::NEG_INFINITY)),
        |(lo, hi), b| (lo.min(b.min), hi.max(b.max)),
    );
    let diag = (hi - lo).length();
    if diag.is_nan() || diag <= 0.0 || !diag.is_finite() {
        return 1.0;
    }
    let e = (20.0 - diag.log2()).round().clamp(-100.0, 100.0) as i32;
    2f32.powi(e)
}

impl std::fmt::Debug for Bvh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Bvh::Empty => write!(f, "Bvh::Empty"),
            Bvh::Cw(b, _) => write!(f, "Bvh::Cw({} nodes)", b.nodes.len()),
            Bvh::Bin(b, _) => write!(f, "Bvh::Bin({} nodes)", b.nodes.len()),
            Bvh::Wide(_) => write!(f, "Bvh::Wide"),
        }
    }
}

/// Pads a box by a margin relative to its coordinates and extent.
pub fn padded(lo: Vec3A, hi: Vec3A) -> Aabb {
    let scale = lo
        .abs()
        .max(hi.abs())
        .max_element()
        .max((hi - lo).max_element());
    let pad = Vec3A::splat(scale * 4.0 * f32::EPSILON + f32::MIN_POSITIVE);
    Aabb::new(lo - pad, hi + pad)
}

impl Bvh {
    /// Builds over `boxes`; returns the BVH and the permutation: slot `i` of the traversal
    /// callbacks is primitive `perm[i]` of `boxes`.
    pub fn build(boxes: &[Aabb], opts: BvhOptions) -> (Bvh, Vec<u32>) {
        Bvh::build_aligned(boxes, opts, 1)
    }

    /// As [`Self::build`], with the 8-wide layout's leaves starting at multiples of `align`
    /// slots and padded to such a multiple (padding slots are [`super::bvh8::EMPTY_SLOT`] in the
    /// permutation; see [`Bvh8::from_bvh2`]). Other layouts ignore `align`.
    pub fn build_aligned(boxes: &[Aabb], opts: BvhOptions, align: usize) -> (Bvh, Vec<u32>) {
        if boxes.is_empty() {
            return (Bvh::Empty, Vec::new());
        }
        let mut t = Duration::ZERO;
        let k = ray_scale(boxes);
        match opts.layout {
            BvhLayout::Cwbvh => {
                let bvh = build_cwbvh(boxes, opts.params(), &mut t);
                let perm = bvh.primitive_indices.clone();
                (Bvh::Cw(bvh, k), perm)
            }
            BvhLayout::Bvh2 => {
                let bvh = build_bvh2(boxes, opts.params(), &mut t);
                let perm = bvh.primitive_indices.clone();
                (Bvh::Bin(bvh, k), perm)
            }
            BvhLayout::Bvh8 => {
                let bvh = build_bvh2(boxes, opts.params(), &mut t);
                let (wide, perm) = Bvh8::from_bvh2(&bvh, align);
                (Bvh::Wide(wide), perm)
            }
        }
    }

    /// Closest hit along `o + t d` (d unit), 0 < t < t_max. `f(o, d, t_max, slot)` returns
    /// the distance to a primitive's hit along that ray with `t < t_max`, or infinity; the
    /// result is the winning slot and distance.
    #[inline]
    pub fn closest(
        &self,
        o: Vec3A,
        d: Vec3A,
        t_max: f32,
        mut f: impl FnMut(Vec3A, Vec3A, f32, usize) -> f32,
    ) -> Option<(usize, f32)> {
        let mut hit = RayHit::none();
        let (found, k) = match self {
            Bvh::Empty => return None,
            Bvh::Cw(b, k) => {
                let g = |r: &BvhRay, slot: usize| f(o, d, r.tmax / k, slot) * k;
                (b.ray_traverse(make_ray(o, d, t_max, *k), &mut hit, g), *k)
            }
            Bvh::Bin(b, k) => {
                let g = |r: &BvhRay, slot: usize| f(o, d, r.tmax / k, slot) * k;
                (b.ray_traverse(make_ray(o, d, t_max, *k), &mut hit, g), *k)
            }
            Bvh::Wide(b) => return b.closest(o, d, t_max, |slot, tm| f(o, d, tm, slot)),
        };
        let t = hit.t / k;
        (found && t < t_max).then_some((hit.primitive_id as usize, t))
    }

    /// Whether any primitive is hit with 0 < t < t_max (`f` as for [`Self::closest`]).
    #[inline]
    pub fn any(
        &self,
        o: Vec3A,
        d: Vec3A,
        t_max: f32,
        mut f: impl FnMut(Vec3A, Vec3A, f32, usize) -> f32,
    ) -> bool {
        let mut g = |slot: usize| f(o, d, t_max, slot) < t_max;
        match self {
            Bvh::Empty => false,
            Bvh::Cw(b, k) => !b.ray_traverse_miss(make_ray(o, d, t_max, *k), |_, s| {
                if g(s) {
                    0.0
                } else {
                    f32::INFINITY
                }
            }),
            Bvh::Bin(b, k) => !b.ray_traverse_miss(make_ray(o, d, t_max, *k), |_, s| {
                if g(s) {
                    0.0
                } else {
                    f32::INFINITY
                }
            }),
            Bvh::Wide(b) => b.any(o, d, t_max, |slot, tm| f(o, d, tm, slot)),
        }
    }
}

#[inline(always)]
fn make_ray(o: Vec3A, d: Vec3A, t_max: f32, k: f32) -> BvhRay {
    let d = d / k;
    let t_max = t_max * k;
    // The CWBVH node test picks near/far planes from `direction < 0`: the reciprocal of a
    // zero component (including -0.0) must be +big to agree with it.
    let inv = |x: f32| {
        if x.abs() > 1e-20 {
            1.0 / x
        } else if x < 0.0 {
            -1e20
        } else {
            1e20
        }
    };
    BvhRay {
        origin: o,
        direction: d,
        inv_direction: Vec3A::new(inv(d.x), inv(d.y), inv(d.z)),
        tmin: 0.0,
        tmax: t_max,
    }
}
