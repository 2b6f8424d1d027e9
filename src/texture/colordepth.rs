//! `colordepth` texture (colour): the absorption coefficient that makes light turn `Kt` (a
//! colour texture, default 0) after travelling `depth` metres (default 1, at least 0.001):
//! −ln(clamp(Kt, 1e-9, 1)) / depth per channel, as LuxRender computes it.

use super::{ColorTex, TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;
use crate::spectrum::Rgb;

pub const DEFAULT_DEPTH: f32 = 1.0;

#[derive(Debug)]
pub struct ColorDepthTex {
    pub kt: ColorTex,
    pub depth: f32,
}

impl ColorDepthTex {
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        self.kt
            .eval(si)
            .map(|c| -c.clamp(1e-9, 1.0).ln() / self.depth)
    }
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let kt = set.color_param(&t.entity.params, "Kt", Rgb::BLACK)?;
    let depth = t.entity.params.float_or("depth", DEFAULT_DEPTH);
    if !depth.is_finite() {
        return Err(TextureError::param(t, "depth", "depth must be finite"));
    }
    Ok(TexNode::ColorDepth(ColorDepthTex {
        kt,
        depth: depth.max(1e-3),
    }))
}
