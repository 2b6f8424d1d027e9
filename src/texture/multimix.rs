//! `multimix` texture: `Σ weightsᵢ · texᵢ` over `tex1`..`texN` (same type as the texture,
//! default 0; fresnel inputs default to index 1) with one `weights` float per input. The bump
//! derivative is the weighted sum of the inputs'.

use super::{Fresnel, FresnelNode, TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;
use crate::spectrum::Rgb;
use glam::Vec2;
use std::sync::Arc;

#[derive(Debug)]
pub struct MultiMixTex {
    pub weights: Vec<f32>,
    pub tex: Vec<Arc<TexNode>>,
}

impl MultiMixTex {
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        self.weights
            .iter()
            .zip(&self.tex)
            .fold(Rgb::BLACK, |acc, (w, t)| acc + t.eval(si) * *w)
    }

    pub fn duv(&self, si: &SurfaceInteraction, delta: f32) -> Vec2 {
        self.weights
            .iter()
            .zip(&self.tex)
            .fold(Vec2::ZERO, |acc, (w, t)| acc + t.duv(si, delta) * *w)
    }
}

fn weights(t: &TextureDesc) -> Result<Vec<f32>, TextureError> {
    let w = t.entity.params.floats("weights").unwrap_or(&[]).to_vec();
    if w.iter().any(|x| !x.is_finite()) {
        return Err(TextureError::param(
            t,
            "weights",
            "multimix weights must be finite",
        ));
    }
    Ok(w)
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let weights = weights(t)?;
    let tex = (1..=weights.len())
        .map(|i| set.same_type(t, &format!("tex{i}"), 0.0))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(TexNode::MultiMix(MultiMixTex { weights, tex }))
}

#[derive(Debug)]
pub struct MultiMixFresnel {
    pub weights: Vec<f32>,
    pub tex: Vec<Arc<FresnelNode>>,
}

impl MultiMixFresnel {
    pub fn eval(&self, si: &SurfaceInteraction) -> Fresnel {
        self.weights
            .iter()
            .zip(&self.tex)
            .fold(Fresnel::dielectric(0.0), |acc, (w, t)| {
                acc.plus(t.eval(si).scaled(*w))
            })
    }

    /// The real index at wavelength `nm` (see [`FresnelNode::index_at`]).
    pub fn index_at(&self, si: &SurfaceInteraction, nm: f32) -> f32 {
        self.weights
            .iter()
            .zip(&self.tex)
            .map(|(w, t)| w * t.index_at(si, nm))
            .sum()
    }
}

pub fn build_fresnel(set: &mut TextureSet, t: &TextureDesc) -> Result<FresnelNode, TextureError> {
    let weights = weights(t)?;
    let tex = (1..=weights.len())
        .map(|i| set.fresnel_node_param(&t.entity.params, &format!("tex{i}"), 1.0))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(FresnelNode::MultiMix(MultiMixFresnel { weights, tex }))
}
