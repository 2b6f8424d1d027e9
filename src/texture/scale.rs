//! `scale` texture: `tex1 · tex2` (both default 1). For colour textures `tex1` may be a float
//! texture (LuxRender's `ScaleTexture<float, SWCSpectrum>`); for fresnel textures `tex1` is a
//! float and `tex2` the fresnel texture it scales. The bump derivative follows the product
//! rule.

use super::{Fresnel, FresnelNode, TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::{TextureDesc, TextureType};
use crate::spectrum::Rgb;
use std::sync::Arc;

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let (a, b) = set.operands(t, 1.0, 1.0)?;
    Ok(TexNode::Scale(a, b))
}

/// A fresnel texture scaled by a float.
#[derive(Debug)]
pub struct ScaleFresnel {
    pub k: Arc<TexNode>,
    pub f: Arc<FresnelNode>,
}

impl ScaleFresnel {
    pub fn eval(&self, si: &SurfaceInteraction) -> Fresnel {
        self.f.eval(si).scaled(self.k.value(si))
    }

    /// The real index at wavelength `nm` (see [`FresnelNode::index_at`]).
    pub fn index_at(&self, si: &SurfaceInteraction, nm: f32) -> f32 {
        self.f.index_at(si, nm) * self.k.value(si)
    }
}

pub fn build_fresnel(set: &mut TextureSet, t: &TextureDesc) -> Result<FresnelNode, TextureError> {
    let k = set.node_param(TextureType::Float, &t.entity.params, "tex1", Rgb::WHITE)?;
    let f = set.fresnel_node_param(&t.entity.params, "tex2", 1.0)?;
    Ok(FresnelNode::Scale(ScaleFresnel { k, f }))
}
