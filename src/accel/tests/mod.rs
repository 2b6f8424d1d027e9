//! Tests of shapes through the accelerator: analytic hits, clipping, orientation, files,
//! instancing, scale robustness and area sampling (one file per theme).

mod files;
pub(crate) mod fixtures;
mod motion;
mod robust;
mod sampling;
mod shapes;

use super::*;
use crate::geometry::Interaction;
use crate::lxs::{ObjectDesc, ParamValue};
use crate::shape::test_util::{floats, ints, points, quad, shape};
use glam::{DMat4, DVec3, Vec2};
use std::f32::consts::PI;

pub(super) fn geo(descs: &[ShapeDesc]) -> Geometry {
    let mut b = GeometryBuilder::new();
    for (i, d) in descs.iter().enumerate() {
        b.add_shape(d, i as u32, &ShapeCtx::default())
            .expect("shape builds");
    }
    let mut g = b.build();
    for i in 0..descs.len() {
        g.prepare_sampling(ShapeId(i as u32));
    }
    g
}

pub(super) fn close(a: Vec3A, b: Vec3A, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

pub(super) fn hit(g: &Geometry, o: [f32; 3], d: [f32; 3]) -> Option<SurfaceInteraction> {
    g.intersect(&Ray::new(Vec3A::from_array(o), Vec3A::from_array(d)))
}

pub(super) fn sphere(params: Vec<(&str, ParamValue)>, reverse: bool) -> ShapeDesc {
    shape("sphere", params, DMat4::IDENTITY, reverse)
}
