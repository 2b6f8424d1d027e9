//! `mix` texture: `(1 − amount)·tex1 + amount·tex2`; `amount` is a float texture (default
//! 0.5), `tex1` defaults to 0 and `tex2` to 1 (for fresnel textures: indices 1 and 1.5). Its
//! bump derivative is LuxRender's: lerp(amount, d1, d2) + (tex2 − tex1)·d(amount).

use super::{Fresnel, FresnelNode, TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;
use crate::spectrum::Rgb;
use glam::Vec2;
use std::sync::Arc;

pub const DEFAULT_AMOUNT: f32 = 0.5;

#[derive(Debug)]
pub struct MixTex {
    pub amount: Arc<TexNode>,
    pub tex1: Arc<TexNode>,
    pub tex2: Arc<TexNode>,
}

impl MixTex {
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        let a = self.amount.value(si);
        self.tex1.eval(si) * (1.0 - a) + self.tex2.eval(si) * a
    }

    pub fn duv(&self, si: &SurfaceInteraction, delta: f32) -> Vec2 {
        let a = self.amount.value(si);
        let da = self.amount.duv(si, delta);
        let (d1, d2) = (self.tex1.duv(si, delta), self.tex2.duv(si, delta));
        let d = self.tex2.value(si) - self.tex1.value(si);
        d1 * (1.0 - a) + d2 * a + da * d
    }
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let amount = set.float_of(t, "amount", DEFAULT_AMOUNT)?;
    let (tex1, tex2) = set.operands(t, 0.0, 1.0)?;
    Ok(TexNode::Mix(MixTex { amount, tex1, tex2 }))
}

/// Two fresnel textures mixed.
#[derive(Debug)]
pub struct MixFresnel {
    pub amount: Arc<TexNode>,
    pub tex1: Arc<FresnelNode>,
    pub tex2: Arc<FresnelNode>,
}

impl MixFresnel {
    pub fn eval(&self, si: &SurfaceInteraction) -> Fresnel {
        Fresnel::lerp(
            self.amount.value(si),
            self.tex1.eval(si),
            self.tex2.eval(si),
        )
    }

    /// The real index at wavelength `nm` (see [`FresnelNode::index_at`]).
    pub fn index_at(&self, si: &SurfaceInteraction, nm: f32) -> f32 {
        let a = self.amount.value(si);
        self.tex1.index_at(si, nm) * (1.0 - a) + self.tex2.index_at(si, nm) * a
    }
}

pub fn build_fresnel(set: &mut TextureSet, t: &TextureDesc) -> Result<FresnelNode, TextureError> {
    let amount = set.float_of(t, "amount", DEFAULT_AMOUNT)?;
    let tex1 = set.fresnel_node_param(&t.entity.params, "tex1", 1.0)?;
    let tex2 = set.fresnel_node_param(&t.entity.params, "tex2", 1.5)?;
    Ok(FresnelNode::Mix(MixFresnel { amount, tex1, tex2 }))
}
