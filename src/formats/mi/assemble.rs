//! From a [`MiScene`] to the [`SceneDescription`] every luxfarm scene becomes: walks the
//! scene graph from the `render` statement's root and places what it finds.
//!
//! ```text
//! render "root" "camera instance" "options"
//!   root instgroup --walk.rs (world→local matrices compose parent first; materials inherit
//!                             downwards; instance `hide` drops a branch)-->
//!   placements: geometry (instance, object, matrix, materials), lights, cameras
//!   --> Camera + Film (camera.rs), PixelFilter + path integrator + haltspp (options.rs),
//!       materials (shaders.rs; a name that is not a `material` but a shader is that shader
//!       as a material, as mental ray 3.13 allows for MDL materials), LightSources (lights.rs),
//!       shapes: one trianglemesh per object part (objects.rs), world shapes, or an object
//!       with instances when an object is placed more than once with the same materials;
//!       object lights: an AreaLightSource on every shape of the emitting instance.
//! ```
//!
//! Camera space: mental ray's camera looks down −z (right-handed, y up); LuxRender's looks
//! down +z with the same x and y, so world→camera is diag(1, 1, −1) × the camera instance's
//! world→local matrix. Item names that do not resolve are located errors; the walk is bounded
//! in depth ([`MAX_DEPTH`]), refuses cycles, and counts its placements against
//! `ParseOptions::max_array_len` (nested instgroups can multiply them).

use super::camera;
use super::cursor::MiResult;
use super::instances::InstMaterial;
use super::lights::{self, LightOut};
use super::objects::{self, MeshPart, PolyMat};
use super::options::{self, Options};
use super::params::{ShaderParams, ShaderRef};
use super::parse::{MiScene, RenderStmt};
use super::shaders;
pub use super::walk::MAX_DEPTH;
use super::walk::{local_to_world, undefined, Geometry, Walk};
use crate::lxs::{
    AreaLightDesc, CameraDesc, Diagnostic, Entity, InstanceDesc, LightDesc, Loc, LxsError,
    LxsErrorKind, MaterialDesc, ObjectDesc, Param, ParamSet, ParamValue, SceneDescription,
    ShapeDesc, Xform,
};
use glam::{DMat4, DVec3, DVec4};
use std::collections::HashMap;

/// A shader reference resolved to its type and parameters.
fn resolve_shader<'s>(
    s: &'s MiScene,
    r: &'s ShaderRef,
) -> MiResult<(&'s str, &'s ShaderParams, &'s Loc)> {
    match r {
        ShaderRef::Inline { kind, params, loc } => Ok((kind.as_str(), params, loc)),
        ShaderRef::Named { name, loc } => match s.shaders.get(name) {
            Some(sh) => Ok((sh.kind.as_str(), &sh.params, &sh.loc)),
            None => Err(shaders::undefined_shader(name, loc)),
        },
    }
}

/// Builds the description (see the module docs).
pub fn assemble(s: &MiScene, opts_max: usize) -> MiResult<SceneDescription> {
    let root_name = s.files.first().cloned().unwrap_or_default();
    let file_loc = Loc {
        file: root_name.as_str().into(),
        line: 0,
        col: 0,
    };
    let Some(render) = &s.render else {
        return Err(LxsError::new(
            LxsErrorKind::Syntax,
            file_loc,
            "no render statement: nothing names the root instgroup, camera and options to render",
        ));
    };
    let Some(opts) = s.options.get(&render.options.0) else {
        return Err(undefined(
            &render.options.1,
            format!("options \"{}\" are not defined", render.options.0),
        ));
    };
    let mut walk = Walk::default();
    walk.visit(
        s,
        &render.root.0,
        &render.root.1,
        DMat4::IDENTITY,
        &InstMaterial::None,
        opts_max,
    )?;
    let mut w: Vec<Diagnostic> = s.warnings.clone();
    let mut desc = SceneDescription {
        root_file: root_name,
        files: s.files.clone(),
        ..SceneDescription::default()
    };
    camera_and_film(s, render, opts, &walk, &mut desc, &mut w)?;
    desc.pixel_filter = options::pixel_filter(opts, &mut w);
    desc.surface_integrator = Some(options::integrator(opts));
    if !opts.ignored.is_empty() {
        w.push(Diagnostic {
            loc: opts.loc.clone(),
            message: format!(
                "options not used by luxfarm's path tracer: {}",
                opts.ignored.join(", ")
            ),
        });
    }
    let emitters = place_lights(s, &walk, &mut desc, &mut w)?;
    place_geometry(s, &walk, &emitters, &mut desc, &mut w)?;
    desc.warnings = w;
    Ok(desc)
}

fn camera_and_film(
    s: &MiScene,
    render: &RenderStmt,
    opts: &Options,
    walk: &Walk,
    desc: &mut SceneDescription,
    w: &mut Vec<Diagnostic>,
) -> MiResult<()> {
    let name = &render.camera.0;
    let placed = walk.cameras.iter().find(|c| c.inst.name == *name);
    let (cam, w2l) = match placed {
        Some(p) => (p.item, p.world_to_local),
        None => {
            // A camera instance outside the root group: placed by its own transform.
            let inst = s.instances.get(name).ok_or_else(|| {
                undefined(
                    &render.camera.1,
                    format!("camera instance \"{name}\" is not defined"),
                )
            })?;
            let cam = s.cameras.get(&inst.item).ok_or_else(|| {
                undefined(&inst.item_loc, format!("\"{}\" is not a camera", inst.item))
            })?;
            (cam, inst.transform.unwrap_or(DMat4::IDENTITY))
        }
    };
    let flip = DMat4::from_diagonal(DVec4::new(1.0, 1.0, -1.0, 1.0));
    desc.camera = Some(CameraDesc {
        entity: camera::camera_entity(cam, w),
        world_to_camera: Xform::fixed(flip * w2l),
        exterior: None,
    });
    desc.film = Some(camera::film_entity(cam, options::haltspp(opts), w));
    Ok(())
}

/// Adds the lights; returns the object lights' AreaLightSources by emitting instance name.
fn place_lights(
    s: &MiScene,
    walk: &Walk,
    desc: &mut SceneDescription,
    w: &mut Vec<Diagnostic>,
) -> MiResult<HashMap<String, (Entity, Loc)>> {
    let mut emitters: HashMap<String, (Entity, Loc)> = HashMap::new();
    for p in &walk.lights {
        let l = p.item;
        let shader = l
            .shader
            .as_ref()
            .map(|r| resolve_shader(s, r))
            .transpose()?;
        let l2w = local_to_world(p.world_to_local);
        match lights::light_entity(l, shader, &l2w, w) {
            LightOut::Source(entity) => desc.lights.push(LightDesc {
                entity,
                light_to_world: Xform::fixed(l2w),
                light_group: "default".into(),
                exterior: None,
                instance_motion: None,
            }),
            LightOut::Object(inst) => {
                let at = l.area.as_ref().map_or(&l.loc, |a| &a.1).clone();
                let parts: Vec<&Geometry> = walk
                    .geometry
                    .iter()
                    .filter(|g| g.inst.name == inst)
                    .collect();
                if parts.is_empty() {
                    return Err(undefined(
                        &at,
                        format!("object light \"{}\": instance \"{inst}\" is not placed in the rendered scene", l.name),
                    ));
                }
                let mut area = 0.0;
                for g in &parts {
                    let to_world = local_to_world(g.world_to_local);
                    if let Some(obj) = s.objects.get(g.object) {
                        for part in objects::mesh_parts(obj, &mut Vec::new()) {
                            area += mesh_area(&part, &to_world);
                        }
                    }
                }
                let entity = lights::object_area_entity(l, shader, area, w);
                if emitters
                    .insert(inst.clone(), (entity, at.clone()))
                    .is_some()
                {
                    w.push(Diagnostic {
                        loc: at,
                        message: format!("instance \"{inst}\" is the emitter of two object lights: the last one is used"),
                    });
                }
            }
            LightOut::Nothing => {}
        }
    }
    Ok(emitters)
}

/// World-space area of a mesh part.
fn mesh_area(part: &MeshPart, to_world: &DMat4) -> f64 {
    let p: Vec<DVec3> = part
        .p
        .iter()
        .map(|v| to_world.transform_point3(DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64)))
        .collect();
    part.tris
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| p.get(i as usize).copied().unwrap_or(DVec3::ZERO));
            0.5 * (b - a).cross(c - a).length()
        })
        .sum()
}

/// The materials of the scene's luxfarm description, made on first use.
struct Materials<'s> {
    scene: &'s MiScene,
    index: HashMap<String, usize>,
}

impl<'s> Materials<'s> {
    /// The description's material for mental ray material `name`, referenced at `loc`.
    fn get(
        &mut self,
        name: &str,
        loc: &Loc,
        desc: &mut SceneDescription,
        w: &mut Vec<Diagnostic>,
    ) -> MiResult<usize> {
        if let Some(&i) = self.index.get(name) {
            return Ok(i);
        }
        let entity = match self.scene.materials.get(name) {
            Some(m) => {
                let surface = m
                    .surface
                    .as_ref()
                    .map(|r| resolve_shader(self.scene, r))
                    .transpose()?;
                for (what, at) in &m.ignored {
                    w.push(Diagnostic {
                        loc: at.clone(),
                        message: format!("material \"{name}\": \"{what}\" is not used by luxfarm"),
                    });
                }
                shaders::material_entity(name, &m.loc, surface, w)
            }
            // mental ray 3.13+ instances may name a material shader (an MDL material)
            // directly.
            None => match self.scene.shaders.get(name) {
                Some(sh) => shaders::material_entity(
                    name,
                    &sh.loc,
                    Some((&sh.kind, &sh.params, &sh.loc)),
                    w,
                ),
                None => {
                    return Err(undefined(
                        loc,
                        format!("material \"{name}\" is not defined"),
                    ))
                }
            },
        };
        let i = desc.materials.len();
        desc.materials.push(MaterialDesc {
            name: Some(name.to_string()),
            entity,
        });
        desc.named_materials.insert(name.to_string(), i);
        self.index.insert(name.to_string(), i);
        Ok(i)
    }
}

/// The material name a part asks for from its instance's material(s).
fn part_material<'a>(
    part: &'a MeshPart,
    inst_mat: &'a InstMaterial,
    g: &Geometry,
    w: &mut Vec<Diagnostic>,
) -> Option<&'a str> {
    match (&part.mat, inst_mat) {
        (Some(PolyMat::Name(n)), _) => Some(n),
        (Some(PolyMat::Tag(t)), InstMaterial::Array(v)) => match v.get(*t as usize) {
            Some(n) => Some(n),
            None => {
                w.push(Diagnostic {
                    loc: g.inst.material_loc.clone(),
                    message: format!(
                        "instance \"{}\": material tag {t} is beyond its {} materials: the first is used",
                        g.inst.name,
                        v.len()
                    ),
                });
                v.first().map(String::as_str)
            }
        },
        (_, InstMaterial::One(n)) => Some(n),
        (_, InstMaterial::Array(v)) => v.first().map(String::as_str),
        (_, InstMaterial::None) => None,
    }
}

fn param(name: &str, value: ParamValue, loc: &Loc) -> Param {
    Param::new(name, value, loc.clone())
}

/// The trianglemesh statement of a part.
fn mesh_entity(part: &MeshPart) -> MiResult<Entity> {
    let loc = &part.loc;
    let mut ps = ParamSet::new();
    let mut idx = Vec::with_capacity(part.tris.len() * 3);
    for t in &part.tris {
        for i in t {
            idx.push(i32::try_from(*i).map_err(|_| {
                LxsError::new(
                    LxsErrorKind::ArrayTooLong,
                    loc.clone(),
                    "mesh has too many vertices",
                )
            })?);
        }
    }
    ps.push(param("P", ParamValue::Point(part.p.clone()), loc));
    ps.push(param("indices", ParamValue::Integer(idx), loc));
    if let Some(n) = &part.n {
        ps.push(param("N", ParamValue::Normal(n.clone()), loc));
    }
    if let Some(uv) = &part.uv {
        ps.push(param(
            "uv",
            ParamValue::Float(uv.iter().flatten().copied().collect()),
            loc,
        ));
    }
    Ok(Entity {
        kind: "trianglemesh".into(),
        params: ps,
        loc: loc.clone(),
    })
}

fn shape(
    entity: Entity,
    to_world: DMat4,
    material: Option<usize>,
    light: Option<AreaLightDesc>,
) -> ShapeDesc {
    ShapeDesc {
        entity,
        object_to_world: Xform::fixed(to_world),
        material,
        area_light: light,
        reverse_orientation: false,
        interior: None,
        exterior: None,
        portal: false,
        portal_light: None,
    }
}

/// Adds the shapes of every placed object.
fn place_geometry(
    s: &MiScene,
    walk: &Walk,
    emitters: &HashMap<String, (Entity, Loc)>,
    desc: &mut SceneDescription,
    w: &mut Vec<Diagnostic>,
) -> MiResult<()> {
    let mut mats = Materials {
        scene: s,
        index: HashMap::new(),
    };
    // Object parts once per object, and each placement's material indices.
    let mut parts: HashMap<&str, Vec<MeshPart>> = HashMap::new();
    let mut placements: Vec<(usize, Vec<Option<usize>>)> = Vec::new();
    let mut warned_no_material = false;
    for (gi, g) in walk.geometry.iter().enumerate() {
        let Some(obj) = s.objects.get(g.object) else {
            continue;
        };
        if let Some((why, at)) = &obj.unsupported {
            w.push(Diagnostic {
                loc: at.clone(),
                message: format!(
                    "object \"{}\": '{why}' geometry is not supported; the object is left out",
                    obj.name
                ),
            });
            continue;
        }
        if !obj.visible {
            w.push(Diagnostic {
                loc: obj.loc.clone(),
                message: format!(
                    "object \"{}\" is 'visible off': luxfarm renders it visible",
                    obj.name
                ),
            });
        }
        let ps = parts
            .entry(g.object)
            .or_insert_with(|| objects::mesh_parts(obj, w));
        let mut idx = Vec::with_capacity(ps.len());
        for part in ps.iter() {
            let m = match part_material(part, &g.material, g, w) {
                Some(name) => {
                    let at = if g.inst.material_loc.line > 0 {
                        g.inst.material_loc.clone()
                    } else {
                        part.loc.clone()
                    };
                    Some(mats.get(name, &at, desc, w)?)
                }
                None => {
                    if !warned_no_material {
                        warned_no_material = true;
                        w.push(Diagnostic {
                            loc: g.inst.loc.clone(),
                            message: format!(
                                "instance \"{}\" has no material: LuxRender's default matte",
                                g.inst.name
                            ),
                        });
                    }
                    None
                }
            };
            idx.push(m);
        }
        placements.push((gi, idx));
    }
    // Objects placed more than once with the same materials, and not emitting: instanced.
    let mut uses: HashMap<(&str, &Vec<Option<usize>>), usize> = HashMap::new();
    for (gi, idx) in &placements {
        let g = &walk.geometry[*gi];
        if !emitters.contains_key(&g.inst.name) {
            *uses.entry((g.object, idx)).or_default() += 1;
        }
    }
    let mut object_index: HashMap<(&str, &Vec<Option<usize>>), usize> = HashMap::new();
    for (gi, idx) in &placements {
        let g = &walk.geometry[*gi];
        let to_world = local_to_world(g.world_to_local);
        let Some(ps) = parts.get(g.object) else {
            continue;
        };
        let light = emitters.get(&g.inst.name).map(|(e, _)| AreaLightDesc {
            entity: e.clone(),
            light_group: "default".into(),
        });
        let key = (g.object, idx);
        if light.is_none() && uses.get(&key).copied().unwrap_or(0) > 1 {
            let oi = match object_index.get(&key) {
                Some(&oi) => oi,
                None => {
                    let shapes = ps
                        .iter()
                        .zip(idx.iter())
                        .map(|(part, m)| Ok(shape(mesh_entity(part)?, DMat4::IDENTITY, *m, None)))
                        .collect::<MiResult<Vec<_>>>()?;
                    let loc = s
                        .objects
                        .get(g.object)
                        .map(|o| o.loc.clone())
                        .unwrap_or_default();
                    desc.objects.push(ObjectDesc {
                        name: format!("{}#{}", g.object, desc.objects.len()),
                        shapes,
                        loc,
                    });
                    object_index.insert(key, desc.objects.len() - 1);
                    desc.objects.len() - 1
                }
            };
            desc.instances.push(InstanceDesc {
                object: oi,
                instance_to_world: Xform::fixed(to_world),
                loc: g.inst.loc.clone(),
                portal: false,
                portal_light: None,
            });
            continue;
        }
        for (part, m) in ps.iter().zip(idx.iter()) {
            desc.shapes
                .push(shape(mesh_entity(part)?, to_world, *m, light.clone()));
        }
    }
    Ok(())
}
