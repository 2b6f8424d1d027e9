//! Textures: every texture class of LuxRender 1.x, with its parameter names, defaults and
//! pattern functions (one file per texture, the Blender ones under [`blender`]).
//!
//! ```text
//! TextureDesc ("class", params) --TextureSet::named (set.rs: on demand, cached, cycles refused)
//!     --build_node / build_fresnel (here: dispatch on the class name only)
//!     --<class>.rs::build (reads its own parameters) --> TexNode / FresnelNode
//! hit (SurfaceInteraction) --TexNode::eval--> Rgb;  --TexNode::duv--> bump derivatives
//! ```
//!
//! A [`TextureSet`] builds textures on demand from the [`SceneDescription`]: only names a
//! material, light or other texture references are built, and an image is loaded only when a
//! texture that uses it is built (each file once, shared). Float, colour and fresnel textures
//! live in separate namespaces as in LuxRender. Float and colour textures evaluate through one
//! node tree ([`TexNode`], node.rs): a float texture is a node whose three channels are equal
//! ([`FloatTex::eval`] reads one). Fresnel textures (optical constants n, k) are their own tree
//! ([`FresnelNode`], fresnel.rs). The renderer is RGB: spectral data (lamp and gaussian
//! spectra, tabulated data, n/k tables, Cauchy and Sellmeier laws) is converted once, at build
//! time, and kept beside the converted value ([`crate::spectrum::spd`]) for spectral rendering.
//! After a texture is built, its parameters that no code read are reported as located warnings.

pub mod add;
pub mod band;
pub mod bilerp;
pub mod blackbody;
pub mod blender;
pub mod brick;
pub mod cauchy;
pub mod checkerboard;
pub mod cloud;
pub mod colordepth;
pub mod constant;
pub mod dots;
pub mod equalenergy;
pub mod fbm;
pub mod fresnel;
pub mod fresnelcolor;
pub mod fresnelname;
pub mod gaussian;
pub mod harlequin;
pub mod hitpointalpha;
pub mod hitpointcolor;
pub mod hitpointgrey;
pub mod image_io;
pub mod imagemap;
pub mod lampspectrum;
pub mod luxpop;
pub mod mapping;
pub mod marble;
pub mod mipmap;
pub mod mix;
pub mod multimix;
pub mod node;
pub mod noise;
pub mod normalmap;
pub mod scale;
pub mod sellmeier;
pub mod set;
pub mod sopra;
pub mod spectral;
pub mod subtract;
pub mod tabulateddata;
pub mod uv;
pub mod uvmask;
pub mod windy;
pub mod wrinkled;

pub use fresnel::{Fresnel, FresnelData, FresnelNode, FresnelTex};
pub use node::TexNode;
pub use set::TextureSet;

use crate::fileio::SceneFiles;
use crate::geometry::SurfaceInteraction;
use crate::lxs::{Loc, ParamSet, TextureDesc, TextureType};
use crate::plugin::BuildError;
use crate::spectrum::Rgb;
use glam::Vec2;
use std::sync::Arc;
use thiserror::Error;

/// Errors building textures; every one names the scene location.
#[derive(Debug, Error)]
pub enum TextureError {
    #[error("{loc}: unknown {ty} texture class \"{class}\"")]
    UnknownClass { loc: Loc, ty: String, class: String },
    #[error("{loc}: no {ty} texture named \"{name}\"")]
    Missing { loc: Loc, ty: String, name: String },
    #[error("{loc}: texture \"{name}\" is a {actual} texture where a {ty} texture is needed")]
    WrongType {
        loc: Loc,
        ty: String,
        name: String,
        actual: String,
    },
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

impl TextureError {
    /// A parameter error located at parameter `name` of `t` (the statement when absent).
    pub fn param(t: &TextureDesc, name: &str, message: impl Into<String>) -> TextureError {
        TextureError::BadParam {
            loc: param_loc(&t.entity.params, name, &t.entity.loc),
            message: message.into(),
        }
    }
}

impl From<TextureError> for BuildError {
    /// The one build error type: the location, and the message without it.
    fn from(e: TextureError) -> BuildError {
        let loc = match &e {
            TextureError::UnknownClass { loc, .. }
            | TextureError::Missing { loc, .. }
            | TextureError::WrongType { loc, .. }
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
    #[inline]
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
    #[inline]
    pub fn eval(&self, si: &SurfaceInteraction) -> f32 {
        self.0.value(si)
    }
    pub fn as_const(&self) -> Option<f32> {
        self.0.as_const().map(|c| c.r)
    }
    /// The texture's derivatives with respect to the surface (u, v) at a hit, as LuxRender's
    /// `GetDuv` computes them for bump mapping; `delta` is the material's
    /// `bumpmapsampledistance` (the world-space step of the textures that difference).
    pub fn duv(&self, si: &SurfaceInteraction, delta: f32) -> Vec2 {
        self.0.duv(si, delta)
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

/// "float", "color" or "fresnel".
pub fn type_name(ty: TextureType) -> &'static str {
    match ty {
        TextureType::Float => "float",
        TextureType::Color => "color",
        TextureType::Fresnel => "fresnel",
    }
}

fn unknown(t: &TextureDesc) -> TextureError {
    TextureError::UnknownClass {
        loc: t.entity.loc.clone(),
        ty: type_name(t.value_type).to_string(),
        class: t.entity.kind.clone(),
    }
}

/// Builds a float or colour texture: dispatch on the class name.
pub(crate) fn build_node(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let color_only =
        |set: &mut TextureSet,
         f: fn(&mut TextureSet, &TextureDesc) -> Result<TexNode, TextureError>| {
            if t.value_type == TextureType::Color {
                f(set, t)
            } else {
                Err(unknown(t))
            }
        };
    match t.entity.kind.as_str() {
        "constant" => constant::build(set, t),
        "imagemap" => imagemap::build(set, t),
        "normalmap" => normalmap::build(set, t),
        "scale" => scale::build(set, t),
        "mix" => mix::build(set, t),
        "add" => add::build(set, t),
        "subtract" => subtract::build(set, t),
        "band" => band::build(set, t),
        "bilerp" => bilerp::build(set, t),
        "multimix" => multimix::build(set, t),
        "checkerboard" => checkerboard::build(set, t),
        "dots" => dots::build(set, t),
        "brick" => brick::build(set, t),
        "uvmask" => uvmask::build(set, t),
        "fbm" => fbm::build(set, t),
        "wrinkled" => wrinkled::build(set, t),
        "windy" => windy::build(set, t),
        "marble" => marble::build(set, t),
        "cloud" => cloud::build(set, t),
        "hitpointalpha" => hitpointalpha::build(set, t),
        "hitpointgrey" => hitpointgrey::build(set, t),
        "uv" => color_only(set, uv::build),
        "harlequin" => color_only(set, harlequin::build),
        "hitpointcolor" => color_only(set, hitpointcolor::build),
        "colordepth" => color_only(set, colordepth::build),
        "blackbody" => color_only(set, blackbody::build),
        "equalenergy" => color_only(set, equalenergy::build),
        "gaussian" => color_only(set, gaussian::build),
        "lampspectrum" => color_only(set, lampspectrum::build),
        "tabulateddata" => color_only(set, tabulateddata::build),
        other => match blender::kind(other) {
            Some(kind) => blender::build(set, t, kind),
            None => Err(unknown(t)),
        },
    }
}

/// Builds a fresnel texture: dispatch on the class name.
pub(crate) fn build_fresnel(
    set: &mut TextureSet,
    t: &TextureDesc,
) -> Result<FresnelNode, TextureError> {
    match t.entity.kind.as_str() {
        "constant" => constant::build_fresnel(set, t),
        "mix" => mix::build_fresnel(set, t),
        "scale" => scale::build_fresnel(set, t),
        "band" => band::build_fresnel(set, t),
        "bilerp" => bilerp::build_fresnel(set, t),
        "multimix" => multimix::build_fresnel(set, t),
        "fresnelcolor" => fresnelcolor::build(set, t),
        "fresnelname" => fresnelname::build(set, t),
        "sopra" => sopra::build(set, t),
        "luxpop" => luxpop::build(set, t),
        "cauchy" => cauchy::build(set, t),
        "sellmeier" => sellmeier::build(set, t),
        _ => Err(unknown(t)),
    }
}

/// The text of the data file a scene names `name` (spectral and nk data), opened through the
/// scene's `files` and refused above `max` bytes. Errors give the reason.
pub(crate) fn read_bounded(files: &SceneFiles, name: &str, max: u64) -> Result<String, String> {
    files.read_small_text(name, max).map_err(|e| e.reason())
}

#[cfg(test)]
pub(crate) mod tests;
