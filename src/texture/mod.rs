//! Textures: constant, imagemap, scale, mix, add, subtract, checkerboard (2D and 3D), uv and
//! blackbody, with LuxRender's parameter names and defaults (one file per texture).
//!
//! A [`TextureSet`] builds textures on demand from the [`SceneDescription`]: only names a
//! material (or another texture) references are built, and an image is loaded only when an
//! `imagemap` that uses it is built (each file once, shared). Float and colour textures live
//! in separate namespaces as in LuxRender; both evaluate through the same node tree, a float
//! texture being a node whose three channels are equal ([`FloatTex::eval`] reads one).

pub mod add;
pub mod blackbody;
pub mod checkerboard;
pub mod constant;
pub mod image_io;
pub mod imagemap;
pub mod mapping;
pub mod mix;
pub mod scale;
pub mod subtract;
pub mod uv;

use crate::fileio::SceneFiles;
use crate::geometry::SurfaceInteraction;
use crate::lxs::{Diagnostic, Loc, ParamSet, SceneDescription, TextureDesc, TextureType};
use crate::plugin::BuildError;
use crate::spectrum::Rgb;
use std::collections::HashMap;
use std::sync::Arc;
use thiserror::Error;

/// Errors building textures; every one names the scene location.
#[derive(Debug, Error)]
pub enum TextureError {
    #[error("{loc}: unknown {ty} texture class \"{class}\"")]
    UnknownClass { loc: Loc, ty: String, class: String },
    #[error("{loc}: no {ty} texture named \"{name}\"")]
    Missing { loc: Loc, ty: String, name: String },
    #[error("{loc}: texture \"{name}\" refers to itself")]
    Cycle { loc: Loc, name: String },
    #[error("{loc}: cannot load image \"{path}\": {message}")]
    Image {
        loc: Loc,
        path: String,
        message: String,
    },
    #[error("{loc}: {message}")]
    BadParam { loc: Loc, message: String },
}

impl From<TextureError> for BuildError {
    /// The one build error type: the location, and the message without it.
    fn from(e: TextureError) -> BuildError {
        let loc = match &e {
            TextureError::UnknownClass { loc, .. }
            | TextureError::Missing { loc, .. }
            | TextureError::Cycle { loc, .. }
            | TextureError::Image { loc, .. }
            | TextureError::BadParam { loc, .. } => loc.clone(),
        };
        let full = e.to_string();
        let message = full
            .strip_prefix(&format!("{loc}: "))
            .unwrap_or(&full)
            .to_string();
        BuildError { loc, message }
    }
}

/// Where texture files are found.
#[derive(Clone, Debug, Default)]
pub struct TextureCtx {
    /// Where image files are opened: relative to the scene's directory, confined to it on a
    /// farm.
    pub files: SceneFiles,
}

/// One node of a texture tree. Each variant is implemented in the file of its texture.
#[derive(Debug)]
pub enum TexNode {
    Const(Rgb),
    Image(imagemap::ImageTex),
    Scale(Arc<TexNode>, Arc<TexNode>),
    Mix(mix::MixTex),
    Add(Arc<TexNode>, Arc<TexNode>),
    Subtract(Arc<TexNode>, Arc<TexNode>),
    Checker2D(checkerboard::Checker2D),
    Checker3D(checkerboard::Checker3D),
    Uv(uv::UvTex),
}

impl TexNode {
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        match self {
            TexNode::Const(c) => *c,
            TexNode::Image(t) => t.eval(si),
            TexNode::Scale(a, b) => a.eval(si) * b.eval(si),
            TexNode::Mix(m) => m.eval(si),
            TexNode::Add(a, b) => a.eval(si) + b.eval(si),
            TexNode::Subtract(a, b) => a.eval(si) - b.eval(si),
            TexNode::Checker2D(c) => c.eval(si),
            TexNode::Checker3D(c) => c.eval(si),
            TexNode::Uv(u) => u.eval(si),
        }
    }

    /// The constant value when the node does not vary.
    pub fn as_const(&self) -> Option<Rgb> {
        match self {
            TexNode::Const(c) => Some(*c),
            _ => None,
        }
    }
}

/// A colour-valued texture.
#[derive(Clone, Debug)]
pub struct ColorTex(pub Arc<TexNode>);

/// A float-valued texture.
#[derive(Clone, Debug)]
pub struct FloatTex(pub Arc<TexNode>);

impl ColorTex {
    pub fn constant(c: Rgb) -> ColorTex {
        ColorTex(Arc::new(TexNode::Const(c)))
    }
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        self.0.eval(si)
    }
    pub fn as_const(&self) -> Option<Rgb> {
        self.0.as_const()
    }
}

impl FloatTex {
    pub fn constant(v: f32) -> FloatTex {
        FloatTex(Arc::new(TexNode::Const(Rgb::splat(v))))
    }
    pub fn eval(&self, si: &SurfaceInteraction) -> f32 {
        self.0.eval(si).r
    }
    pub fn as_const(&self) -> Option<f32> {
        self.0.as_const().map(|c| c.r)
    }
}

/// The location of parameter `name` in `params`, or `fallback`.
pub fn param_loc(params: &ParamSet, name: &str, fallback: &Loc) -> Loc {
    params
        .params
        .iter()
        .rev()
        .find(|p| p.name == name && !p.loc.file.is_empty())
        .map(|p| p.loc.clone())
        .unwrap_or_else(|| fallback.clone())
}

fn type_name(ty: TextureType) -> &'static str {
    match ty {
        TextureType::Float => "float",
        TextureType::Color => "color",
    }
}

/// Builds referenced textures on demand and caches them (and their images).
pub struct TextureSet<'a> {
    desc: &'a SceneDescription,
    ctx: TextureCtx,
    built: HashMap<(TextureType, String), Arc<TexNode>>,
    building: Vec<(TextureType, String)>,
    images: image_io::ImageCache,
    /// Non-fatal problems (unsupported options that fell back), with their location.
    pub warnings: Vec<Diagnostic>,
}

impl<'a> TextureSet<'a> {
    pub fn new(desc: &'a SceneDescription, ctx: TextureCtx) -> TextureSet<'a> {
        TextureSet {
            desc,
            ctx,
            built: HashMap::new(),
            building: Vec::new(),
            images: image_io::ImageCache::default(),
            warnings: Vec::new(),
        }
    }

    /// Number of distinct image files loaded so far.
    pub fn images_loaded(&self) -> usize {
        self.images.len()
    }

    /// Names of the textures built so far.
    pub fn built_names(&self) -> Vec<String> {
        let mut v: Vec<String> = self.built.keys().map(|k| k.1.clone()).collect();
        v.sort();
        v
    }

    pub(crate) fn warn(&mut self, loc: &Loc, message: String) {
        tracing::warn!("{loc}: {message}");
        self.warnings.push(Diagnostic {
            loc: loc.clone(),
            message,
        });
    }

    /// A colour parameter: a `texture` reference, a constant `color`, a `float` (grey), or the
    /// default.
    pub fn color_param(
        &mut self,
        params: &ParamSet,
        name: &str,
        default: Rgb,
    ) -> Result<ColorTex, TextureError> {
        Ok(ColorTex(self.node_param(
            TextureType::Color,
            params,
            name,
            default,
        )?))
    }

    /// A float parameter: a `texture` reference, a constant `float`, or the default.
    pub fn float_param(
        &mut self,
        params: &ParamSet,
        name: &str,
        default: f32,
    ) -> Result<FloatTex, TextureError> {
        Ok(FloatTex(self.node_param(
            TextureType::Float,
            params,
            name,
            Rgb::splat(default),
        )?))
    }

    /// An optional float texture parameter (`bumpmap`): `None` when absent.
    pub fn optional_float(
        &mut self,
        params: &ParamSet,
        name: &str,
    ) -> Result<Option<FloatTex>, TextureError> {
        if !params.contains(name) {
            return Ok(None);
        }
        self.float_param(params, name, 0.0).map(Some)
    }

    pub(crate) fn node_param(
        &mut self,
        ty: TextureType,
        params: &ParamSet,
        name: &str,
        default: Rgb,
    ) -> Result<Arc<TexNode>, TextureError> {
        if let Some(tex) = params.texture(name) {
            let tex = tex.to_string();
            let loc = param_loc(params, name, &Loc::default());
            return self.named(ty, &tex, &loc);
        }
        if ty == TextureType::Color {
            if let Some(c) = params.color(name) {
                return Ok(Arc::new(TexNode::Const(Rgb::from_array(c))));
            }
        }
        if let Some(v) = params.float(name) {
            return Ok(Arc::new(TexNode::Const(Rgb::splat(v))));
        }
        Ok(Arc::new(TexNode::Const(default)))
    }

    /// The texture `name` of type `ty`, built on first use.
    pub fn named(
        &mut self,
        ty: TextureType,
        name: &str,
        loc: &Loc,
    ) -> Result<Arc<TexNode>, TextureError> {
        let key = (ty, name.to_string());
        if let Some(n) = self.built.get(&key) {
            return Ok(n.clone());
        }
        if self.building.contains(&key) {
            return Err(TextureError::Cycle {
                loc: loc.clone(),
                name: name.to_string(),
            });
        }
        let desc = self.desc;
        let Some(tdesc) = desc.texture(ty, name) else {
            return Err(TextureError::Missing {
                loc: loc.clone(),
                ty: type_name(ty).to_string(),
                name: name.to_string(),
            });
        };
        self.building.push(key.clone());
        let node = self.build(tdesc);
        self.building.pop();
        let node = Arc::new(node?);
        tracing::debug!(
            "built {} texture \"{name}\" ({})",
            type_name(ty),
            tdesc.entity.kind
        );
        self.built.insert(key, node.clone());
        Ok(node)
    }

    fn build(&mut self, t: &TextureDesc) -> Result<TexNode, TextureError> {
        match t.entity.kind.as_str() {
            "constant" => constant::build(self, t),
            "imagemap" => imagemap::build(self, t),
            "scale" => scale::build(self, t),
            "mix" => mix::build(self, t),
            "add" => add::build(self, t),
            "subtract" => subtract::build(self, t),
            "checkerboard" => checkerboard::build(self, t),
            "uv" => uv::build(self, t),
            "blackbody" => blackbody::build(self, t),
            other => Err(TextureError::UnknownClass {
                loc: t.entity.loc.clone(),
                ty: type_name(t.value_type).to_string(),
                class: other.to_string(),
            }),
        }
    }

    /// The two operands `tex1`/`tex2` of a binary texture, typed like the texture itself.
    pub(crate) fn operands(
        &mut self,
        t: &TextureDesc,
        d1: f32,
        d2: f32,
    ) -> Result<(Arc<TexNode>, Arc<TexNode>), TextureError> {
        let p = &t.entity.params;
        let a = self.node_param(t.value_type, p, "tex1", Rgb::splat(d1))?;
        let b = self.node_param(t.value_type, p, "tex2", Rgb::splat(d2))?;
        Ok((a, b))
    }
}

#[cfg(test)]
pub(crate) mod tests;
