//! Portals of the world build: the `PortalShape`s and `PortalInstance`s of the description,
//! grouped by the LightSource each belongs to (`portal_light`, the last light declared in its
//! attribute scope), built as world-space triangles and handed to the lights that light
//! statement built ([`crate::light::Light::set_portals`]: infinite, sky, sky2 — for sunsky
//! and sunsky2 the sky half). Portals are never rendered geometry.
//!
//! Nothing here stops a render: a portal that cannot be built or used is left out with a
//! located warning, and the light is then sampled over its whole extent (or through the
//! portals that remain), which stays unbiased.

use crate::geometry::Transform;
use crate::light::{Light, Portals};
use crate::lxs::{Diagnostic, Loc, SceneDescription, ShapeDesc};
use crate::plugin::warn;
use crate::shape::{Shape, ShapeCtx};
use glam::Vec3A;
use std::collections::BTreeMap;
use std::ops::Range;

/// Portal triangles gathered for one light statement, and where the first portal was given.
struct Gathered {
    tris: Vec<[Vec3A; 3]>,
    loc: Loc,
}

/// Gives each light the portals of its statement; `built[i]` is the range of `lights` that
/// `desc.lights[i]` built.
pub(super) fn attach(
    desc: &SceneDescription,
    ctx: &ShapeCtx,
    built: &[Range<usize>],
    lights: &mut [Light],
    warnings: &mut Vec<Diagnostic>,
) {
    let mut by_light: BTreeMap<usize, Gathered> = BTreeMap::new();
    for s in desc.shapes.iter().filter(|s| s.portal) {
        let Some(li) = owner(s.portal_light, &s.entity.loc, warnings) else {
            continue;
        };
        add_shape(&mut by_light, li, s, &Transform::IDENTITY, ctx, warnings);
    }
    for inst in desc.instances.iter().filter(|i| i.portal) {
        let Some(li) = owner(inst.portal_light, &inst.loc, warnings) else {
            continue;
        };
        let Some(obj) = desc.objects.get(inst.object) else {
            continue;
        };
        let Some(to_world) = Transform::new(inst.instance_to_world.start()) else {
            warn(
                warnings,
                &inst.loc,
                "PortalInstance with a singular transform: ignored",
            );
            continue;
        };
        for s in &obj.shapes {
            add_shape(&mut by_light, li, s, &to_world, ctx, warnings);
        }
    }
    for (li, g) in by_light {
        give(li, g, built, lights, warnings);
    }
}

/// The light index of a portal, warning when it has none.
fn owner(light: Option<usize>, loc: &Loc, warnings: &mut Vec<Diagnostic>) -> Option<usize> {
    if light.is_none() {
        warn(
            warnings,
            loc,
            "portal ignored: no LightSource outside ObjectBegin in its scope to belong to",
        );
    }
    light
}

/// Builds portal shape `s` (placed by `space`) and adds its triangles to light `li`'s.
fn add_shape(
    by_light: &mut BTreeMap<usize, Gathered>,
    li: usize,
    s: &ShapeDesc,
    space: &Transform,
    ctx: &ShapeCtx,
    warnings: &mut Vec<Diagnostic>,
) {
    let tris = match Shape::build(s, space, ctx) {
        Ok(Shape::Mesh(m)) => (0..m.tris.len()).map(|i| m.vertices(i)).collect(),
        Ok(Shape::Quadric(_)) => {
            warn(
                warnings,
                &s.entity.loc,
                format!(
                    "portal shape \"{}\" ignored: only mesh portals are sampled (write the window as a trianglemesh)",
                    s.entity.kind
                ),
            );
            return;
        }
        Err(e) => {
            warn(
                warnings,
                &s.entity.loc,
                format!("portal ignored: {}", e.message),
            );
            return;
        }
    };
    by_light
        .entry(li)
        .or_insert_with(|| Gathered {
            tris: Vec::new(),
            loc: s.entity.loc.clone(),
        })
        .tris
        .extend::<Vec<_>>(tris);
}

/// Hands light statement `li`'s portals to the lights it built that sample through them.
fn give(
    li: usize,
    g: Gathered,
    built: &[Range<usize>],
    lights: &mut [Light],
    warnings: &mut Vec<Diagnostic>,
) {
    let portals = match Portals::new(g.tris) {
        Ok(p) => p,
        Err(e) => {
            warn(warnings, &g.loc, format!("portals ignored: {e}"));
            return;
        }
    };
    let range = built.get(li).cloned().unwrap_or(0..0);
    let mut taken = 0;
    for l in lights.get_mut(range).into_iter().flatten() {
        if l.set_portals(portals.clone()) {
            taken += 1;
        }
    }
    if taken == 0 {
        warn(
            warnings,
            &g.loc,
            "portals ignored: only infinite, sky, sky2, sunsky and sunsky2 lights are sampled through portals, and not when they move with an object instance",
        );
    } else {
        tracing::info!(
            triangles = portals.triangle_count(),
            area = portals.area(),
            lights = taken,
            "portals attached"
        );
    }
}
