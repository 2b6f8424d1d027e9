//! `DescriptionBuilder`: the [`SceneBuilder`] that keeps LuxRender's graphics state and
//! produces a [`SceneDescription`].
//!
//! This file implements the trait (transforms, coordinate systems, options, blocks);
//! `blocks.rs` holds the phase and nesting rules, `world.rs` the world statements (textures,
//! materials, lights, shapes, objects, volumes).

mod blocks;
mod refs;
mod state;
mod texrefs;
mod world;

pub use world::MAX_COPIED_VALUES;
pub mod xform;

use super::builder::SceneBuilder;
use super::description::{Diagnostic, Entity, SceneDescription, Xform};
use super::error::{LxsError, LxsErrorKind, LxsResult};
use super::params::{Loc, ParamSet};
use glam::DMat4;
use refs::Family;
use state::{Block, BlockKind, GraphicsState, Motion, Phase};
use std::collections::HashMap;

/// Builds a [`SceneDescription`] from statements, enforcing LuxRender's rules.
pub struct DescriptionBuilder {
    desc: SceneDescription,
    phase: Phase,
    ctm: Xform,
    gs: GraphicsState,
    blocks: Vec<Block>,
    motion: Option<Motion>,
    coord_systems: HashMap<String, Xform>,
    /// Object being defined (index into `desc.objects`).
    current_object: Option<usize>,
    objects_by_name: HashMap<String, usize>,
    /// Lights declared inside object definitions, instanced with each ObjectInstance.
    object_lights: HashMap<usize, Vec<super::description::LightDesc>>,
    /// Emitting shapes (an AreaLightSource in scope) of object definitions, with their area
    /// lights' texture bindings: each ObjectInstance places them as world shapes.
    object_emitters: HashMap<usize, Vec<(super::description::ShapeDesc, Vec<texrefs::Binding>)>>,
    /// Parameter values copied so far by instancing (shapes of an object instanced inside
    /// another definition, and emitting shapes placed per instance), against
    /// `copy_limit`.
    copied_values: u64,
    copy_limit: u64,
    /// Texture references with the texture each was bound to.
    tex_refs: Vec<(texrefs::Owner, texrefs::Binding)>,
    /// `namedmaterialN` references: (material, parameter, item, bound material).
    mat_refs: Vec<(usize, usize, usize, usize)>,
}

impl DescriptionBuilder {
    /// A builder for the scene whose root file is `root_file`.
    pub fn new(root_file: &str) -> DescriptionBuilder {
        let desc = SceneDescription {
            root_file: root_file.to_string(),
            files: vec![root_file.to_string()],
            ..SceneDescription::default()
        };
        DescriptionBuilder {
            desc,
            phase: Phase::Options,
            ctm: Xform::identity(),
            gs: GraphicsState::default(),
            blocks: Vec::new(),
            motion: None,
            coord_systems: HashMap::new(),
            current_object: None,
            objects_by_name: HashMap::new(),
            object_lights: HashMap::new(),
            object_emitters: HashMap::new(),
            copied_values: 0,
            copy_limit: MAX_COPIED_VALUES,
            tex_refs: Vec::new(),
            mat_refs: Vec::new(),
        }
    }

    /// This builder with at most `limit` parameter values copied by instancing
    /// ([`crate::lxs::ParseOptions::max_copied_values`]).
    pub fn with_copy_limit(mut self, limit: u64) -> DescriptionBuilder {
        self.copy_limit = limit;
        self
    }

    /// The finished description.
    pub fn finish(mut self) -> SceneDescription {
        texrefs::bind_aliases(&mut self.desc, &self.tex_refs);
        texrefs::bind_material_aliases(&mut self.desc, &self.mat_refs);
        if self.desc.light_groups.is_empty() {
            self.desc.light_groups.push("default".to_string());
        }
        self.desc
    }

    fn warn(&mut self, loc: &Loc, message: impl Into<String>) {
        self.desc.warnings.push(Diagnostic {
            loc: loc.clone(),
            message: message.into(),
        });
    }

    fn legacy(&mut self, family: Family, stmt: &str, e: &Entity) {
        if let Some(modern) = refs::modern_equivalent(family, &e.kind) {
            let msg = format!(
                "legacy {stmt} \"{}\" accepted as written; its modern equivalent is \"{modern}\"",
                e.kind
            );
            self.warn(&e.loc, msg);
        }
    }

    fn set_option(&mut self, stmt: &str, family: Option<Family>, e: Entity) -> LxsResult<()> {
        self.options_only(stmt, &e.loc)?;
        if let Some(f) = family {
            self.legacy(f, stmt, &e);
        }
        let slot = match stmt {
            "Film" => &mut self.desc.film,
            "PixelFilter" => &mut self.desc.pixel_filter,
            "Sampler" => &mut self.desc.sampler,
            "SurfaceIntegrator" => &mut self.desc.surface_integrator,
            "VolumeIntegrator" => &mut self.desc.volume_integrator,
            "Accelerator" => &mut self.desc.accelerator,
            _ => &mut self.desc.renderer,
        };
        *slot = Some(e);
        Ok(())
    }

    fn undefined(&self, loc: &Loc, what: &str, name: &str, known: Vec<&str>) -> LxsError {
        let hint = super::suggest::nearest(name, &known)
            .map(|s| format!(" (did you mean \"{s}\"?)"))
            .unwrap_or_default();
        LxsError::new(
            LxsErrorKind::Undefined,
            loc.clone(),
            format!("{what} \"{name}\" is not defined here{hint}"),
        )
    }
}

impl SceneBuilder for DescriptionBuilder {
    fn identity(&mut self, loc: &Loc) -> LxsResult<()> {
        self.apply("Identity", DMat4::IDENTITY, true, loc)
    }

    fn translate(&mut self, d: [f64; 3], loc: &Loc) -> LxsResult<()> {
        self.apply("Translate", xform::translate(d), false, loc)
    }

    fn rotate(&mut self, angle_deg: f64, axis: [f64; 3], loc: &Loc) -> LxsResult<()> {
        let m = xform::rotate(angle_deg, axis, loc)?;
        self.apply("Rotate", m, false, loc)
    }

    fn scale(&mut self, s: [f64; 3], loc: &Loc) -> LxsResult<()> {
        self.apply("Scale", xform::scale(s), false, loc)
    }

    fn look_at(
        &mut self,
        eye: [f64; 3],
        target: [f64; 3],
        up: [f64; 3],
        loc: &Loc,
    ) -> LxsResult<()> {
        let m = xform::look_at(eye, target, up, loc)?;
        self.apply("LookAt", m, false, loc)
    }

    fn transform(&mut self, m: [f64; 16], loc: &Loc) -> LxsResult<()> {
        let m = xform::from_columns(m, loc)?;
        self.apply("Transform", m, true, loc)
    }

    fn concat_transform(&mut self, m: [f64; 16], loc: &Loc) -> LxsResult<()> {
        let m = xform::from_columns(m, loc)?;
        self.apply("ConcatTransform", m, false, loc)
    }

    fn coordinate_system(&mut self, name: &str, loc: &Loc) -> LxsResult<()> {
        self.before_end("CoordinateSystem", loc)?;
        self.not_in_motion("CoordinateSystem", loc)?;
        self.coord_systems
            .insert(name.to_string(), self.ctm.clone());
        self.desc
            .coordinate_systems
            .insert(name.to_string(), self.ctm.start());
        Ok(())
    }

    fn coord_sys_transform(&mut self, name: &str, loc: &Loc) -> LxsResult<()> {
        self.before_end("CoordSysTransform", loc)?;
        let Some(cs) = self.coord_systems.get(name).cloned() else {
            let known = self.coord_systems.keys().map(String::as_str).collect();
            return Err(self.undefined(loc, "coordinate system", name, known));
        };
        if let Some(motion) = &mut self.motion {
            if cs.keys.len() != 1 {
                return Err(LxsError::new(
                    LxsErrorKind::Unsupported,
                    loc.clone(),
                    format!("animated coordinate system \"{name}\" cannot be used inside a motion block"),
                ));
            }
            motion.transforms.push(cs.start());
        } else {
            self.ctm = cs;
        }
        Ok(())
    }

    fn motion_begin(&mut self, times: Vec<f32>, loc: &Loc) -> LxsResult<()> {
        self.before_end("MotionBegin", loc)?;
        self.not_in_motion("MotionBegin", loc)?;
        self.motion = Some(Motion {
            loc: loc.clone(),
            times,
            transforms: Vec::new(),
        });
        Ok(())
    }

    fn motion_end(&mut self, loc: &Loc) -> LxsResult<()> {
        let Some(m) = self.motion.take() else {
            return Err(LxsError::new(
                LxsErrorKind::UnmatchedEnd,
                loc.clone(),
                "MotionEnd without MotionBegin",
            ));
        };
        if m.times.len() != m.transforms.len() {
            return Err(LxsError::new(
                LxsErrorKind::WrongValueCount,
                loc.clone(),
                format!(
                    "the MotionBegin at {} gives {} times but its block holds {} transforms",
                    m.loc,
                    m.times.len(),
                    m.transforms.len()
                ),
            ));
        }
        let motion = Xform {
            keys: m.times.into_iter().zip(m.transforms).collect(),
        };
        self.ctm = xform::mul(&self.ctm, &motion, loc)?;
        Ok(())
    }

    fn transform_begin(&mut self, loc: &Loc) -> LxsResult<()> {
        self.before_end("TransformBegin", loc)?;
        self.not_in_motion("TransformBegin", loc)?;
        self.push_block(BlockKind::Transform, loc);
        Ok(())
    }

    fn transform_end(&mut self, loc: &Loc) -> LxsResult<()> {
        self.before_end("TransformEnd", loc)?;
        self.not_in_motion("TransformEnd", loc)?;
        self.pop_block(BlockKind::Transform, loc)
    }

    fn camera(&mut self, mut e: Entity) -> LxsResult<()> {
        self.options_only("Camera", &e.loc)?;
        let world_to_camera = self.camera_transform(&mut e)?;
        let camera_to_world = xform::inverse(&world_to_camera, &e.loc, "the camera transform")?;
        self.coord_systems
            .insert("camera".to_string(), camera_to_world.clone());
        self.desc
            .coordinate_systems
            .insert("camera".to_string(), camera_to_world.start());
        self.desc.camera = Some(super::description::CameraDesc {
            entity: e,
            world_to_camera,
            exterior: None,
        });
        Ok(())
    }

    fn film(&mut self, e: Entity) -> LxsResult<()> {
        self.set_option("Film", Some(Family::Film), e)
    }

    fn pixel_filter(&mut self, e: Entity) -> LxsResult<()> {
        self.set_option("PixelFilter", None, e)
    }

    fn sampler(&mut self, e: Entity) -> LxsResult<()> {
        self.set_option("Sampler", Some(Family::Sampler), e)
    }

    fn surface_integrator(&mut self, e: Entity) -> LxsResult<()> {
        self.set_option("SurfaceIntegrator", None, e)
    }

    fn volume_integrator(&mut self, e: Entity) -> LxsResult<()> {
        self.set_option("VolumeIntegrator", None, e)
    }

    fn accelerator(&mut self, e: Entity) -> LxsResult<()> {
        self.set_option("Accelerator", None, e)
    }

    fn renderer(&mut self, e: Entity) -> LxsResult<()> {
        self.set_option("Renderer", None, e)
    }

    fn world_begin(&mut self, loc: &Loc) -> LxsResult<()> {
        self.options_only("WorldBegin", loc)?;
        self.check_closed("WorldBegin")?;
        self.phase = Phase::World(loc.clone());
        self.ctm = Xform::identity();
        self.coord_systems
            .insert("world".to_string(), Xform::identity());
        self.desc
            .coordinate_systems
            .insert("world".to_string(), DMat4::IDENTITY);
        Ok(())
    }

    fn world_end(&mut self, loc: &Loc) -> LxsResult<()> {
        self.world_only("WorldEnd", loc)?;
        self.check_closed("WorldEnd")?;
        if let Some(cam) = &mut self.desc.camera {
            cam.exterior = self.gs.exterior.clone();
        }
        self.phase = Phase::Ended(loc.clone());
        Ok(())
    }

    fn attribute_begin(&mut self, loc: &Loc) -> LxsResult<()> {
        self.world_only("AttributeBegin", loc)?;
        self.push_block(BlockKind::Attribute, loc);
        Ok(())
    }

    fn attribute_end(&mut self, loc: &Loc) -> LxsResult<()> {
        self.world_only("AttributeEnd", loc)?;
        self.pop_block(BlockKind::Attribute, loc)
    }

    fn object_begin(&mut self, name: &str, loc: &Loc) -> LxsResult<()> {
        self.world_only("ObjectBegin", loc)?;
        self.begin_object(name, loc)
    }

    fn object_end(&mut self, loc: &Loc) -> LxsResult<()> {
        self.world_only("ObjectEnd", loc)?;
        self.end_object(loc)
    }

    fn object_instance(&mut self, name: &str, loc: &Loc) -> LxsResult<()> {
        self.world_only("ObjectInstance", loc)?;
        self.instance(name, loc, false)
    }

    fn portal_instance(&mut self, name: &str, loc: &Loc) -> LxsResult<()> {
        self.world_only("PortalInstance", loc)?;
        self.instance(name, loc, true)
    }

    fn motion_instance(
        &mut self,
        name: &str,
        start: f32,
        end: f32,
        to: &str,
        loc: &Loc,
    ) -> LxsResult<()> {
        self.world_only("MotionInstance", loc)?;
        self.motion_instance_impl(name, start, end, to, loc)
    }

    fn texture(&mut self, name: &str, value_type: &str, e: Entity) -> LxsResult<()> {
        self.world_only("Texture", &e.loc)?;
        self.define_texture(name, value_type, e)
    }

    fn material(&mut self, e: Entity) -> LxsResult<()> {
        self.world_only("Material", &e.loc)?;
        self.legacy(Family::Material, "Material", &e);
        self.define_material(None, e)
    }

    fn make_named_material(&mut self, name: &str, params: ParamSet, loc: &Loc) -> LxsResult<()> {
        self.world_only("MakeNamedMaterial", loc)?;
        let kind = match params.string("type") {
            Some(k) => k.to_string(),
            None => {
                self.warn(loc, format!("MakeNamedMaterial \"{name}\" has no \"string type\": matte assumed, as LuxRender does"));
                "matte".to_string()
            }
        };
        let e = Entity {
            kind,
            params,
            loc: loc.clone(),
        };
        self.legacy(Family::Material, "Material", &e);
        self.define_material(Some(name), e)
    }

    fn named_material(&mut self, name: &str, loc: &Loc) -> LxsResult<()> {
        self.world_only("NamedMaterial", loc)?;
        match self.gs.named_materials.get(name) {
            Some(&i) => {
                self.gs.material = Some(i);
                Ok(())
            }
            None => {
                let known = self.gs.named_materials.keys().map(String::as_str).collect();
                Err(self.undefined(loc, "named material", name, known))
            }
        }
    }

    fn light_group(&mut self, name: &str, _params: ParamSet, loc: &Loc) -> LxsResult<()> {
        self.world_only("LightGroup", loc)?;
        if !self.desc.light_groups.iter().any(|g| g == name) {
            self.desc.light_groups.push(name.to_string());
        }
        self.gs.light_group = name.to_string();
        Ok(())
    }

    fn light_source(&mut self, e: Entity) -> LxsResult<()> {
        self.world_only("LightSource", &e.loc)?;
        self.legacy(Family::Light, "LightSource", &e);
        self.add_light(e)
    }

    fn area_light_source(&mut self, e: Entity) -> LxsResult<()> {
        self.world_only("AreaLightSource", &e.loc)?;
        let bindings = self.texture_refs(&e.params, None)?;
        self.gs.area_light = Some(std::rc::Rc::new((e, bindings)));
        Ok(())
    }

    fn shape(&mut self, e: Entity) -> LxsResult<()> {
        self.world_only("Shape", &e.loc)?;
        self.add_shape(e, false)
    }

    fn portal_shape(&mut self, e: Entity) -> LxsResult<()> {
        self.world_only("PortalShape", &e.loc)?;
        self.add_shape(e, true)
    }

    fn reverse_orientation(&mut self, loc: &Loc) -> LxsResult<()> {
        self.world_only("ReverseOrientation", loc)?;
        self.gs.reverse_orientation = !self.gs.reverse_orientation;
        Ok(())
    }

    fn make_named_volume(&mut self, name: &str, e: Entity) -> LxsResult<()> {
        self.world_only("MakeNamedVolume", &e.loc)?;
        self.add_volume(Some(name), e)
    }

    fn volume(&mut self, e: Entity) -> LxsResult<()> {
        self.world_only("Volume", &e.loc)?;
        self.add_volume(None, e)
    }

    fn interior(&mut self, name: &str, loc: &Loc) -> LxsResult<()> {
        self.world_only("Interior", loc)?;
        self.gs.interior = self.volume_ref(name, loc)?;
        Ok(())
    }

    fn exterior(&mut self, name: &str, loc: &Loc) -> LxsResult<()> {
        self.world_only("Exterior", loc)?;
        self.gs.exterior = self.volume_ref(name, loc)?;
        Ok(())
    }

    fn include(&mut self, path: &str, _loc: &Loc) -> LxsResult<()> {
        if !self.desc.files.iter().any(|f| f == path) {
            self.desc.files.push(path.to_string());
        }
        Ok(())
    }

    fn search_path(&mut self, path: &str, loc: &Loc) -> LxsResult<()> {
        self.warn(
            loc,
            format!("SearchPath \"{path}\" ignored (LuxRender never implemented it)"),
        );
        Ok(())
    }

    fn warning(&mut self, d: Diagnostic) {
        self.desc.warnings.push(d);
    }

    fn end_of_input(&mut self, loc: &Loc) -> LxsResult<()> {
        self.check_closed("the end of the input")?;
        if let Phase::World(at) = &self.phase {
            return Err(LxsError::new(
                LxsErrorKind::UnclosedBlock,
                at.clone(),
                format!("WorldBegin is not closed by WorldEnd before the end of the input ({loc})"),
            ));
        }
        Ok(())
    }
}
