//! Area sampling of world-level shapes (for area lights): each shape's world area and, for
//! meshes, a triangle-picking table, made on demand for emitters only.
//!
//! A static shape is sampled where it was built (world space). A moving shape is sampled in
//! its own space and the point carried to world space with the transform at the sample's
//! time, so the light moves with the shape; its density is the object-space one divided by
//! the motion's area scale (exact when every key is a similarity of one scale: then the area
//! is the same at every time).

use super::{to_world, Geometry, ShapeId, ShapeRef};
use crate::geometry::frame::LocalGeometry;
use crate::geometry::motion::MotionTransform;
use crate::geometry::Interaction;
use crate::sampling::DiscreteDistribution;
use crate::shape::Shape;
use glam::{Vec2, Vec3A};

/// Area of a world shape (world space) and, for meshes, the triangle-picking table.
#[derive(Clone, Debug)]
pub(super) struct ShapeArea {
    area: f64,
    tris: Option<DiscreteDistribution>,
}

impl ShapeArea {
    /// `scale` multiplies the shape's own area (1 for a shape built in world space).
    fn new(s: &Shape, scale: f64) -> ShapeArea {
        match s {
            Shape::Mesh(m) => {
                let w: Vec<f64> = (0..m.tris.len()).map(|i| m.area(i)).collect();
                ShapeArea {
                    area: w.iter().sum::<f64>() * scale,
                    tris: DiscreteDistribution::new(&w),
                }
            }
            Shape::Quadric(q) => ShapeArea {
                area: q.area() * scale,
                tris: None,
            },
        }
    }
}

/// A moving shape's area scale: exact for keys that are similarities of one scale, else
/// (with a warning when the shape is added) the first key's.
pub(super) fn area_scale(motion: &MotionTransform) -> f64 {
    motion
        .area_scale()
        .unwrap_or_else(|| motion.first_key_area_scale())
}

impl Geometry {
    /// A world-level shape and, when it moves, its motion.
    fn shape_of(&self, id: ShapeId) -> Option<(&Shape, Option<&MotionTransform>)> {
        match self.refs.get(id.0 as usize)? {
            ShapeRef::World(i) => Some((self.world.shapes.get(*i as usize)?, None)),
            ShapeRef::Moving { object, motion } => {
                let shape = self.objects.get(*object as usize)?.shapes.first()?;
                Some((shape, Some(motion)))
            }
        }
    }

    /// World-space area of a world-level shape (0 for an unknown id).
    pub fn area(&self, id: ShapeId) -> f32 {
        if let Some(Some(a)) = self.areas.get(id.0 as usize) {
            return a.area as f32;
        }
        match self.shape_of(id) {
            Some((s, None)) => s.area() as f32,
            Some((s, Some(m))) => (s.area() * area_scale(m)) as f32,
            None => 0.0,
        }
    }

    /// Makes world shape `id` ready for [`Self::sample`] (for a mesh, its triangle-picking
    /// table, 16 bytes per triangle: only emitters pay for it) and returns its area.
    pub fn prepare_sampling(&mut self, id: ShapeId) -> f32 {
        let Some((shape, motion)) = self.shape_of(id) else {
            return 0.0;
        };
        if motion.is_some_and(|m| m.area_scale().is_none()) {
            tracing::warn!(
                "area light on a moving shape whose motion keys change its size: light \
                 sampling uses the area at the first key, so its direct light is biased"
            );
        }
        let made = ShapeArea::new(shape, motion.map_or(1.0, area_scale));
        let Some(slot) = self.areas.get_mut(id.0 as usize) else {
            return 0.0;
        };
        slot.get_or_insert(made).area as f32
    }

    /// Whether [`Self::sample`] of shape `id` reads its `u_pick`: only a mesh with more
    /// than `REMAP_MAX_TRIANGLES` triangles does (see `pick_triangle`).
    pub fn sample_reads_pick(&self, id: ShapeId) -> bool {
        let area = self.areas.get(id.0 as usize).and_then(Option::as_ref);
        area.and_then(|a| a.tris.as_ref())
            .is_some_and(|d| d.len() > REMAP_MAX_TRIANGLES)
    }

    /// A point of the shape at shutter time `time`, uniform by area (`u_pick` chooses the
    /// triangle of a mesh), its uv and its density with respect to area. An unknown id, or
    /// one not prepared by [`Self::prepare_sampling`], gives pdf 0.
    pub fn sample(&self, id: ShapeId, u: Vec2, u_pick: f32, time: f32) -> (Interaction, Vec2, f32) {
        let none = (Interaction::default(), Vec2::ZERO, 0.0);
        let i = id.0 as usize;
        let (Some(r), Some(Some(a))) = (self.refs.get(i), self.areas.get(i)) else {
            return none;
        };
        let shape = match r {
            ShapeRef::World(w) => match self.world.shapes.get(*w as usize) {
                Some(s) => s,
                None => return none,
            },
            ShapeRef::Moving { object, motion } => {
                return self
                    .sample_moving(*object, motion, a, (u, u_pick), time)
                    .unwrap_or(none)
            }
        };
        match shape {
            Shape::Mesh(m) => match &a.tris {
                Some(dist) => {
                    let (s, uv) = pick_triangle(m, dist, u, u_pick);
                    let it = Interaction {
                        p: s.p,
                        p_error: s.p_error,
                        n: s.n,
                        time,
                    };
                    (it, uv, (1.0 / a.area) as f32)
                }
                None => none,
            },
            Shape::Quadric(q) => {
                let (g, pdf) = q.sample(u);
                (g.interaction(time), g.uv, pdf)
            }
        }
    }

    /// [`Self::sample`] of a moving shape (the one shape of `object`): sampled in its own
    /// space, carried to world space with the transform at `time`.
    #[inline(never)]
    fn sample_moving(
        &self,
        object: u32,
        motion: &MotionTransform,
        a: &ShapeArea,
        (u, u_pick): (Vec2, f32),
        time: f32,
    ) -> Option<(Interaction, Vec2, f32)> {
        let shape = self.objects.get(object as usize)?.shapes.first()?;
        let (g, pdf) = match shape {
            Shape::Mesh(m) => {
                let (s, uv) = pick_triangle(m, a.tris.as_ref()?, u, u_pick);
                let g = LocalGeometry {
                    p: s.p,
                    p_error: s.p_error,
                    n: s.n,
                    ns: None,
                    uv,
                    dpdu: Vec3A::ZERO,
                    dpdv: Vec3A::ZERO,
                    hit: Default::default(),
                };
                (g, (1.0 / a.area) as f32)
            }
            Shape::Quadric(q) => {
                let (g, pdf) = q.sample(u);
                (g, (pdf as f64 / area_scale(motion)) as f32)
            }
        };
        let g = to_world(&motion.transform_at(time)?, &g);
        Some((g.interaction(time), g.uv, pdf))
    }
}

/// Meshes with at most this many triangles pick theirs with the point's own first coordinate
/// (remapped within the triangle's share), so the 2D sample stays stratified over the whole
/// light; past it the remapped coordinate would keep too few bits of an f32, and the
/// separate `u_pick` chooses.
const REMAP_MAX_TRIANGLES: usize = 1 << 10;

/// A point of mesh `m` uniform by area: the triangle drawn by area from `dist`, then a point
/// in it. With few triangles the triangle comes from `u.x` itself ([`REMAP_MAX_TRIANGLES`]):
/// a stratified `u` then stays stratified across the triangles of a quad light, which a
/// separate pick dimension would shuffle.
fn pick_triangle(
    m: &crate::shape::TriangleMesh,
    dist: &DiscreteDistribution,
    u: Vec2,
    u_pick: f32,
) -> (crate::shape::mesh::MeshPoint, Vec2) {
    if dist.len() <= REMAP_MAX_TRIANGLES {
        let (i, ux) = dist.sample(u.x);
        m.sample(i, Vec2::new(ux, u.y))
    } else {
        m.sample(dist.pick(u_pick), u)
    }
}
