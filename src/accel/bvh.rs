//! Thin wrapper over obvhs: build a BVH over padded primitive boxes with a chosen layout and
//! build quality, and traverse it for the closest or any hit.
//!
//! Rays handed to obvhs have a unit direction and an exact reciprocal (obvhs's own
//! `Ray::new` clamps tiny direction components to 1/ε, which shrinks slabs at small scales);
//! primitive boxes are padded by a relative margin so the f32 slab test stays conservative.

use obvhs::aabb::Aabb;
use obvhs::bvh2::builder::build_bvh2;
use obvhs::bvh2::Bvh2;
use obvhs::cwbvh::builder::build_cwbvh;
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray as BvhRay, RayHit};
use obvhs::BvhBuildParams;
use glam::Vec3A;
use std::time::Duration;

/// Node layout used for traversal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BvhLayout {
    /// Compressed 8-wide BVH (SIMD node tests).
    Cwbvh,
    /// Binary BVH.
    Bvh2,
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
            layout: BvhLayout::Cwbvh,
            quality: BuildQuality::Medium,
            max_prims_per_leaf: 3,
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
    Cw(CwBvh),
    Bin(Bvh2),
}

impl std::fmt::Debug for Bvh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Bvh::Empty => write!(f, "Bvh::Empty"),
            Bvh::Cw(b) => write!(f, "Bvh::Cw({} nodes)", b.nodes.len()),
            Bvh::Bin(b) => write!(f, "Bvh::Bin({} nodes)", b.nodes.len()),
        }
    }
}

/// Pads a box by a margin relative to its coordinates and extent.
pub fn padded(lo: Vec3A, hi: Vec3A) -> Aabb {
    let scale = lo.abs().max(hi.abs()).max_element().max((hi - lo).max_element());
    let pad = Vec3A::splat(scale * 4.0 * f32::EPSILON + f32::MIN_POSITIVE);
    Aabb::new(lo - pad, hi + pad)
}

impl Bvh {
    /// Builds over `boxes`; returns the BVH and the permutation: slot `i` of the traversal
    /// callbacks is primitive `perm[i]` of `boxes`.
    pub fn build(boxes: &[Aabb], opts: BvhOptions) -> (Bvh, Vec<u32>) {
        if boxes.is_empty() {
            return (Bvh::Empty, Vec::new());
        }
        let mut t = Duration::ZERO;
        match opts.layout {
            BvhLayout::Cwbvh => {
                let bvh = build_cwbvh(boxes, opts.params(), &mut t);
                let perm = bvh.primitive_indices.clone();
                (Bvh::Cw(bvh), perm)
            }
            BvhLayout::Bvh2 => {
                let bvh = build_bvh2(boxes, opts.params(), &mut t);
                let perm = bvh.primitive_indices.clone();
                (Bvh::Bin(bvh), perm)
            }
        }
    }

    /// Closest hit along `o + t d` (d unit), 0 < t < t_max. `f(ray, slot)` returns the hit
    /// distance of a primitive or infinity; the result is the winning slot and distance.
    #[inline]
    pub fn closest(
        &self,
        o: Vec3A,
        d: Vec3A,
        t_max: f32,
        mut f: impl FnMut(&BvhRay, usize) -> f32,
    ) -> Option<(usize, f32)> {
        let ray = make_ray(o, d, t_max);
        let mut hit = RayHit::none();
        let found = match self {
            Bvh::Empty => false,
            Bvh::Cw(b) => b.ray_traverse(ray, &mut hit, &mut f),
            Bvh::Bin(b) => b.ray_traverse(ray, &mut hit, &mut f),
        };
        (found && hit.t < t_max).then_some((hit.primitive_id as usize, hit.t))
    }

    /// Whether any primitive is hit with 0 < t < t_max.
    #[inline]
    pub fn any(&self, o: Vec3A, d: Vec3A, t_max: f32, mut f: impl FnMut(&BvhRay, usize) -> f32) -> bool {
        let ray = make_ray(o, d, t_max);
        match self {
            Bvh::Empty => false,
            Bvh::Cw(b) => !b.ray_traverse_miss(ray, &mut f),
            Bvh::Bin(b) => !b.ray_traverse_miss(ray, &mut f),
        }
    }
}

#[inline(always)]
fn make_ray(o: Vec3A, d: Vec3A, t_max: f32) -> BvhRay {
    let inv = |x: f32| {
        if x.abs() > 1e-20 {
            1.0 / x
        } else {
            1e20f32.copysign(x)
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
