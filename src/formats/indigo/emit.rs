//! Emitting a converted Indigo [`Scene`] as LuxRender statements through a
//! [`SceneBuilder`], in the order a .lxs file would hold them, so the description is built
//! by the same graphics state the .lxs parser uses.
//!
//! ```text
//! Film, PixelFilter, Sampler, SurfaceIntegrator, LookAt (MotionBegin for keyframes), Camera
//! WorldBegin
//!   MakeNamedVolume (media), Texture + MakeNamedMaterial (materials, in file order)
//!   AttributeBegin LightGroup LightSource ... PortalShape (exit portals) AttributeEnd
//!   ObjectBegin ... ObjectEnd for every mesh placed twice or more with the same materials,
//!   then one ObjectInstance per placement; other placements as shapes under their transform
//!   (one per material; emitting materials get their AreaLightSource and LightGroup)
//! WorldEnd
//! ```
//!
//! Shapes that emit stay world shapes (one emitter per placement, as an instanced area light
//! of LuxRender 1.x would be anyway), and so
//! do models with emission scales or IES profiles; everything else placed twice is instanced,
//! so a scene of thousands of placements of a few meshes holds each mesh once.

use super::ctx::Ctx;
use super::geometry::{flux, Model};
use super::lights::AreaOut;
use super::material::MatOut;
use super::mesh::MeshData;
use super::scene::Scene;
use crate::lxs::{Entity, Loc, LxsError, ParamSet, ParamValue, SceneBuilder};
use glam::{DMat4, DVec3};
use std::collections::HashMap;

/// A shape of one material: its LuxRender material, parameters, area light.
struct Part {
    material: Option<String>,
    params: ParamSet,
    area: Option<AreaOut>,
    interior: Option<String>,
}

struct Emitter<'a> {
    b: &'a mut dyn SceneBuilder,
    scene: &'a Scene,
    mats: HashMap<&'a str, &'a MatOut>,
    ctx: &'a Ctx,
}

fn keys_transform(
    b: &mut dyn SceneBuilder,
    keys: &[(f32, DMat4)],
    loc: &Loc,
) -> Result<(), LxsError> {
    match keys {
        [(_, m)] => b.transform(m.to_cols_array(), loc),
        _ => {
            b.motion_begin(keys.iter().map(|k| k.0).collect(), loc)?;
            for (_, m) in keys {
                b.transform(m.to_cols_array(), loc)?;
            }
            b.motion_end(loc)
        }
    }
}

impl Emitter<'_> {
    fn options(&mut self) -> Result<(), LxsError> {
        let s = &self.scene.settings;
        self.b.film(Entity {
            kind: "fleximage".into(),
            params: s.film.clone(),
            loc: s.loc.clone(),
        })?;
        if let Some(f) = &s.filter {
            self.b.pixel_filter(f.clone())?;
        }
        self.b.sampler(s.sampler.clone())?;
        self.b.surface_integrator(s.integrator.clone())?;
        if let Some(c) = &self.scene.camera {
            let loc = &c.entity.loc;
            if c.poses.len() == 1 {
                let p = c.poses[0];
                self.b.look_at(p.eye, p.target, p.up, loc)?;
            } else {
                self.b
                    .motion_begin(c.poses.iter().map(|p| p.time).collect(), loc)?;
                for p in &c.poses {
                    self.b.look_at(p.eye, p.target, p.up, loc)?;
                }
                self.b.motion_end(loc)?;
            }
            self.b.camera(c.entity.clone())?;
        }
        Ok(())
    }

    fn materials(&mut self) -> Result<(), LxsError> {
        for m in &self.scene.media {
            if let Some(v) = &m.volume {
                self.b.make_named_volume(&m.name, v.clone())?;
            }
        }
        for m in &self.scene.materials {
            for t in &m.textures {
                self.b.texture(&t.name, t.ty, t.entity.clone())?;
            }
            self.b
                .make_named_material(&m.name, m.params.clone(), &m.loc)?;
        }
        Ok(())
    }

    fn lights(&mut self) -> Result<(), LxsError> {
        let loc = self.scene.loc.clone();
        let n = self.scene.lights.len();
        for (i, l) in self.scene.lights.iter().enumerate() {
            self.b.attribute_begin(&l.entity.loc)?;
            self.b
                .light_group(&l.group, ParamSet::new(), &l.entity.loc)?;
            self.b.light_source(l.entity.clone())?;
            // Exit portals belong to the environment light: emitted in its scope.
            if i + 1 == n {
                self.portals()?;
            }
            self.b.attribute_end(&l.entity.loc)?;
        }
        if n == 0 && !self.scene.portals.is_empty() {
            self.b.attribute_begin(&loc)?;
            self.portals()?;
            self.b.attribute_end(&loc)?;
        }
        Ok(())
    }

    fn portals(&mut self) -> Result<(), LxsError> {
        for p in &self.scene.portals {
            let Some(data) = &self.scene.meshes.list[p.mesh].data else {
                continue;
            };
            let entry = &self.scene.meshes.list[p.mesh];
            self.b.attribute_begin(&p.loc)?;
            keys_transform(self.b, &p.keys, &p.loc)?;
            for mat in data.materials_used() {
                if let Some(ps) = data.to_params(mat, 0, false, entry.scale) {
                    self.b.portal_shape(Entity {
                        kind: "trianglemesh".into(),
                        params: ps,
                        loc: p.loc.clone(),
                    })?;
                }
            }
            self.b.attribute_end(&p.loc)?;
        }
        Ok(())
    }

    fn part(&mut self, part: Part, loc: &Loc) -> Result<(), LxsError> {
        self.b.attribute_begin(loc)?;
        if let Some(a) = &part.area {
            self.b.light_group(&a.group, ParamSet::new(), &a.loc)?;
            self.b.area_light_source(a.entity())?;
        }
        match &part.material {
            Some(m) => self.b.named_material(m, loc)?,
            None => self.b.material(black(loc))?,
        }
        if let Some(v) = &part.interior {
            self.b.interior(v, loc)?;
        }
        self.b.shape(Entity {
            kind: "trianglemesh".into(),
            params: part.params,
            loc: loc.clone(),
        })?;
        self.b.attribute_end(loc)
    }

    /// The LuxRender material of mesh index `i` of `model`.
    fn material_of<'m>(&self, model: &'m Model, i: u32) -> &'m str {
        match model.materials.get(i as usize) {
            Some(m) => m,
            None => {
                self.ctx.warn(
                    &model.loc,
                    format!(
                        "the mesh uses material index {i} but the model names {} material(s): the last one is used",
                        model.materials.len()
                    ),
                );
                model.materials.last().map(String::as_str).unwrap_or("")
            }
        }
    }

    fn uv_index(&self, data: &MeshData, mat: &MatOut) -> u32 {
        let Some(set) = &mat.uv_set else { return 0 };
        if let Some((_, i)) = data.uv_set_names.iter().find(|(n, _)| n == set) {
            return *i;
        }
        set.trim_start_matches("uv").parse().unwrap_or(0)
    }

    /// The parts of `model` (one per material it uses), with area lights.
    fn parts(&self, model: &Model, data: &MeshData, scale: f32, smooth: bool) -> Vec<Part> {
        let mut out = Vec::new();
        for i in data.materials_used() {
            let name = self.material_of(model, i);
            let mat = self.mats.get(name).copied();
            let uv = mat.map_or(0, |m| self.uv_index(data, m));
            let Some(params) = data.to_params(i, uv, smooth, scale) else {
                continue;
            };
            let area = mat.and_then(|m| self.area(model, i, m, data, scale));
            out.push(Part {
                material: Some(name.to_string()),
                params,
                area,
                interior: mat.and_then(|m| m.interior.clone()),
            });
        }
        out
    }

    fn area(
        &self,
        model: &Model,
        i: u32,
        m: &MatOut,
        data: &MeshData,
        scale: f32,
    ) -> Option<AreaOut> {
        let e = m.emission.as_ref()?;
        let mut a = AreaOut {
            l: e.l.clone(),
            power: 0.0,
            efficacy: 0.0,
            ies: model
                .ies
                .iter()
                .find(|(n, _)| *n == m.name)
                .map(|(_, p)| p.clone()),
            group: self.scene.group(e.layer),
            loc: e.loc.clone(),
        };
        if let Some(s) = model.emission_scales.iter().find(|s| s.material == m.name) {
            let m0 = model.keys[0].1;
            let xf =
                |p: [f32; 3]| m0.transform_point3(DVec3::from(p.map(|c| f64::from(c * scale))));
            if let Some(f) = flux(s, data.area(i, &xf), self.ctx) {
                a.power = f;
                a.efficacy = 1.0;
            }
        }
        Some(a)
    }

    fn geometry(&mut self) -> Result<(), LxsError> {
        let scene = self.scene;
        // Placements of the same mesh with the same materials, none emitting: instanced.
        let mut groups: HashMap<(usize, Vec<String>), Vec<usize>> = HashMap::new();
        for (k, m) in scene.models.iter().enumerate() {
            let Some(data) = &scene.meshes.list[m.mesh].data else {
                continue;
            };
            let used: Vec<String> = data
                .materials_used()
                .into_iter()
                .map(|i| self.material_of(m, i).to_string())
                .collect();
            let emits = used.iter().any(|n| {
                self.mats
                    .get(n.as_str())
                    .is_some_and(|x| x.emission.is_some())
            });
            if !emits && m.emission_scales.is_empty() && m.ies.is_empty() {
                groups.entry((m.mesh, used)).or_default().push(k);
            }
        }
        let mut object_of: HashMap<usize, String> = HashMap::new();
        let mut defs: Vec<_> = groups.iter().filter(|(_, v)| v.len() > 1).collect();
        defs.sort_by_key(|(_, v)| v[0]);
        for (n, (key, members)) in defs.into_iter().enumerate() {
            let model = &scene.models[members[0]];
            let entry = &scene.meshes.list[key.0];
            let Some(data) = &entry.data else { continue };
            let name = format!("{}#{n}", entry.name);
            self.b.attribute_begin(&entry.loc)?;
            self.b.object_begin(&name, &entry.loc)?;
            for part in self.parts(model, data, entry.scale, entry.smooth) {
                self.part(part, &entry.loc)?;
            }
            self.b.object_end(&entry.loc)?;
            self.b.attribute_end(&entry.loc)?;
            for &k in members {
                object_of.insert(k, name.clone());
            }
        }
        for (k, m) in scene.models.iter().enumerate() {
            let entry = &scene.meshes.list[m.mesh];
            let Some(data) = &entry.data else { continue };
            self.b.attribute_begin(&m.loc)?;
            keys_transform(self.b, &m.keys, &m.loc)?;
            match object_of.get(&k) {
                Some(obj) => self.b.object_instance(obj, &m.loc)?,
                None => {
                    for part in self.parts(m, data, entry.scale, entry.smooth) {
                        self.part(part, &m.loc)?;
                    }
                }
            }
            self.b.attribute_end(&m.loc)?;
        }
        for ml in &scene.mesh_lights {
            let entry = &scene.meshes.list[ml.mesh];
            let Some(data) = &entry.data else { continue };
            self.b.attribute_begin(&ml.loc)?;
            keys_transform(self.b, &ml.keys, &ml.loc)?;
            for i in data.materials_used() {
                if let Some(params) = data.to_params(i, 0, entry.smooth, entry.scale) {
                    let part = Part {
                        material: None,
                        params,
                        area: Some(ml.area.clone()),
                        interior: None,
                    };
                    self.part(part, &ml.loc)?;
                }
            }
            self.b.attribute_end(&ml.loc)?;
        }
        for r in &scene.area_shapes {
            let part = Part {
                material: None,
                params: r.params.clone(),
                area: Some(r.area.clone()),
                interior: None,
            };
            self.part(part, &r.loc)?;
        }
        for s in &scene.spheres {
            let loc = &s.loc;
            self.b.attribute_begin(loc)?;
            self.b.translate(s.center, loc)?;
            let mat = self.mats.get(s.material.as_str()).copied();
            if let Some(e) = mat.and_then(|m| m.emission.as_ref()) {
                self.b
                    .light_group(&scene.group(e.layer), ParamSet::new(), &e.loc)?;
                let a = AreaOut {
                    l: e.l.clone(),
                    power: 0.0,
                    efficacy: 0.0,
                    ies: None,
                    group: scene.group(e.layer),
                    loc: e.loc.clone(),
                };
                self.b.area_light_source(a.entity())?;
            }
            self.b.named_material(&s.material, loc)?;
            if let Some(v) = mat.and_then(|m| m.interior.as_ref()) {
                self.b.interior(v, loc)?;
            }
            let mut ps = ParamSet::new();
            ps.add("radius", ParamValue::Float(vec![s.radius as f32]));
            self.b.shape(Entity {
                kind: "sphere".into(),
                params: ps,
                loc: loc.clone(),
            })?;
            self.b.attribute_end(loc)?;
        }
        Ok(())
    }
}

/// The material of pure emitters (mesh and rectangle lights): black matte.
fn black(loc: &Loc) -> Entity {
    let mut ps = ParamSet::new();
    ps.add("Kd", ParamValue::Color(vec![[0.0; 3]]));
    Entity {
        kind: "matte".into(),
        params: ps,
        loc: loc.clone(),
    }
}

/// Emits `scene` into `b`.
pub fn emit(scene: &Scene, b: &mut dyn SceneBuilder, ctx: &Ctx) -> Result<(), LxsError> {
    let mats = scene
        .materials
        .iter()
        .map(|m| (m.name.as_str(), m))
        .collect();
    let mut e = Emitter {
        b,
        scene,
        mats,
        ctx,
    };
    e.options()?;
    let loc = scene.loc.clone();
    e.b.world_begin(&loc)?;
    e.materials()?;
    e.lights()?;
    e.geometry()?;
    e.b.world_end(&loc)?;
    e.b.end_of_input(&loc)
}
