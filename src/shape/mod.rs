//! Shapes: meshes, PLY, quadrics, heightfield (one file per shape).
//!
//! [`create`] turns a `ShapeDesc` into a [`Shape`] placed in the space the caller asks for
//! (world space for world shapes, the object's definition space for shapes inside
//! `ObjectBegin`). Triangle meshes are stored with their vertices already transformed (as
//! LuxRender does); quadrics keep their own object space and are intersected analytically in
//! f64. Parameter names and defaults follow LuxRender's `shapes/*.cpp`.

pub mod cone;
pub mod cylinder;
pub mod disk;
pub mod heightfield;
pub mod hyperboloid;
pub mod mesh;
pub mod paraboloid;
pub mod plymesh;
pub mod quadric;
pub mod sphere;
pub mod stlmesh;
pub mod triangle;
pub mod trianglemesh;

use crate::geometry::Transform;
use crate::lxs::{Loc, ShapeDesc};
use std::path::PathBuf;

pub use mesh::TriangleMesh;
pub use quadric::Quadric;

/// What shape creation needs besides the description.
#[derive(Clone, Debug, Default)]
pub struct ShapeCtx {
    /// Directory that relative file names (plymesh/stlmesh `filename`) resolve against.
    pub base_dir: PathBuf,
}

/// A shape that could not be built; Display is `file:line:col: shape "kind": message`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{loc}: shape \"{kind}\": {message}")]
pub struct ShapeError {
    pub loc: Loc,
    pub kind: String,
    pub message: String,
}

/// A built shape.
#[derive(Clone, Debug)]
pub enum Shape {
    Mesh(TriangleMesh),
    Quadric(Box<Quadric>),
}

impl Shape {
    pub fn triangle_count(&self) -> usize {
        match self {
            Shape::Mesh(m) => m.tris.len(),
            Shape::Quadric(_) => 0,
        }
    }

    /// Surface area in the shape's space.
    pub fn area(&self) -> f64 {
        match self {
            Shape::Mesh(m) => (0..m.tris.len()).map(|i| m.area(i)).sum(),
            Shape::Quadric(q) => q.area(),
        }
    }
}

/// Context of one shape being built: its description, transforms and error reporting.
pub(crate) struct Build<'a> {
    pub desc: &'a ShapeDesc,
    pub ctx: &'a ShapeCtx,
    /// Shape's object space to the target space.
    pub to_space: Transform,
}

impl Build<'_> {
    pub fn err(&self, message: impl Into<String>) -> ShapeError {
        ShapeError {
            loc: self.desc.entity.loc.clone(),
            kind: self.desc.entity.kind.clone(),
            message: message.into(),
        }
    }

    pub fn params(&self) -> &crate::lxs::ParamSet {
        &self.desc.entity.params
    }

    pub fn reverse(&self) -> bool {
        self.desc.reverse_orientation
    }

    /// Logs a warning naming the shape's place in the scene.
    pub fn warn(&self, message: &str) {
        tracing::warn!(
            "{}: shape \"{}\": {}",
            self.desc.entity.loc,
            self.desc.entity.kind,
            message
        );
    }

    /// A finite float parameter (non-finite values are errors).
    pub fn float(&self, name: &str, default: f32) -> Result<f64, ShapeError> {
        let v = self.params().float_or(name, default);
        if v.is_finite() {
            Ok(v as f64)
        } else {
            Err(self.err(format!("parameter \"{name}\" is not finite")))
        }
    }

    /// `phimax` in radians, clamped to [0, 2π] as LuxRender does.
    pub fn phimax(&self) -> Result<f64, ShapeError> {
        Ok(self.float("phimax", 360.0)?.clamp(0.0, 360.0).to_radians())
    }
}

/// Builds the shape of `desc`, placing it with `space_from_world` applied after the shape's own
/// transform (identity for world shapes).
pub fn create(
    desc: &ShapeDesc,
    space_from_world: &Transform,
    ctx: &ShapeCtx,
) -> Result<Shape, ShapeError> {
    let mut b = Build {
        desc,
        ctx,
        to_space: Transform::IDENTITY,
    };
    if desc.object_to_world.is_animated() {
        b.warn("motion-blurred transform: using its first key (motion blur is not implemented)");
    }
    let o2w = Transform::new(desc.object_to_world.start())
        .ok_or_else(|| b.err("the shape's transform is singular or not finite"))?;
    b.to_space = space_from_world.compose(&o2w);
    match desc.entity.kind.as_str() {
        "trianglemesh" | "mesh" | "waldtrianglemesh" | "barytrianglemesh" | "loopsubdiv" => {
            trianglemesh::create(&b).map(Shape::Mesh)
        }
        "plymesh" => plymesh::create(&b).map(Shape::Mesh),
        "stlmesh" => stlmesh::create(&b).map(Shape::Mesh),
        "heightfield" => heightfield::create(&b).map(Shape::Mesh),
        "sphere" => sphere::create(&b).map(quadric),
        "disk" => disk::create(&b).map(quadric),
        "cylinder" => cylinder::create(&b).map(quadric),
        "cone" => cone::create(&b).map(quadric),
        "paraboloid" => paraboloid::create(&b).map(quadric),
        "hyperboloid" => hyperboloid::create(&b).map(quadric),
        other => Err(b.err(format!("unsupported shape type \"{other}\""))),
    }
}

#[cfg(test)]
pub(crate) mod test_util;

fn quadric(q: Quadric) -> Shape {
    Shape::Quadric(Box::new(q))
}
