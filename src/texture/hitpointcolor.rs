//! `hitpointcolor` texture (colour): the interpolated vertex colour of the mesh at the hit
//! (white where the shape has none, as LuxRender).

use super::{TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;
use crate::spectrum::Rgb;

#[derive(Debug)]
pub struct HitpointColor;

impl HitpointColor {
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        Rgb::from_array(si.hit.color)
    }
}

pub fn build(_set: &mut TextureSet, _t: &TextureDesc) -> Result<TexNode, TextureError> {
    Ok(TexNode::HitpointColor(HitpointColor))
}
