//! LuxRender's graphics state as the description builder keeps it: what AttributeBegin saves
//! and AttributeEnd restores (material, area light, orientation, volumes, light group, and the
//! scoped namespaces of textures, named materials and named volumes), the stack of open
//! blocks, and which part of the file (options, world, motion) the parser is in.

use crate::lxs::description::Entity;
use crate::lxs::description::TextureType;
use crate::lxs::params::Loc;
use std::collections::HashMap;
use std::rc::Rc;

/// One resolved texture reference inside a parameter list (see `texrefs`): parameter index,
/// namespace, texture index. Kept in the graphics state with the area light it belongs to.
#[derive(Clone, Copy, Debug)]
pub struct Binding {
    pub param: usize,
    pub ty: TextureType,
    pub texture: usize,
}

/// A scoped name -> index map, shared between saved states until one of them changes it.
pub type Names = Rc<HashMap<String, usize>>;

/// The attributes AttributeBegin/AttributeEnd save and restore.
#[derive(Clone, Default)]
pub struct GraphicsState {
    /// Index into `SceneDescription::materials` (None: LuxRender's default matte).
    pub material: Option<usize>,
    /// The current AreaLightSource with its resolved texture references.
    pub area_light: Option<Rc<(Entity, Vec<Binding>)>>,
    pub reverse_orientation: bool,
    pub interior: Option<String>,
    pub exterior: Option<String>,
    /// Empty until a LightGroup statement: lights then go to "default".
    pub light_group: String,
    /// Kind of the last LightSource (PortalShape/PortalInstance attach to it).
    pub current_light: Option<String>,
    /// Index in `SceneDescription::lights` of that light (`None` inside ObjectBegin, whose
    /// lights are only placed by their instances).
    pub current_light_index: Option<usize>,
    pub float_textures: Names,
    pub color_textures: Names,
    pub fresnel_textures: Names,
    pub named_materials: Names,
    pub named_volumes: Names,
}

impl GraphicsState {
    pub fn textures(&self, ty: TextureType) -> &Names {
        match ty {
            TextureType::Float => &self.float_textures,
            TextureType::Color => &self.color_textures,
            TextureType::Fresnel => &self.fresnel_textures,
        }
    }

    pub fn textures_mut(&mut self, ty: TextureType) -> &mut HashMap<String, usize> {
        match ty {
            TextureType::Float => Rc::make_mut(&mut self.float_textures),
            TextureType::Color => Rc::make_mut(&mut self.color_textures),
            TextureType::Fresnel => Rc::make_mut(&mut self.fresnel_textures),
        }
    }
}

/// Kinds of nested blocks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BlockKind {
    Attribute,
    Transform,
    Object,
}

impl BlockKind {
    pub fn begin(self) -> &'static str {
        match self {
            BlockKind::Attribute => "AttributeBegin",
            BlockKind::Transform => "TransformBegin",
            BlockKind::Object => "ObjectBegin",
        }
    }

    pub fn end(self) -> &'static str {
        match self {
            BlockKind::Attribute => "AttributeEnd",
            BlockKind::Transform => "TransformEnd",
            BlockKind::Object => "ObjectEnd",
        }
    }
}

/// An open block and what it saved.
pub struct Block {
    pub kind: BlockKind,
    pub loc: Loc,
    pub ctm: crate::lxs::description::Xform,
    /// Saved graphics state (Attribute and Object blocks).
    pub gs: Option<GraphicsState>,
}

/// Where in the file the parser is.
#[derive(Clone, Debug, PartialEq)]
pub enum Phase {
    Options,
    World(Loc),
    Ended(Loc),
}

/// An open MotionBegin block.
pub struct Motion {
    pub loc: Loc,
    pub times: Vec<f32>,
    pub transforms: Vec<glam::DMat4>,
}
