//! Moving instances: objects placed by an animated transform (an `ObjectInstance` inside a
//! motion block, `MotionInstance`, or a world shape whose transform is animated, built once in
//! its own space as a one-shape object).
//!
//! They have their own top-level BVH, over boxes that bound the whole motion
//! ([`MotionTransform::bound`]), so static instances and world shapes keep their path with no
//! per-ray interpolation and scenes without motion never traverse this one. Per ray and per
//! instance reached, the transform is interpolated at the ray's time, the ray goes into object
//! space (f64, one f32 rounding), the object's BVH is traversed, and the hit comes back with
//! the same time's matrix.

use super::blas::{Blas, BlasHit};
use super::bvh::{padded, Bvh, BvhOptions};
use crate::geometry::frame::LocalGeometry;
use crate::geometry::motion::MotionTransform;
use crate::geometry::transform::{to_f32, to_f64};
use glam::Vec3A;

/// An object placed by an animated transform.
#[derive(Clone, Debug)]
pub(super) struct MovingInstance {
    pub object: u32,
    /// Object space to world, over time.
    pub motion: MotionTransform,
}

/// The moving instances and their BVH.
#[derive(Clone, Debug)]
pub(super) struct Movers {
    /// By traversal slot (`None` for a padding slot).
    instances: Vec<Option<MovingInstance>>,
    count: usize,
    tlas: Bvh,
    /// World box over every instance's whole motion (inverted when there are none).
    pub lo: Vec3A,
    pub hi: Vec3A,
}

impl Movers {
    /// Builds the BVH over `instances` whose object is not empty.
    pub fn build(instances: Vec<MovingInstance>, objects: &[Blas], options: BvhOptions) -> Movers {
        let (instances, boxes): (Vec<MovingInstance>, Vec<_>) = instances
            .into_iter()
            .filter_map(|i| {
                let b = objects.get(i.object as usize).filter(|b| !b.is_empty())?;
                let (lo, hi) = i.motion.bound(to_f64(b.lo), to_f64(b.hi));
                Some((i, padded(to_f32(lo), to_f32(hi))))
            })
            .unzip();
        let count = instances.len();
        let (tlas, perm) = Bvh::build(&boxes, options);
        let instances = perm
            .iter()
            .map(|&i| instances.get(i as usize).cloned())
            .collect();
        let (mut lo, mut hi) = (Vec3A::INFINITY, Vec3A::NEG_INFINITY);
        for b in &boxes {
            lo = lo.min(b.min);
            hi = hi.max(b.max);
        }
        Movers {
            instances,
            count,
            tlas,
            lo,
            hi,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    pub fn len(&self) -> usize {
        self.count
    }

    /// Triangles over all moving instances.
    pub fn triangle_count(&self, objects: &[Blas]) -> usize {
        self.instances
            .iter()
            .flatten()
            .filter_map(|i| objects.get(i.object as usize))
            .map(Blas::triangle_count)
            .sum()
    }

    /// The closest hit along `o + t·dn` (dn unit) with t < `t_max` at `time`: the instance
    /// slot and the object-space hit (its t is along dn).
    pub fn closest(
        &self,
        objects: &[Blas],
        o: Vec3A,
        dn: Vec3A,
        t_max: f32,
        time: f32,
    ) -> Option<(u32, BlasHit)> {
        let mut best = None;
        self.tlas.closest(o, dn, t_max, |o, d, tm, slot| {
            let Some((inst, obj)) = self.get(objects, slot) else {
                return f32::INFINITY;
            };
            let Some(to_world) = inst.motion.transform_at(time) else {
                return f32::INFINITY;
            };
            let to_object = to_world.inverse();
            match obj.closest(to_object.point_f32(o), to_object.vector_f32(d), tm) {
                Some(h) => {
                    best = Some((slot as u32, h));
                    h.t
                }
                None => f32::INFINITY,
            }
        });
        best
    }

    /// Whether anything moving is hit along `o + t·dn` (dn unit) with t < `t_max` at `time`.
    pub fn any(&self, objects: &[Blas], o: Vec3A, dn: Vec3A, t_max: f32, time: f32) -> bool {
        self.tlas.any(o, dn, t_max, |o, d, tm, slot| {
            let hit = self.get(objects, slot).is_some_and(|(inst, obj)| {
                inst.motion.transform_at(time).is_some_and(|to_world| {
                    let to_object = to_world.inverse();
                    obj.any(to_object.point_f32(o), to_object.vector_f32(d), tm)
                })
            });
            if hit {
                0.0
            } else {
                f32::INFINITY
            }
        })
    }

    /// World-space geometry and primitive of a hit [`Self::closest`] found for the ray
    /// `o + t·dn` at `time`.
    pub fn hit_geometry(
        &self,
        objects: &[Blas],
        slot: u32,
        hit: BlasHit,
        (o, dn): (Vec3A, Vec3A),
        time: f32,
    ) -> Option<(LocalGeometry, u32)> {
        let (inst, obj) = self.get(objects, slot as usize)?;
        let to_world = inst.motion.transform_at(time)?;
        let to_object = to_world.inverse();
        let (g, prim) = obj.hit_geometry(
            hit,
            to_object.point_f32(o),
            to_object.vector_f32(dn),
            f32::INFINITY,
        )?;
        Some((super::to_world(&to_world, &g), prim))
    }

    fn get<'a>(
        &'a self,
        objects: &'a [Blas],
        slot: usize,
    ) -> Option<(&'a MovingInstance, &'a Blas)> {
        let inst = self.instances.get(slot)?.as_ref()?;
        Some((inst, objects.get(inst.object as usize)?))
    }
}
