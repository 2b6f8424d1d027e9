//! The geometry half of [`super::World::build`]: world shapes, then the objects that
//! instances use (each object built once, then instanced), into one [`Geometry`] with its BVH.
//! Every primitive gets a [`PrimInfo`] (its material; its light once area lights exist) and
//! the names of its Interior/Exterior volumes (glass2 takes its index from them), and
//! world shapes with an `AreaLightSource` are remembered as [`PendingArea`] until the
//! geometry can say their area.

use super::PrimInfo;
use crate::accel::{Geometry, GeometryBuilder, ObjectId, ShapeId};
use crate::lxs::{Diagnostic, Entity, SceneDescription};
use crate::plugin::{warn, BuildError};
use crate::shape::ShapeCtx;
use std::collections::BTreeMap;

/// A world-level area light waiting for the geometry (its area) to be built.
pub(super) struct PendingArea<'a> {
    pub prim: u32,
    pub shape: ShapeId,
    pub entity: &'a Entity,
    pub group: &'a str,
}

/// Interior and Exterior volume names of a primitive.
pub(super) type Media<'a> = (Option<&'a str>, Option<&'a str>);

fn media_of(s: &crate::lxs::ShapeDesc) -> Media<'_> {
    (s.interior.as_deref(), s.exterior.as_deref())
}

/// The built geometry and what the rest of the world build needs from it.
pub(super) struct BuiltGeometry<'a> {
    pub geometry: Geometry,
    pub prims: Vec<PrimInfo>,
    /// Interior and Exterior volume names of each primitive (same order as `prims`).
    pub media: Vec<Media<'a>>,
    pub pending: Vec<PendingArea<'a>>,
    /// Objects built for instancing.
    pub objects: usize,
}

/// Builds every non-portal shape and instance of the description.
pub(super) fn build<'a>(
    desc: &'a SceneDescription,
    ctx: &ShapeCtx,
    warnings: &mut Vec<Diagnostic>,
) -> Result<BuiltGeometry<'a>, BuildError> {
    let mut gb = GeometryBuilder::new();
    let mut prims: Vec<PrimInfo> = Vec::new();
    let mut media = Vec::new();
    let mut pending = Vec::new();
    for shape in desc.shapes.iter().filter(|s| !s.portal) {
        let prim = prims.len() as u32;
        let id = gb.add_shape(shape, prim, ctx)?;
        prims.push(PrimInfo {
            material: shape.material,
            light: None,
        });
        media.push(media_of(shape));
        if let Some(al) = &shape.area_light {
            pending.push(PendingArea {
                prim,
                shape: id,
                entity: &al.entity,
                group: &al.light_group,
            });
        }
    }
    let mut objects: BTreeMap<usize, ObjectId> = BTreeMap::new();
    for inst in desc.instances.iter().filter(|i| !i.portal) {
        let oid = match objects.get(&inst.object) {
            Some(o) => *o,
            None => {
                let o = add_object(
                    desc,
                    inst.object,
                    &inst.loc,
                    &mut gb,
                    (&mut prims, &mut media),
                    ctx,
                    warnings,
                )?;
                objects.insert(inst.object, o);
                o
            }
        };
        gb.add_instance(oid, &inst.instance_to_world);
    }
    Ok(BuiltGeometry {
        geometry: gb.build(),
        prims,
        media,
        pending,
        objects: objects.len(),
    })
}

/// Builds object `index` (on its first instance), giving each of its shapes a primitive.
fn add_object<'a>(
    desc: &'a SceneDescription,
    index: usize,
    loc: &crate::lxs::Loc,
    gb: &mut GeometryBuilder,
    (prims, media): (&mut Vec<PrimInfo>, &mut Vec<Media<'a>>),
    ctx: &ShapeCtx,
    warnings: &mut Vec<Diagnostic>,
) -> Result<ObjectId, BuildError> {
    let Some(obj) = desc.objects.get(index) else {
        return Err(BuildError::new(loc, "unknown object"));
    };
    let ids: Vec<u32> = obj
        .shapes
        .iter()
        .map(|s| {
            if s.area_light.is_some() {
                warn(
                    warnings,
                    &s.entity.loc,
                    "area lights inside objects are not supported: the shape is rendered without emission",
                );
            }
            prims.push(PrimInfo {
                material: s.material,
                light: None,
            });
            media.push(media_of(s));
            prims.len() as u32 - 1
        })
        .collect();
    gb.add_object(obj, &ids, ctx)
}
