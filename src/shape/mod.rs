//! Shapes: meshes, PLY, quadrics, heightfield (one file per shape).
//!
//! [`create`] turns a `ShapeDesc` into a [`Shape`] placed in the space the caller asks for
//! (world space for world shapes, the object's definition space for shapes inside
//! `ObjectBegin`). Triangle meshes are stored with their vertices already transformed (as
//! LuxRender does); quadrics keep their own object space and are intersected analytically in
//! f64 ([`quadric`], the intersection in `quadric_hit.rs`). Parameter names and defaults
//! follow LuxRender's `shapes/*.cpp`. Mesh shapes that ask for subdivision go through
//! [`loopsubdiv`] (the Loop scheme itself is in [`subdiv`]).

pub mod cone;
pub mod cylinder;
pub mod disk;
pub mod heightfield;
pub mod hyperboloid;
pub mod loopsubdiv;
pub mod mesh;
pub mod mesh_arrays;
pub mod microdisplace;
pub mod paraboloid;
pub mod plymesh;
pub mod quadric;
mod quadric_hit;
pub mod sphere;
pub mod stlmesh;
pub mod subdiv;
pub mod triangle;
pub mod trianglemesh;

use crate::fileio::SceneFiles;
use crate::geometry::Transform;
use crate::lxs::ShapeDesc;
pub use crate::plugin::BuildError;
use crate::texture::FloatTex;
use std::collections::BTreeMap;

pub use mesh::TriangleMesh;
pub use quadric::Quadric;

/// What shape creation needs besides the description.
#[derive(Clone, Debug, Default)]
pub struct ShapeCtx {
    /// Where the files shapes name (plymesh/stlmesh `filename`) are opened: relative to the
    /// scene's directory, confined to it on a farm.
    pub files: SceneFiles,
    /// The float textures that subdivided shapes displace by (`displacementmap`), by name:
    /// built by the scene before the geometry ([`loopsubdiv::displacement_maps`]).
    pub displacement: BTreeMap<String, FloatTex>,
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
    /// An error naming the shape: `file:line:col: shape "kind": message`.
    pub fn err(&self, message: impl Into<String>) -> BuildError {
        BuildError::new(
            &self.desc.entity.loc,
            format!("shape \"{}\": {}", self.desc.entity.kind, message.into()),
        )
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
    pub fn float(&self, name: &str, default: f32) -> Result<f64, BuildError> {
        let v = self.params().float_or(name, default);
        if v.is_finite() {
            Ok(v as f64)
        } else {
            Err(self.err(format!("parameter \"{name}\" is not finite")))
        }
    }

    /// `phimax` in radians, clamped to [0, 2π] as LuxRender does.
    pub fn phimax(&self) -> Result<f64, BuildError> {
        Ok(self.float("phimax", 360.0)?.clamp(0.0, 360.0).to_radians())
    }
}

impl Shape {
    /// Builds the shape of `desc`, placing it with `space_from_world` applied after the shape's own
    /// transform (identity for world shapes). Each shape file reads its own parameters; this
    /// only dispatches on the name.
    pub fn build(
        desc: &ShapeDesc,
        space_from_world: &Transform,
        ctx: &ShapeCtx,
    ) -> Result<Shape, BuildError> {
        let mut b = Build {
            desc,
            ctx,
            to_space: Transform::IDENTITY,
        };
        if desc.object_to_world.is_animated() {
            b.warn(
                "motion-blurred transform not interpolated here (a shape inside an object, or \
                 keys that cannot be): using its first key; world shapes and object instances \
                 move with all their keys",
            );
        }
        let o2w = Transform::new(desc.object_to_world.start())
            .ok_or_else(|| b.err("the shape's transform is singular or not finite"))?;
        b.to_space = space_from_world.compose(&o2w);
        b.dispatch()
    }

    /// Builds the shape of `desc` in its own object space, ignoring its transform (a moving
    /// shape: its animated transform places it per ray).
    pub fn build_local(desc: &ShapeDesc, ctx: &ShapeCtx) -> Result<Shape, BuildError> {
        Build {
            desc,
            ctx,
            to_space: Transform::IDENTITY,
        }
        .dispatch()
    }
}

impl Build<'_> {
    /// Builds the shape by its name; each shape file reads its own parameters.
    fn dispatch(&self) -> Result<Shape, BuildError> {
        let b = self;
        match b.desc.entity.kind.as_str() {
            "trianglemesh" | "mesh" | "waldtrianglemesh" | "barytrianglemesh" | "loopsubdiv" => {
                trianglemesh::build(b).map(Shape::Mesh)
            }
            "plymesh" => plymesh::build(b).map(Shape::Mesh),
            "stlmesh" => stlmesh::build(b).map(Shape::Mesh),
            "heightfield" => heightfield::build(b).map(Shape::Mesh),
            "sphere" => sphere::build(b).map(quadric),
            "disk" => disk::build(b).map(quadric),
            "cylinder" => cylinder::build(b).map(quadric),
            "cone" => cone::build(b).map(quadric),
            "paraboloid" => paraboloid::build(b).map(quadric),
            "hyperboloid" => hyperboloid::build(b).map(quadric),
            other => Err(b.err(format!("unsupported shape type \"{other}\""))),
        }
    }
}

#[cfg(test)]
mod loopsubdiv_tests;
#[cfg(test)]
pub(crate) mod test_util;

fn quadric(q: Quadric) -> Shape {
    Shape::Quadric(Box::new(q))
}
