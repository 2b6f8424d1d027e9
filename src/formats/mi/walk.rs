//! The walk of the scene graph from the `render` statement's root instgroup: every object,
//! light and camera it reaches, placed by its world→local matrix (composed parent first)
//! with the material it inherits; hidden instances drop their branch. The walk is bounded in
//! depth ([`MAX_DEPTH`]) and in placements, and refuses cycles. `assemble.rs` makes the
//! description from what it lists.

use super::cursor::MiResult;
use super::instances::{InstMaterial, MiInstance};
use super::lights::MiLight;
use super::parse::MiScene;
use crate::lxs::{Loc, LxsError, LxsErrorKind};
use glam::DMat4;

/// Deepest nesting of instances and instgroups.
pub const MAX_DEPTH: usize = 64;

/// An object placed in the world.
pub(super) struct Geometry<'s> {
    pub(super) inst: &'s MiInstance,
    pub(super) object: &'s str,
    pub(super) world_to_local: DMat4,
    pub(super) material: InstMaterial,
}

/// A light or camera placed in the world.
pub(super) struct Placed<'s, T> {
    pub(super) inst: &'s MiInstance,
    pub(super) item: &'s T,
    pub(super) world_to_local: DMat4,
}

#[derive(Default)]
pub(super) struct Walk<'s> {
    pub(super) geometry: Vec<Geometry<'s>>,
    pub(super) lights: Vec<Placed<'s, MiLight>>,
    pub(super) cameras: Vec<Placed<'s, super::camera::MiCamera>>,
    stack: Vec<&'s str>,
}

pub(super) fn undefined(loc: &Loc, msg: String) -> LxsError {
    LxsError::new(LxsErrorKind::Undefined, loc.clone(), msg)
}

impl<'s> Walk<'s> {
    fn count(&self) -> usize {
        self.geometry.len() + self.lights.len() + self.cameras.len()
    }

    /// Visits the instgroup or instance `name` under a parent's world→local matrix.
    pub(super) fn visit(
        &mut self,
        s: &'s MiScene,
        name: &'s str,
        loc: &Loc,
        parent: DMat4,
        inherited: &InstMaterial,
        max: usize,
    ) -> MiResult<()> {
        if self.stack.len() >= MAX_DEPTH {
            return Err(LxsError::new(
                LxsErrorKind::InputTooLarge,
                loc.clone(),
                format!("instances nested deeper than {MAX_DEPTH}"),
            ));
        }
        if self.stack.contains(&name) {
            return Err(LxsError::new(
                LxsErrorKind::IncludeCycle,
                loc.clone(),
                format!("\"{name}\" contains itself"),
            ));
        }
        if self.count() > max {
            return Err(LxsError::new(
                LxsErrorKind::ArrayTooLong,
                loc.clone(),
                format!("more than {max} placements (ParseOptions::max_array_len)"),
            ));
        }
        self.stack.push(name);
        let r = self.visit_inner(s, name, loc, parent, inherited, max);
        self.stack.pop();
        r
    }

    fn visit_inner(
        &mut self,
        s: &'s MiScene,
        name: &'s str,
        loc: &Loc,
        parent: DMat4,
        inherited: &InstMaterial,
        max: usize,
    ) -> MiResult<()> {
        if let Some(g) = s.instgroups.get(name) {
            for (m, at) in &g.members {
                self.visit(s, m, at, parent, inherited, max)?;
            }
            return Ok(());
        }
        let Some(inst) = s.instances.get(name) else {
            return Err(undefined(
                loc,
                format!("\"{name}\" is neither an instance nor an instgroup"),
            ));
        };
        if inst.hide {
            return Ok(());
        }
        let w2l = inst.transform.map_or(parent, |m| m * parent);
        let material = match &inst.material {
            InstMaterial::None => inherited.clone(),
            own => own.clone(),
        };
        let item = inst.item.as_str();
        if let Some(g) = s.instgroups.get(item) {
            for (m, at) in &g.members {
                self.visit(s, m, at, w2l, &material, max)?;
            }
        } else if s.objects.contains_key(item) {
            self.geometry.push(Geometry {
                inst,
                object: item,
                world_to_local: w2l,
                material,
            });
        } else if let Some(l) = s.lights.get(item) {
            self.lights.push(Placed {
                inst,
                item: l,
                world_to_local: w2l,
            });
        } else if let Some(cam) = s.cameras.get(item) {
            self.cameras.push(Placed {
                inst,
                item: cam,
                world_to_local: w2l,
            });
        } else {
            return Err(undefined(
                &inst.item_loc,
                format!(
                    "instance \"{}\" places \"{item}\", which is not defined",
                    inst.name
                ),
            ));
        }
        Ok(())
    }
}

/// The inverse of a world→local matrix (already checked invertible where read).
pub(super) fn local_to_world(m: DMat4) -> DMat4 {
    m.inverse()
}
