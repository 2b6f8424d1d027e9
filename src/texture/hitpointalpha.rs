//! `hitpointalpha` texture (float): the interpolated vertex alpha of the mesh at the hit (1
//! where the shape has none, as LuxRender).

use super::{TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;

#[derive(Debug)]
pub struct HitpointAlpha;

impl HitpointAlpha {
    pub fn value(&self, si: &SurfaceInteraction) -> f32 {
        si.hit.alpha
    }
}

pub fn build(_set: &mut TextureSet, _t: &TextureDesc) -> Result<TexNode, TextureError> {
    Ok(TexNode::HitpointAlpha(HitpointAlpha))
}
