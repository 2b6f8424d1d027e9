//! Acceleration structures: BVH over primitives (obvhs builds) and a two-level BVH for object
//! instances.
//!
//! World-level shapes share one bottom-level BVH ([`blas::Blas`]); each `ObjectBegin` object
//! gets its own, and a top-level BVH over the instances' world boxes transforms rays into the
//! object's space (f64 transform, one f32 rounding) and hits back to world space with error
//! bounds. Shapes and instances with animated transforms are moving instances with a
//! top-level BVH of their own over boxes bounding their whole motion (`motion.rs`), so static
//! geometry keeps this path unchanged; `area.rs` samples world shapes (moving ones where they
//! are at the sample's time). Layout and build quality were chosen by measurement (`luxfarm bench bvh --all`,
//! `bench/src/bvh/`, over [`bvh::BvhOptions::candidates`]; the shared 2-core machine was loaded, so rates are per CPU-second
//! received). On cornell-mesh.lxs, single thread: our uncompressed 8-wide BVH ([`bvh8`],
//! collapsed from obvhs's BVH2) with 2 primitives per leaf ran 6.1-6.4 M closest-hit and
//! 11.4-11.7 M any-hit rays per CPU-second, obvhs's CWBVH (leaf 3) 4.8-5.1 M and 6.9-7.5 M.
//! The 8-wide tree replaced a 4-wide one of the same design: 12-15% more closest-hit and
//! 40% more any-hit rays per CPU-second, 6-11% more on 216 tessellated spheres, and 3% less
//! CPU time rendering the scene (leaves of 3 or 4 primitives rendered no faster than 2 with
//! a scalar triangle test). Leaves of up to four triangles are now tested as one SIMD packet
//! ([`tri4`]): rendering the scene takes 3.5% less CPU with leaves of 4 than with scalar
//! leaves of 2 (leaves of 3: 2%, of 8: as 4). In `bench bvh` (one thread, alternating
//! runs) the packets ran closest-hit rays at the same rate (7.0-7.8 against 6.8-7.7 M/s)
//! and any-hit rays about 8% slower (11.0-11.6 against 12.5-12.7 M/s).
//! Earlier, between obvhs's medium and slow PLOC builds the difference was within the
//! noise on that scene, and on 500k triangles the slow build traversed ~10% faster (1.50 vs
//! 1.35 M rays/s) for a 2.4 s instead of 1.4 s build: the slow build is the default.

mod area;
pub mod blas;
pub mod bvh;
pub mod bvh8;
mod motion;
pub mod tri4;

use crate::geometry::frame::LocalGeometry;
use crate::geometry::motion::MotionTransform;
use crate::geometry::transform::{to_f32, to_f64};
use crate::geometry::{unit_or, Ray, SurfaceInteraction, Transform};
use crate::lxs::{ObjectDesc, ShapeDesc, Xform};
use crate::plugin::BuildError;
use crate::shape::{Shape, ShapeCtx};
use area::ShapeArea;
use blas::{Blas, BlasHit};
use bvh::{padded, Bvh, BvhOptions};
use glam::{DVec3, Vec3A};
use motion::{Movers, MovingInstance};

/// A world-level shape (index in the order of `add_shape`), static or moving.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ShapeId(pub u32);

/// An `ObjectBegin` object (index in the order of `add_object`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ObjectId(pub u32);

/// Collects shapes, objects and instances; [`GeometryBuilder::build`] makes the BVHs.
#[derive(Default)]
pub struct GeometryBuilder {
    shapes: Vec<Shape>,
    prims: Vec<u32>,
    objects: Vec<(Vec<Shape>, Vec<u32>)>,
    instances: Vec<(u32, Transform)>,
    moving: Vec<MovingInstance>,
    /// What each `ShapeId` is.
    refs: Vec<ShapeRef>,
    options: BvhOptions,
}

/// Where a world-level shape lives: in the world BVH (index in its shapes), or, moving, as
/// the one shape of an object placed by its animated transform.
#[derive(Clone, Debug)]
enum ShapeRef {
    World(u32),
    Moving {
        object: u32,
        motion: MotionTransform,
    },
}

impl GeometryBuilder {
    pub fn new() -> GeometryBuilder {
        GeometryBuilder::default()
    }

    /// Uses other BVH options than the measured default (benchmarks).
    pub fn with_options(options: BvhOptions) -> GeometryBuilder {
        GeometryBuilder {
            options,
            ..GeometryBuilder::default()
        }
    }

    /// Adds a world-level shape; every hit on it reports `prim`. A shape whose transform is
    /// animated is built once in its own space and placed as a moving instance.
    pub fn add_shape(
        &mut self,
        desc: &ShapeDesc,
        prim: u32,
        ctx: &ShapeCtx,
    ) -> Result<ShapeId, BuildError> {
        let r = match moving_shape_motion(desc) {
            Some(motion) => {
                let s = Shape::build_local(desc, ctx)?;
                let object = self.objects.len() as u32;
                self.objects.push((vec![s], vec![prim]));
                self.moving.push(MovingInstance {
                    object,
                    motion: motion.clone(),
                });
                ShapeRef::Moving { object, motion }
            }
            None => {
                let s = Shape::build(desc, &Transform::IDENTITY, ctx)?;
                self.shapes.push(s);
                self.prims.push(prim);
                ShapeRef::World(self.shapes.len() as u32 - 1)
            }
        };
        self.refs.push(r);
        Ok(ShapeId(self.refs.len() as u32 - 1))
    }

    /// Adds an object; `prims[i]` is reported for hits on `obj.shapes[i]`.
    pub fn add_object(
        &mut self,
        obj: &ObjectDesc,
        prims: &[u32],
        ctx: &ShapeCtx,
    ) -> Result<ObjectId, BuildError> {
        if prims.len() != obj.shapes.len() {
            return Err(BuildError::new(
                &obj.loc,
                format!(
                    "object {}: {} primitive ids for {} shapes",
                    obj.name,
                    prims.len(),
                    obj.shapes.len()
                ),
            ));
        }
        let shapes = obj
            .shapes
            .iter()
            .map(|d| Shape::build(d, &Transform::IDENTITY, ctx))
            .collect::<Result<Vec<_>, _>>()?;
        self.objects.push((shapes, prims.to_vec()));
        Ok(ObjectId(self.objects.len() as u32 - 1))
    }

    /// Places an instance of `object`; an animated transform makes it a moving instance.
    /// Singular transforms are skipped with a warning.
    pub fn add_instance(&mut self, object: ObjectId, instance_to_world: &Xform) {
        if instance_to_world.is_animated() {
            match motion_of(instance_to_world) {
                Ok(motion) if (object.0 as usize) < self.objects.len() => {
                    self.moving.push(MovingInstance {
                        object: object.0,
                        motion,
                    })
                }
                Ok(_) => tracing::warn!("instance of unknown object {} skipped", object.0),
                Err(why) => tracing::warn!("moving object instance skipped: {why}"),
            }
            return;
        }
        match Transform::new(instance_to_world.start()) {
            Some(t) if (object.0 as usize) < self.objects.len() => {
                self.instances.push((object.0, t))
            }
            Some(_) => tracing::warn!("instance of unknown object {} skipped", object.0),
            None => tracing::warn!("object instance with a singular transform skipped"),
        }
    }

    pub fn build(self) -> Geometry {
        let start = std::time::Instant::now();
        // Area-sampling tables are made on demand, for the shapes that emit light.
        let areas = vec![None; self.refs.len()];
        let world = Blas::build(self.shapes, self.prims, self.options);
        let objects: Vec<Blas> = self
            .objects
            .into_iter()
            .map(|(s, p)| Blas::build(s, p, self.options))
            .collect();
        let instances: Vec<Instance> = self
            .instances
            .into_iter()
            .filter(|(o, _)| !objects[*o as usize].is_empty())
            .map(|(object, to_world)| Instance {
                object,
                to_object: to_world.inverse(),
                to_world,
            })
            .collect();
        let boxes: Vec<_> = instances
            .iter()
            .map(|i| {
                let b = &objects[i.object as usize];
                let (lo, hi) = transform_box(&i.to_world, b.lo, b.hi);
                padded(lo, hi)
            })
            .collect();
        let (tlas, perm) = Bvh::build(&boxes, self.options);
        let instances: Vec<Instance> = perm
            .iter()
            .map(|&i| instances[i as usize].clone())
            .collect();
        let movers = Movers::build(self.moving, &objects, self.options);
        let (mut lo, mut hi) = (world.lo.min(movers.lo), world.hi.max(movers.hi));
        for b in &boxes {
            lo = lo.min(b.min);
            hi = hi.max(b.max);
        }
        let instanced_tris: usize = instances
            .iter()
            .map(|i| objects[i.object as usize].triangle_count())
            .sum();
        tracing::info!(
            "geometry: {} shapes ({} triangles, {} quadrics), {} objects ({} triangles), {} instances ({} instanced triangles), {} moving ({} triangles); BVH {} built in {:.1?}",
            world.shapes.len(),
            world.triangle_count(),
            world.quadric_count(),
            objects.len(),
            objects.iter().map(Blas::triangle_count).sum::<usize>(),
            instances.len(),
            instanced_tris,
            movers.len(),
            movers.triangle_count(&objects),
            self.options,
            start.elapsed()
        );
        Geometry {
            world,
            refs: self.refs,
            areas,
            objects,
            instances,
            tlas,
            movers,
            lo,
            hi,
        }
    }
}

#[derive(Clone, Debug)]
struct Instance {
    object: u32,
    to_world: Transform,
    to_object: Transform,
}

/// All the scene's geometry, ready for ray queries.
#[derive(Clone, Debug)]
pub struct Geometry {
    world: Blas,
    /// What each [`ShapeId`] is.
    refs: Vec<ShapeRef>,
    /// Per world shape: its area-sampling table, once [`Geometry::prepare_sampling`] made it.
    areas: Vec<Option<ShapeArea>>,
    objects: Vec<Blas>,
    instances: Vec<Instance>,
    tlas: Bvh,
    /// Instances and world shapes with animated transforms.
    movers: Movers,
    lo: Vec3A,
    hi: Vec3A,
}

/// Where the closest hit so far is.
#[derive(Clone, Copy)]
enum Found {
    World(BlasHit),
    Instance(u32, BlasHit),
    Moving(u32, BlasHit),
}

impl Geometry {
    /// World bounds (min, max); inverted (min > max) when empty.
    pub fn bounds(&self) -> (Vec3A, Vec3A) {
        (self.lo, self.hi)
    }

    fn closest(&self, ray: &Ray) -> Option<(Found, f32)> {
        let mut best: Option<(Found, f32)> = None;
        let mut t_max = ray.t_max;
        if let Some(h) = self.world.closest(ray.o, ray.d, t_max) {
            t_max = h.t;
            best = Some((Found::World(h), h.t));
        }
        if self.instances.is_empty() && self.movers.is_empty() {
            return best;
        }
        self.closest_instanced(ray, t_max, best)
    }

    /// [`Self::closest`] over the static and moving instances, given the world's best hit
    /// (kept out of line: scenes without instances never come here).
    #[inline(never)]
    fn closest_instanced(
        &self,
        ray: &Ray,
        mut t_max: f32,
        mut best: Option<(Found, f32)>,
    ) -> Option<(Found, f32)> {
        let len = ray.d.length();
        if len.is_nan() || len <= 0.0 || !len.is_finite() {
            return best;
        }
        let dn = ray.d / len;
        let mut inst_best = None;
        if !self.instances.is_empty() {
            self.closest_instance(ray.o, dn, t_max * len, &mut inst_best);
        }
        if let Some((slot, h)) = inst_best {
            t_max = h.t / len;
            best = Some((Found::Instance(slot, h), t_max));
        }
        if !self.movers.is_empty() {
            let found = self
                .movers
                .closest(&self.objects, ray.o, dn, t_max * len, ray.time);
            if let Some((slot, h)) = found {
                best = Some((Found::Moving(slot, h), h.t / len));
            }
        }
        best
    }

    /// The closest static instance hit along `o + t·dn` (dn unit) with t < `t_max`.
    fn closest_instance(
        &self,
        o: Vec3A,
        dn: Vec3A,
        t_max: f32,
        inst_best: &mut Option<(u32, BlasHit)>,
    ) {
        self.tlas.closest(o, dn, t_max, |o, d, tm, slot| {
            let inst = &self.instances[slot];
            let o = inst.to_object.point_f32(o);
            let d = inst.to_object.vector_f32(d);
            match self.objects[inst.object as usize].closest(o, d, tm) {
                Some(h) => {
                    *inst_best = Some((slot as u32, h));
                    h.t
                }
                None => f32::INFINITY,
            }
        });
    }

    /// The closest hit with 0 < t < ray.t_max, fully described.
    pub fn intersect(&self, ray: &Ray) -> Option<SurfaceInteraction> {
        if self.instances.is_empty() && self.movers.is_empty() {
            // World shapes only: the hit goes straight from the traversal to its description,
            // field by field (moving it whole through `Found` cost store-forwarding stalls).
            let h = self.world.closest(ray.o, ray.d, ray.t_max)?;
            let (g, prim) = self.world.hit_geometry(h, ray.o, ray.d, ray.t_max)?;
            return Some(Self::described(g, h.t, prim, ray));
        }
        let (found, t) = self.closest(ray)?;
        let (g, prim) = match found {
            Found::World(h) => self.world.hit_geometry(h, ray.o, ray.d, ray.t_max)?,
            Found::Instance(slot, h) => {
                let inst = &self.instances[slot as usize];
                let len = ray.d.length();
                let dn = ray.d / len;
                let o = inst.to_object.point_f32(ray.o);
                let d = inst.to_object.vector_f32(dn);
                let (g, prim) =
                    self.objects[inst.object as usize].hit_geometry(h, o, d, f32::INFINITY)?;
                (to_world(&inst.to_world, &g), prim)
            }
            Found::Moving(slot, h) => {
                let dn = ray.d / ray.d.length();
                self.movers
                    .hit_geometry(&self.objects, slot, h, (ray.o, dn), ray.time)?
            }
        };
        Some(Self::described(g, t, prim, ray))
    }

    /// The interaction at local geometry `g`, distance `t` along `ray`.
    #[inline(always)]
    fn described(g: LocalGeometry, t: f32, prim: u32, ray: &Ray) -> SurfaceInteraction {
        let wo = unit_or(-ray.d, Vec3A::ZERO);
        g.into_surface_interaction(wo, t, prim, ray.time)
    }

    /// Whether anything is hit with 0 < t < ray.t_max (shadow rays).
    pub fn intersect_p(&self, ray: &Ray) -> bool {
        if self.world.any(ray.o, ray.d, ray.t_max) {
            return true;
        }
        if self.instances.is_empty() && self.movers.is_empty() {
            return false;
        }
        self.any_instanced(ray)
    }

    /// [`Self::intersect_p`] over the static and moving instances (out of line, as
    /// [`Self::closest_instanced`]).
    #[inline(never)]
    fn any_instanced(&self, ray: &Ray) -> bool {
        let len = ray.d.length();
        if len.is_nan() || len <= 0.0 || !len.is_finite() {
            return false;
        }
        let dn = ray.d / len;
        let tm = ray.t_max * len;
        (!self.instances.is_empty() && self.any_instance(ray.o, dn, tm))
            || (!self.movers.is_empty() && self.movers.any(&self.objects, ray.o, dn, tm, ray.time))
    }

    /// Whether a static instance is hit along `o + t·dn` (dn unit) with t < `t_max`.
    fn any_instance(&self, o: Vec3A, dn: Vec3A, t_max: f32) -> bool {
        self.tlas.any(o, dn, t_max, |o, d, tm, slot| {
            let inst = &self.instances[slot];
            let o = inst.to_object.point_f32(o);
            let d = inst.to_object.vector_f32(d);
            if self.objects[inst.object as usize].any(o, d, tm) {
                0.0
            } else {
                f32::INFINITY
            }
        })
    }

    /// Number of world-level shapes (static and moving).
    pub fn shape_count(&self) -> usize {
        self.refs.len()
    }
}

/// The motion of a world shape whose transform is animated (`None` for a static one, or
/// when its keys cannot be interpolated: then, with a warning, its first key is used).
fn moving_shape_motion(desc: &ShapeDesc) -> Option<MotionTransform> {
    if !desc.object_to_world.is_animated() {
        return None;
    }
    match motion_of(&desc.object_to_world) {
        Ok(m) => Some(m),
        Err(why) => {
            tracing::warn!(
                "{}: shape \"{}\": {why}; using its first key",
                desc.entity.loc,
                desc.entity.kind
            );
            None
        }
    }
}

/// The interpolated motion of animated keys; an error when a key is singular or not finite.
/// A sheared key is interpolated without its shear (warned).
fn motion_of(x: &Xform) -> Result<MotionTransform, String> {
    if x.keys.iter().any(|(_, m)| Transform::new(*m).is_none()) {
        return Err("a motion key is singular or not finite".into());
    }
    let affine: Vec<(f32, glam::DAffine3)> = x
        .keys
        .iter()
        .map(|(t, m)| (*t, glam::DAffine3::from_mat4(*m)))
        .collect();
    if MotionTransform::loses_shear(&affine) {
        tracing::warn!("a motion key is sheared: it is interpolated without its shear");
    }
    MotionTransform::new(&affine).ok_or_else(|| "motion keys are not finite".to_string())
}

/// Object-space local geometry moved to world space, with the point's error propagated.
fn to_world(t: &Transform, g: &LocalGeometry) -> LocalGeometry {
    let (p, p_error) = t.point_with_error(g.p, g.p_error);
    LocalGeometry {
        p,
        p_error,
        n: t.normal_f32(g.n).normalize_or_zero(),
        ns: g.ns.map(|n| t.normal_f32(n).normalize_or_zero()),
        uv: g.uv,
        dpdu: t.vector_f32(g.dpdu),
        dpdv: t.vector_f32(g.dpdv),
        hit: g.hit,
    }
}

fn transform_box(t: &Transform, lo: Vec3A, hi: Vec3A) -> (Vec3A, Vec3A) {
    let mut a = DVec3::splat(f64::INFINITY);
    let mut b = DVec3::splat(f64::NEG_INFINITY);
    let (lo, hi) = (to_f64(lo), to_f64(hi));
    for i in 0..8 {
        let c = DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        let w = t.point(c);
        a = a.min(w);
        b = b.max(w);
    }
    (to_f32(a), to_f32(b))
}

#[cfg(test)]
mod tests;
