//! `fresnelcolor` texture (fresnel): the optical constants that reflect colour `Kr` (a colour
//! texture, default 0.5) at normal incidence, per hit (LuxRender's `FresnelApproxEta` and
//! `FresnelApproxK`, a conductor).

use super::{ColorTex, Fresnel, FresnelNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;
use crate::spectrum::Rgb;

pub const DEFAULT_KR: f32 = 0.5;

#[derive(Debug)]
pub struct FresnelColorTex {
    pub kr: ColorTex,
}

impl FresnelColorTex {
    pub fn eval(&self, si: &SurfaceInteraction) -> Fresnel {
        Fresnel::from_reflectance(self.kr.eval(si))
    }
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<FresnelNode, TextureError> {
    let kr = set.color_param(&t.entity.params, "Kr", Rgb::splat(DEFAULT_KR))?;
    Ok(match kr.as_const() {
        Some(c) => FresnelNode::Const(Fresnel::from_reflectance(c)),
        None => FresnelNode::Color(FresnelColorTex { kr }),
    })
}
