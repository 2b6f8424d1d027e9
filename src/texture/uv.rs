//! `uv` texture (colour): the fractional part of the 2D-mapped (s, t) as red and green, blue 0.
//! Its bump derivative is LuxRender's generic finite difference.

use super::mapping::Mapping2D;
use super::{TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;
use crate::spectrum::Rgb;

#[derive(Debug)]
pub struct UvTex {
    pub mapping: Mapping2D,
}

impl UvTex {
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        let st = self.mapping.map(si);
        Rgb::new(st.x - st.x.floor(), st.y - st.y.floor(), 0.0)
    }
}

pub fn build(_set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    Ok(TexNode::Uv(UvTex {
        mapping: Mapping2D::from_params(t)?,
    }))
}
