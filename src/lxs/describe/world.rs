//! World statements of the description builder: textures, materials, lights, shapes, object
//! definitions and instances, volumes, and the camera's transform.

use super::state::BlockKind;
use super::texrefs::{self, Binding, Owner};
use super::{xform, DescriptionBuilder};
use crate::lxs::description::{
    AreaLightDesc, Entity, InstanceDesc, LightDesc, MaterialDesc, ObjectDesc, ShapeDesc,
    TextureDesc, TextureType, VolumeDesc, Xform,
};
use crate::lxs::error::{LxsError, LxsErrorKind, LxsResult};
use crate::lxs::params::{Loc, ParamSet, ParamValue};
use std::rc::Rc;

/// The default of most parameter values instancing may copy in one scene (shapes copied
/// into another object's definition, emitting shapes placed per instance): copies multiply
/// what a file holds, so a small hostile file could otherwise ask for unbounded memory. 2^26
/// values is a thousand instances of an emitting mesh of 20,000 vertices.
pub const MAX_COPIED_VALUES: u64 = 1 << 26;

/// The parameter values a shape carries (a triple counts as 3).
fn shape_values(s: &ShapeDesc) -> u64 {
    s.entity
        .params
        .params
        .iter()
        .map(|p| {
            let triples = matches!(
                p.value,
                ParamValue::Point(_)
                    | ParamValue::Vector(_)
                    | ParamValue::Normal(_)
                    | ParamValue::Color(_)
            );
            p.value.len() as u64 * if triples { 3 } else { 1 }
        })
        .sum()
}

impl DescriptionBuilder {
    /// The camera's world-to-camera transform: the CTM, or with `"string endtransform"` naming
    /// a coordinate system, a two-key motion from shutteropen to shutterclose (LuxRender).
    pub(super) fn camera_transform(&mut self, e: &mut Entity) -> LxsResult<Xform> {
        let Some(end_name) = e.params.string("endtransform").map(str::to_string) else {
            return Ok(self.ctm.clone());
        };
        if end_name.is_empty() {
            return Ok(self.ctm.clone());
        }
        let Some(end) = self.coord_systems.get(&end_name).cloned() else {
            let known = self.coord_systems.keys().map(String::as_str).collect();
            return Err(self.undefined(
                &e.loc,
                "coordinate system (endtransform)",
                &end_name,
                known,
            ));
        };
        if self.ctm.keys.len() != 1 {
            self.warn(&e.loc, "both a motion transform and endtransform given for the camera: endtransform ignored, as LuxRender does");
            return Ok(self.ctm.clone());
        }
        let open = e.params.float_or("shutteropen", 0.0);
        let close = e.params.float_or("shutterclose", 1.0);
        Ok(Xform {
            keys: vec![(open, self.ctm.start()), (close, end.start())],
        })
    }

    /// The light group lights get now ("default" when none is set), registered on first use.
    fn current_light_group(&mut self) -> String {
        if self.gs.light_group.is_empty() {
            self.gs.light_group = "default".to_string();
        }
        let g = self.gs.light_group.clone();
        if !self.desc.light_groups.contains(&g) {
            self.desc.light_groups.push(g.clone());
        }
        g
    }

    pub(super) fn define_texture(
        &mut self,
        name: &str,
        value_type: &str,
        e: Entity,
    ) -> LxsResult<()> {
        let ty = match value_type {
            "float" => TextureType::Float,
            "color" => TextureType::Color,
            "fresnel" => TextureType::Fresnel,
            other => {
                return Err(LxsError::new(
                    LxsErrorKind::WrongValueType,
                    e.loc,
                    format!("Texture \"{name}\": value type must be \"float\", \"color\" or \"fresnel\", found \"{other}\""),
                ))
            }
        };
        let bindings = self.texture_refs(&e.params, Some(ty))?;
        if self.gs.textures(ty).contains_key(name) {
            self.warn(&e.loc, format!("{value_type} texture \"{name}\" redefined"));
        }
        let index = self.desc.textures.len();
        self.record_refs(Owner::Texture(index), &bindings);
        self.desc.textures.push(TextureDesc {
            name: name.to_string(),
            value_type: ty,
            entity: e,
            object_to_world: self.ctm.clone(),
        });
        self.desc
            .named_textures
            .insert((ty, name.to_string()), index);
        self.gs.textures_mut(ty).insert(name.to_string(), index);
        Ok(())
    }

    /// Resolves the texture references of a parameter list in the current scope.
    pub(super) fn texture_refs(
        &self,
        params: &ParamSet,
        own: Option<TextureType>,
    ) -> LxsResult<Vec<Binding>> {
        texrefs::resolve(&self.gs, params, own, |what, name, known| {
            self.undefined(&Loc::default(), what, name, known)
        })
    }

    fn record_refs(&mut self, owner: Owner, bindings: &[Binding]) {
        self.tex_refs.extend(bindings.iter().map(|&b| (owner, b)));
    }

    /// Mix and layered materials name other materials in `namedmaterialN` strings: each must
    /// be defined in scope. Returns (parameter, item, material index) for each reference.
    fn material_refs(&self, params: &ParamSet) -> LxsResult<Vec<(usize, usize, usize)>> {
        let mut out = Vec::new();
        for (pi, p) in params.params.iter().enumerate() {
            let ParamValue::String(names) = &p.value else {
                continue;
            };
            if !p.name.starts_with("namedmaterial") {
                continue;
            }
            for (k, n) in names.iter().enumerate().filter(|(_, n)| !n.is_empty()) {
                match self.gs.named_materials.get(n.as_str()) {
                    Some(&m) => out.push((pi, k, m)),
                    None => {
                        let known = self.gs.named_materials.keys().map(String::as_str).collect();
                        let err = self.undefined(&p.loc, "named material", n, known);
                        return Err(LxsError {
                            message: format!("parameter '{}': {}", p.name, err.message),
                            ..err
                        });
                    }
                }
            }
        }
        Ok(out)
    }

    pub(super) fn define_material(&mut self, name: Option<&str>, e: Entity) -> LxsResult<()> {
        let bindings = self.texture_refs(&e.params, None)?;
        let mats = self.material_refs(&e.params)?;
        let index = self.desc.materials.len();
        self.mat_refs
            .extend(mats.into_iter().map(|(p, k, m)| (index, p, k, m)));
        self.record_refs(Owner::Material(index), &bindings);
        let loc = e.loc.clone();
        self.desc.materials.push(MaterialDesc {
            name: name.map(str::to_string),
            entity: e,
        });
        match name {
            Some(n) => {
                if self.gs.named_materials.contains_key(n) {
                    self.warn(&loc, format!("named material \"{n}\" redefined"));
                }
                self.desc.named_materials.insert(n.to_string(), index);
                Rc::make_mut(&mut self.gs.named_materials).insert(n.to_string(), index);
            }
            None => self.gs.material = Some(index),
        }
        Ok(())
    }

    pub(super) fn add_light(&mut self, e: Entity) -> LxsResult<()> {
        let bindings = self.texture_refs(&e.params, None)?;
        let kind = e.kind.clone();
        let light = LightDesc {
            entity: e,
            light_to_world: self.ctm.clone(),
            light_group: self.current_light_group(),
            exterior: self.gs.exterior.clone(),
            instance_motion: None,
        };
        self.gs.current_light_index = match self.current_object {
            Some(obj) => {
                self.object_lights.entry(obj).or_default().push(light);
                None
            }
            None => {
                let index = self.desc.lights.len();
                self.record_refs(Owner::Light(index), &bindings);
                self.desc.lights.push(light);
                Some(index)
            }
        };
        self.gs.current_light = Some(kind);
        Ok(())
    }

    /// A shape. One with an area light in scope inside an object definition is kept aside
    /// and placed by each instance of the object as a world shape of its own (LuxRender 1.x's
    /// `InstanceAreaLight` and `MotionAreaLight`: every instance is a light where it is).
    pub(super) fn add_shape(&mut self, e: Entity, portal: bool) -> LxsResult<()> {
        let mut area_light = None;
        let mut bindings = Vec::new();
        if let Some(al) = self.gs.area_light.clone().filter(|_| !portal) {
            bindings = al.1.clone();
            area_light = Some(AreaLightDesc {
                entity: al.0.clone(),
                light_group: self.current_light_group(),
            });
        }
        if portal && self.gs.current_light.is_none() {
            self.warn(
                &e.loc,
                "PortalShape without a preceding LightSource in scope",
            );
        }
        let shape = ShapeDesc {
            entity: e,
            object_to_world: self.ctm.clone(),
            material: self.gs.material,
            area_light,
            reverse_orientation: self.gs.reverse_orientation,
            interior: self.gs.interior.clone(),
            exterior: self.gs.exterior.clone(),
            portal,
            portal_light: self.gs.current_light_index.filter(|_| portal),
        };
        match self.current_object {
            Some(obj) if !portal && shape.area_light.is_some() => {
                self.object_emitters
                    .entry(obj)
                    .or_default()
                    .push((shape, bindings));
            }
            Some(obj) if !portal => {
                if let Some(o) = self.desc.objects.get_mut(obj) {
                    o.shapes.push(shape);
                }
            }
            _ => self.add_world_shape(shape, &bindings),
        }
        Ok(())
    }

    /// Adds a world shape, recording its area light's texture references.
    fn add_world_shape(&mut self, shape: ShapeDesc, bindings: &[Binding]) {
        if shape.area_light.is_some() {
            self.record_refs(Owner::AreaLight(self.desc.shapes.len()), bindings);
        }
        self.desc.shapes.push(shape);
    }

    /// Counts `values` copied by the instance at `loc` against the copy limit
    /// ([`MAX_COPIED_VALUES`] by default): past it, the instance is an error.
    fn charge_copy(&mut self, values: u64, loc: &Loc) -> LxsResult<()> {
        self.copied_values = self.copied_values.saturating_add(values);
        if self.copied_values > self.copy_limit {
            return Err(LxsError::new(
                LxsErrorKind::InputTooLarge,
                loc.clone(),
                format!(
                    "instancing would copy more than {} parameter values of shapes \
                     (instances inside object definitions, or of emitting shapes)",
                    self.copy_limit
                ),
            ));
        }
        Ok(())
    }

    /// Places the emitting shapes of `object` by an instance's transform `to_world`: world
    /// shapes, or, for an instance inside another definition, emitters of that object.
    fn place_emitters(&mut self, object: usize, to_world: &Xform, loc: &Loc) -> LxsResult<()> {
        let values = self
            .object_emitters
            .get(&object)
            .map_or(0, |v| v.iter().map(|(s, _)| shape_values(s)).sum());
        self.charge_copy(values, loc)?;
        let emitters = self
            .object_emitters
            .get(&object)
            .cloned()
            .unwrap_or_default();
        for (mut s, bindings) in emitters {
            s.object_to_world = xform::mul(to_world, &s.object_to_world, loc)?;
            match self.current_object {
                Some(cur) => self
                    .object_emitters
                    .entry(cur)
                    .or_default()
                    .push((s, bindings)),
                None => self.add_world_shape(s, &bindings),
            }
        }
        Ok(())
    }

    pub(super) fn begin_object(&mut self, name: &str, loc: &Loc) -> LxsResult<()> {
        if let Some(cur) = self.current_object.and_then(|i| self.desc.objects.get(i)) {
            return Err(LxsError::new(
                LxsErrorKind::WrongBlock,
                loc.clone(),
                format!(
                    "ObjectBegin \"{name}\" inside the definition of \"{}\" begun at {}",
                    cur.name, cur.loc
                ),
            ));
        }
        self.push_block(BlockKind::Object, loc);
        let index = self.desc.objects.len();
        self.desc.objects.push(ObjectDesc {
            name: name.to_string(),
            shapes: Vec::new(),
            loc: loc.clone(),
        });
        self.objects_by_name.insert(name.to_string(), index);
        self.current_object = Some(index);
        Ok(())
    }

    pub(super) fn end_object(&mut self, loc: &Loc) -> LxsResult<()> {
        if self.current_object.is_none() {
            return Err(LxsError::new(
                LxsErrorKind::UnmatchedEnd,
                loc.clone(),
                "ObjectEnd without ObjectBegin",
            ));
        }
        self.pop_block(BlockKind::Object, loc)?;
        self.current_object = None;
        Ok(())
    }

    fn object_index(&self, name: &str, loc: &Loc) -> LxsResult<usize> {
        match self.objects_by_name.get(name) {
            Some(&i) if Some(i) == self.current_object => Err(LxsError::new(
                LxsErrorKind::InvalidValue,
                loc.clone(),
                format!("object \"{name}\" instances itself inside its own definition"),
            )),
            Some(&i) => Ok(i),
            None => {
                let known = self.objects_by_name.keys().map(String::as_str).collect();
                Err(self.undefined(loc, "object", name, known))
            }
        }
    }

    /// ObjectInstance / PortalInstance with the current CTM.
    pub(super) fn instance(&mut self, name: &str, loc: &Loc, portal: bool) -> LxsResult<()> {
        let object = self.object_index(name, loc)?;
        if portal && self.gs.current_light.is_none() {
            self.warn(
                loc,
                format!(
                    "PortalInstance \"{name}\" ignored: no LightSource in scope, as LuxRender does"
                ),
            );
            return Ok(());
        }
        let ctm = self.ctm.clone();
        self.place_instance(object, ctm, loc, portal)
    }

    fn place_instance(
        &mut self,
        object: usize,
        to_world: Xform,
        loc: &Loc,
        portal: bool,
    ) -> LxsResult<()> {
        if let Some(cur) = self.current_object.filter(|_| !portal) {
            // An instance inside another definition: copy the shapes in, transformed.
            let values = self
                .desc
                .objects
                .get(object)
                .map_or(0, |o| o.shapes.iter().map(shape_values).sum());
            self.charge_copy(values, loc)?;
            let shapes = self
                .desc
                .objects
                .get(object)
                .map(|o| o.shapes.clone())
                .unwrap_or_default();
            let mut moved = Vec::with_capacity(shapes.len());
            for mut s in shapes {
                s.object_to_world = xform::mul(&to_world, &s.object_to_world, loc)?;
                moved.push(s);
            }
            if let Some(o) = self.desc.objects.get_mut(cur) {
                o.shapes.extend(moved);
            }
        } else {
            self.desc.instances.push(InstanceDesc {
                object,
                instance_to_world: to_world.clone(),
                loc: loc.clone(),
                portal,
                portal_light: self.gs.current_light_index.filter(|_| portal),
            });
        }
        if portal {
            return Ok(());
        }
        self.place_emitters(object, &to_world, loc)?;
        let lights = self.object_lights.get(&object).cloned().unwrap_or_default();
        for mut l in lights {
            place_light(&mut l, &to_world, loc)?;
            match self.current_object {
                Some(cur) => self.object_lights.entry(cur).or_default().push(l),
                None => self.desc.lights.push(l),
            }
        }
        Ok(())
    }

    pub(super) fn motion_instance_impl(
        &mut self,
        name: &str,
        start: f32,
        end: f32,
        to: &str,
        loc: &Loc,
    ) -> LxsResult<()> {
        self.warn(loc, format!("MotionInstance \"{name}\" is deprecated: use ObjectInstance inside a MotionBegin/MotionEnd block"));
        let object = self.object_index(name, loc)?;
        let Some(end_xf) = self.coord_systems.get(to).cloned() else {
            let known = self.coord_systems.keys().map(String::as_str).collect();
            return Err(self.undefined(loc, "coordinate system", to, known));
        };
        let xf = Xform {
            keys: vec![(start, self.ctm.start()), (end, end_xf.start())],
        };
        self.place_instance(object, xf, loc, false)
    }

    pub(super) fn add_volume(&mut self, name: Option<&str>, e: Entity) -> LxsResult<()> {
        let index = self.desc.volumes.len();
        let loc = e.loc.clone();
        self.desc.volumes.push(VolumeDesc {
            name: name.map(str::to_string),
            entity: e,
            object_to_world: self.ctm.clone(),
        });
        if let Some(n) = name {
            if self.gs.named_volumes.contains_key(n) {
                self.warn(&loc, format!("named volume \"{n}\" redefined"));
            }
            self.desc.named_volumes.insert(n.to_string(), index);
            Rc::make_mut(&mut self.gs.named_volumes).insert(n.to_string(), index);
        }
        Ok(())
    }

    /// Interior/Exterior: "" clears; otherwise the named volume must be defined in scope.
    pub(super) fn volume_ref(&self, name: &str, loc: &Loc) -> LxsResult<Option<String>> {
        if name.is_empty() {
            return Ok(None);
        }
        if self.gs.named_volumes.contains_key(name) {
            Ok(Some(name.to_string()))
        } else {
            let known = self.gs.named_volumes.keys().map(String::as_str).collect();
            Err(self.undefined(loc, "named volume", name, known))
        }
    }
}

/// Places a light of an instanced object by the instance's transform `to_world`: a static
/// transform joins the light's own; a moving one becomes (or carries) the light's instance
/// motion, as LuxRender wraps such a light in a `MotionLight` that moves at each ray's time.
fn place_light(l: &mut LightDesc, to_world: &Xform, loc: &Loc) -> LxsResult<()> {
    match &l.instance_motion {
        Some(m) => l.instance_motion = Some(xform::mul(to_world, m, loc)?),
        None if to_world.is_animated() => l.instance_motion = Some(to_world.clone()),
        None => l.light_to_world = xform::mul(to_world, &l.light_to_world, loc)?,
    }
    Ok(())
}
