//! Writing the evaluated LightWave scene as LuxRender statements into a
//! [`DescriptionBuilder`], so that the result is the same `SceneDescription` a .lxs file
//! would give.
//!
//! ```text
//! Film, SurfaceIntegrator, [MotionBegin] LookAt [MotionEnd], Camera
//! WorldBegin
//!   environment light, lights (delta lights; area lights as emitting meshes)
//!   textures and named materials of every surface in use
//!   ObjectBegin/End for object layers placed by several items (non-emitting surfaces)
//!   per visible item: AttributeBegin, its transform, NamedMaterial + Shape "trianglemesh"
//!     per surface (or ObjectInstance), luminous surfaces as AreaLightSource + Shape
//! WorldEnd
//! ```
//!
//! Statements about an item carry the location of the item's line in the .lws; materials and
//! textures the location of their object file. Fully dissolved or `UnseenByCamera` objects are
//! left out; a partly dissolved one renders its surfaces mixed with a null material.

use super::camera::CameraOut;
use super::coords::to_lux;
use super::lights::LightOut;
use super::material::{float, string, SurfacePlan};
use super::mesh::MeshData;
use crate::lxs::{
    DescriptionBuilder, Diagnostic, Entity, Loc, LxsError, LxsErrorKind, ParamSet, ParamValue,
    SceneBuilder,
};
use glam::DMat4;

/// A mesh of one surface of one layer, ready to emit.
pub struct SurfaceMesh {
    pub mesh: MeshData,
    /// Index into the plans of [`World::plans`].
    pub plan: usize,
}

/// An object layer's geometry: its meshes, by surface.
pub struct Geometry {
    pub name: String,
    pub file_loc: Loc,
    pub meshes: Vec<SurfaceMesh>,
}

/// One placed object: its geometry, transforms at the shutter times and dissolve.
pub struct Placed {
    pub geometry: usize,
    pub loc: Loc,
    pub transforms: Vec<(f32, DMat4)>,
    pub dissolve: f32,
}

/// Everything to write.
pub struct World<'a> {
    pub root_file: &'a str,
    pub camera: CameraOut,
    pub camera_loc: Loc,
    pub integrator: (&'static str, i32),
    pub environment: Option<ParamSet>,
    pub lights: Vec<(Loc, LightOut)>,
    pub plans: Vec<(Loc, SurfacePlan)>,
    pub geometries: Vec<Geometry>,
    pub placed: Vec<Placed>,
    /// Object files read, for `SceneDescription::files`.
    pub files: Vec<String>,
    pub max_array_len: usize,
}

fn entity(kind: &str, params: ParamSet, loc: &Loc) -> Entity {
    Entity {
        kind: kind.to_string(),
        params,
        loc: loc.clone(),
    }
}

const NULL_MATERIAL: &str = "lw:null";

/// Writes `w` and returns the description with `warnings` appended.
pub fn emit(w: World, warnings: Vec<Diagnostic>) -> Result<crate::lxs::SceneDescription, LxsError> {
    let mut b = DescriptionBuilder::new(w.root_file);
    for f in &w.files {
        b.include(f, &w.camera_loc)?;
    }
    let cl = &w.camera_loc;
    b.film(entity("fleximage", w.camera.film.clone(), cl))?;
    let mut integ = ParamSet::new();
    integ.add("maxdepth", ParamValue::Integer(vec![w.integrator.1]));
    b.surface_integrator(entity(w.integrator.0, integ, cl))?;
    let views = &w.camera.views;
    let blurred = views.len() > 1;
    if blurred {
        b.motion_begin(views.iter().map(|v| v.time).collect(), cl)?;
    }
    for v in views {
        b.look_at(v.eye, v.target, v.up, cl)?;
    }
    if blurred {
        b.motion_end(cl)?;
    }
    b.camera(entity("perspective", w.camera.camera.clone(), cl))?;
    b.world_begin(cl)?;
    if let Some(env) = &w.environment {
        b.attribute_begin(cl)?;
        b.light_source(entity("infinite", env.clone(), cl))?;
        b.attribute_end(cl)?;
    }
    declare_materials(&mut b, &w)?;
    for (loc, l) in &w.lights {
        emit_light(&mut b, loc, l)?;
    }
    let instanced = declare_objects(&mut b, &w)?;
    for p in &w.placed {
        emit_placed(
            &mut b,
            &w,
            p,
            instanced.get(p.geometry).copied().unwrap_or(false),
        )?;
    }
    b.world_end(cl)?;
    b.end_of_input(cl)?;
    let mut desc = b.finish();
    desc.warnings.extend(warnings);
    Ok(desc)
}

fn emit_light(b: &mut DescriptionBuilder, loc: &Loc, l: &LightOut) -> Result<(), LxsError> {
    match l {
        LightOut::Delta { kind, params } => {
            b.attribute_begin(loc)?;
            b.light_source(entity(kind, params.clone(), loc))?;
            b.attribute_end(loc)
        }
        LightOut::Area { area, meshes } => {
            for m in meshes {
                b.attribute_begin(loc)?;
                b.named_material(NULL_MATERIAL, loc)?;
                b.area_light_source(entity("area", area.clone(), loc))?;
                b.shape(entity("trianglemesh", m.clone(), loc))?;
                b.attribute_end(loc)?;
            }
            Ok(())
        }
    }
}

/// Textures and named materials of every surface, the null material, and dissolve mixes.
fn declare_materials(b: &mut DescriptionBuilder, w: &World) -> Result<(), LxsError> {
    let mut null = ParamSet::new();
    null.add("type", string("null"));
    b.make_named_material(NULL_MATERIAL, null, &w.camera_loc)?;
    for (loc, plan) in &w.plans {
        for t in &plan.textures {
            b.texture(&t.name, t.value_type, entity(t.kind, t.params.clone(), loc))?;
        }
        for m in &plan.materials {
            b.make_named_material(&m.name, m.params.clone(), loc)?;
        }
    }
    let mut done: Vec<(usize, u32)> = Vec::new();
    for p in &w.placed {
        if p.dissolve <= 0.0 {
            continue;
        }
        let Some(g) = w.geometries.get(p.geometry) else {
            continue;
        };
        for sm in &g.meshes {
            let key = (sm.plan, p.dissolve.to_bits());
            if done.contains(&key) {
                continue;
            }
            done.push(key);
            let (loc, plan) = &w.plans[sm.plan];
            let mut mix = ParamSet::new();
            mix.add("type", string("mix"));
            mix.add("namedmaterial1", string(plan.material_name()));
            mix.add("namedmaterial2", string(NULL_MATERIAL));
            mix.add("amount", float(p.dissolve));
            b.make_named_material(&dissolved_name(plan, p.dissolve), mix, loc)?;
        }
    }
    Ok(())
}

fn dissolved_name(plan: &SurfacePlan, dissolve: f32) -> String {
    format!("{}|dissolve {dissolve}", plan.material_name())
}

/// Object definitions for geometries placed (undissolved) more than once; returns which
/// geometries are instanced.
fn declare_objects(b: &mut DescriptionBuilder, w: &World) -> Result<Vec<bool>, LxsError> {
    let mut uses = vec![0usize; w.geometries.len()];
    for p in &w.placed {
        if p.dissolve <= 0.0 {
            if let Some(u) = uses.get_mut(p.geometry) {
                *u += 1;
            }
        }
    }
    let mut instanced = vec![false; w.geometries.len()];
    for (i, g) in w.geometries.iter().enumerate() {
        if uses[i] < 2 {
            continue;
        }
        instanced[i] = true;
        b.object_begin(&g.name, &g.file_loc)?;
        for sm in &g.meshes {
            let (_, plan) = &w.plans[sm.plan];
            if plan.emission.is_none() {
                b.named_material(plan.material_name(), &g.file_loc)?;
                b.shape(entity(
                    "trianglemesh",
                    mesh_params(&sm.mesh, w.max_array_len, &g.file_loc)?,
                    &g.file_loc,
                ))?;
            }
        }
        b.object_end(&g.file_loc)?;
    }
    Ok(instanced)
}

/// The item's transform: absolute, or a motion block over the shutter times.
fn place(
    b: &mut DescriptionBuilder,
    transforms: &[(f32, DMat4)],
    loc: &Loc,
) -> Result<(), LxsError> {
    let cols = |m: &DMat4| to_lux(*m).to_cols_array();
    match transforms {
        [(_, m)] => b.transform(cols(m), loc),
        many => {
            b.motion_begin(many.iter().map(|(t, _)| *t).collect(), loc)?;
            for (_, m) in many {
                b.concat_transform(cols(m), loc)?;
            }
            b.motion_end(loc)
        }
    }
}

fn emit_placed(
    b: &mut DescriptionBuilder,
    w: &World,
    p: &Placed,
    instanced: bool,
) -> Result<(), LxsError> {
    let Some(g) = w.geometries.get(p.geometry) else {
        return Ok(());
    };
    b.attribute_begin(&p.loc)?;
    place(b, &p.transforms, &p.loc)?;
    if instanced && p.dissolve <= 0.0 {
        b.object_instance(&g.name, &p.loc)?;
    }
    for sm in &g.meshes {
        let (_, plan) = &w.plans[sm.plan];
        let emits = plan.emission.is_some();
        if instanced && p.dissolve <= 0.0 && !emits {
            continue;
        }
        let material = if p.dissolve > 0.0 {
            dissolved_name(plan, p.dissolve)
        } else {
            plan.material_name().to_string()
        };
        let params = mesh_params(&sm.mesh, w.max_array_len, &p.loc)?;
        b.attribute_begin(&p.loc)?;
        b.named_material(&material, &p.loc)?;
        if let Some(l) = plan.emission {
            let mut area = ParamSet::new();
            area.add(
                "L",
                ParamValue::Color(vec![l.map(|c| c * (1.0 - p.dissolve))]),
            );
            area.add("power", float(0.0));
            area.add("efficacy", float(0.0));
            b.area_light_source(entity("area", area.clone(), &p.loc))?;
            b.shape(entity("trianglemesh", params.clone(), &p.loc))?;
            if plan.double_sided {
                b.attribute_end(&p.loc)?;
                b.attribute_begin(&p.loc)?;
                b.named_material(&material, &p.loc)?;
                b.area_light_source(entity("area", area, &p.loc))?;
                b.reverse_orientation(&p.loc)?;
                b.shape(entity("trianglemesh", params, &p.loc))?;
            }
        } else {
            b.shape(entity("trianglemesh", params, &p.loc))?;
        }
        b.attribute_end(&p.loc)?;
    }
    b.attribute_end(&p.loc)
}

/// `trianglemesh` parameters, refusing arrays longer than the scene's limit.
fn mesh_params(m: &MeshData, max: usize, loc: &Loc) -> Result<ParamSet, LxsError> {
    if m.indices.len() > max || m.p.len() > max {
        return Err(LxsError::new(
            LxsErrorKind::ArrayTooLong,
            loc.clone(),
            format!(
                "a mesh of {} points and {} indices exceeds the limit of {max} values",
                m.p.len(),
                m.indices.len()
            ),
        ));
    }
    let mut ps = ParamSet::new();
    ps.add("P", ParamValue::Point(m.p.clone()));
    ps.add("indices", ParamValue::Integer(m.indices.clone()));
    if let Some(n) = &m.n {
        ps.add("N", ParamValue::Normal(n.clone()));
    }
    if let Some(uv) = &m.uv {
        ps.add("uv", ParamValue::Float(uv.clone()));
    }
    Ok(ps)
}

/// The integrator LightWave's settings ask for: path tracing with radiosity, else direct
/// lighting with ray-traced reflections and refractions up to the recursion limit.
pub fn integrator(radiosity: bool, recursion: i64) -> (&'static str, i32) {
    let depth = recursion.clamp(1, 64) as i32;
    if radiosity {
        ("path", depth)
    } else {
        ("directlighting", depth)
    }
}
