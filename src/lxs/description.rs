//! `SceneDescription`: the parsed scene as plain, serializable data.
//!
//! This is the single hand-off between parsing and rendering (and between master and worker).
//! Every entity carries its plugin name, its typed [`ParamSet`], the place it was declared and
//! its world transform (all motion keys). Nothing here knows how to render.
//!
//! Transform conventions: matrices are `glam::DMat4` mapping the entity's own space to world
//! space (`object_to_world`), except the camera, whose `world_to_camera` is the current
//! transformation matrix at the `Camera` statement, as in LuxRender.

use super::params::{Loc, ParamSet};
use glam::DMat4;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A transform, possibly animated: one key when static, several (time, matrix) keys when the
/// statement was inside `MotionBegin [t0 t1 ...] ... MotionEnd`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Xform {
    pub keys: Vec<(f32, DMat4)>,
}

impl Xform {
    pub fn fixed(m: DMat4) -> Xform {
        Xform {
            keys: vec![(0.0, m)],
        }
    }

    pub fn identity() -> Xform {
        Xform::fixed(DMat4::IDENTITY)
    }

    /// The matrix at the first key (the whole transform when not animated).
    pub fn start(&self) -> DMat4 {
        self.keys.first().map(|k| k.1).unwrap_or(DMat4::IDENTITY)
    }

    pub fn is_animated(&self) -> bool {
        self.keys.len() > 1 && self.keys.iter().any(|k| k.1 != self.keys[0].1)
    }
}

impl Default for Xform {
    fn default() -> Self {
        Xform::identity()
    }
}

/// A plugin instance as written: `Camera "perspective" ...` gives kind "perspective".
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Entity {
    pub kind: String,
    pub params: ParamSet,
    pub loc: Loc,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CameraDesc {
    pub entity: Entity,
    /// The CTM at the `Camera` statement (world space to camera space).
    pub world_to_camera: Xform,
    /// Named coordinate system "CAMERA" is defined by this statement, as in LuxRender.
    pub exterior: Option<String>,
}

/// Value type of a texture: LuxRender keeps float, color and fresnel textures in separate
/// namespaces. Fresnel textures give optical data (a complex index of refraction).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, PartialOrd, Ord)]
#[serde(rename_all = "lowercase")]
pub enum TextureType {
    Float,
    Color,
    Fresnel,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TextureDesc {
    pub name: String,
    pub value_type: TextureType,
    /// Texture class ("imagemap", "checkerboard", ...) in `entity.kind`.
    pub entity: Entity,
    pub object_to_world: Xform,
}

/// A material: `Material "matte" ...` (anonymous) or `MakeNamedMaterial "name" "string type"
/// ["matte"] ...` (named; `entity.kind` is taken from its `type` parameter).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MaterialDesc {
    pub name: Option<String>,
    pub entity: Entity,
}

/// An `AreaLightSource` bound to the shapes that follow it in the same attribute block.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AreaLightDesc {
    pub entity: Entity,
    pub light_group: String,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LightDesc {
    pub entity: Entity,
    pub light_to_world: Xform,
    pub light_group: String,
    pub exterior: Option<String>,
    /// The motion of the moving object instance that placed this light (LuxRender's
    /// `MotionLight`): `light_to_world` places the light in the instance, this moves the
    /// instance at each ray's time. `None` for a light that no moving instance placed.
    #[serde(default)]
    pub instance_motion: Option<Xform>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShapeDesc {
    pub entity: Entity,
    /// For shapes inside `ObjectBegin`, the CTM at the shape relative to world at definition
    /// time; instances apply their own transform on top.
    pub object_to_world: Xform,
    /// Index into `SceneDescription::materials`; `None` means LuxRender's default (matte 0.9).
    pub material: Option<usize>,
    pub area_light: Option<AreaLightDesc>,
    pub reverse_orientation: bool,
    pub interior: Option<String>,
    pub exterior: Option<String>,
    /// True when declared with `PortalShape` (used only for light sampling, never rendered).
    pub portal: bool,
    /// For a portal: index into `SceneDescription::lights` of the LightSource it belongs to
    /// (the last one declared in its attribute scope, as LuxRender ties them).
    #[serde(default)]
    pub portal_light: Option<usize>,
}

/// Shapes collected between `ObjectBegin "name"` and `ObjectEnd`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ObjectDesc {
    pub name: String,
    pub shapes: Vec<ShapeDesc>,
    pub loc: Loc,
}

/// `ObjectInstance "name"` (or `PortalInstance`), with the CTM at that statement.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct InstanceDesc {
    /// Index into `SceneDescription::objects`.
    pub object: usize,
    pub instance_to_world: Xform,
    pub loc: Loc,
    pub portal: bool,
    /// For a `PortalInstance`: index into `SceneDescription::lights` of its light.
    #[serde(default)]
    pub portal_light: Option<usize>,
}

/// `MakeNamedVolume "name" "type" ...` or an anonymous `Volume "type" ...` region.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VolumeDesc {
    pub name: Option<String>,
    pub entity: Entity,
    pub object_to_world: Xform,
}

/// A problem that does not stop parsing (unused parameter, legacy name accepted, ...).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Diagnostic {
    pub loc: Loc,
    pub message: String,
}

impl std::fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.loc, self.message)
    }
}

/// `named_textures` is keyed by (type, name) pairs, which JSON object keys cannot hold: it is
/// written as a list of `{type, name, index}` records.
mod named_textures_serde {
    use super::TextureType;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};
    use std::collections::BTreeMap;

    #[derive(Serialize, Deserialize)]
    struct Record {
        #[serde(rename = "type")]
        ty: TextureType,
        name: String,
        index: usize,
    }

    pub fn serialize<S: Serializer>(
        map: &BTreeMap<(TextureType, String), usize>,
        s: S,
    ) -> Result<S::Ok, S::Error> {
        let list: Vec<Record> = map
            .iter()
            .map(|((ty, name), &index)| Record {
                ty: *ty,
                name: name.clone(),
                index,
            })
            .collect();
        list.serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<BTreeMap<(TextureType, String), usize>, D::Error> {
        let list = Vec::<Record>::deserialize(d)?;
        Ok(list
            .into_iter()
            .map(|r| ((r.ty, r.name), r.index))
            .collect())
    }
}

/// The whole parsed scene.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SceneDescription {
    /// The .lxs file that was parsed, as given.
    pub root_file: String,
    /// Every file read while parsing (the root and each Include), in order of first reading.
    pub files: Vec<String>,
    pub camera: Option<CameraDesc>,
    pub film: Option<Entity>,
    pub pixel_filter: Option<Entity>,
    pub sampler: Option<Entity>,
    pub surface_integrator: Option<Entity>,
    pub volume_integrator: Option<Entity>,
    pub accelerator: Option<Entity>,
    pub renderer: Option<Entity>,
    /// All textures in declaration order. A redefinition appends; `named_textures` points at
    /// the definition in force at the end of the file.
    pub textures: Vec<TextureDesc>,
    #[serde(with = "named_textures_serde")]
    pub named_textures: BTreeMap<(TextureType, String), usize>,
    /// All materials (anonymous and named) in declaration order.
    pub materials: Vec<MaterialDesc>,
    pub named_materials: BTreeMap<String, usize>,
    pub lights: Vec<LightDesc>,
    pub shapes: Vec<ShapeDesc>,
    pub objects: Vec<ObjectDesc>,
    pub instances: Vec<InstanceDesc>,
    pub volumes: Vec<VolumeDesc>,
    pub named_volumes: BTreeMap<String, usize>,
    /// Light group names in order of first use; "default" when none is declared.
    pub light_groups: Vec<String>,
    /// Named coordinate systems (`CoordinateSystem "name"`), world-to-that-space CTMs.
    pub coordinate_systems: BTreeMap<String, DMat4>,
    pub warnings: Vec<Diagnostic>,
}

impl SceneDescription {
    pub fn named_material(&self, name: &str) -> Option<&MaterialDesc> {
        self.named_materials.get(name).map(|&i| &self.materials[i])
    }

    pub fn texture(&self, ty: TextureType, name: &str) -> Option<&TextureDesc> {
        self.named_textures
            .get(&(ty, name.to_string()))
            .map(|&i| &self.textures[i])
    }

    pub fn object(&self, name: &str) -> Option<&ObjectDesc> {
        self.objects.iter().rev().find(|o| o.name == name)
    }

    /// All entities with parameters, with a label, for reporting unused parameters.
    pub fn entities(&self) -> impl Iterator<Item = (&'static str, &Entity)> {
        let singles = [
            ("Camera", self.camera.as_ref().map(|c| &c.entity)),
            ("Film", self.film.as_ref()),
            ("PixelFilter", self.pixel_filter.as_ref()),
            ("Sampler", self.sampler.as_ref()),
            ("SurfaceIntegrator", self.surface_integrator.as_ref()),
            ("VolumeIntegrator", self.volume_integrator.as_ref()),
            ("Accelerator", self.accelerator.as_ref()),
            ("Renderer", self.renderer.as_ref()),
        ];
        let singles = singles.into_iter().filter_map(|(l, e)| e.map(|e| (l, e)));
        let shapes = self
            .shapes
            .iter()
            .chain(self.objects.iter().flat_map(|o| o.shapes.iter()));
        singles
            .chain(self.textures.iter().map(|t| ("Texture", &t.entity)))
            .chain(self.materials.iter().map(|m| ("Material", &m.entity)))
            .chain(self.lights.iter().map(|l| ("LightSource", &l.entity)))
            .chain(shapes.flat_map(|s| {
                std::iter::once(("Shape", &s.entity))
                    .chain(s.area_light.iter().map(|a| ("AreaLightSource", &a.entity)))
            }))
            .chain(self.volumes.iter().map(|v| ("Volume", &v.entity)))
    }
}
