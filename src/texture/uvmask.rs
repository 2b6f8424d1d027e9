//! `uvmask` texture (float): `innertex` (default 1) where the 2D-mapped (s, t) lies in
//! [0, 1]², `outertex` (default 0) elsewhere. Its bump derivative is LuxRender's: a step of
//! (inner − outer)/delta within a sample distance of the mask's edges.

use super::mapping::Mapping2D;
use super::{TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;
use crate::spectrum::Rgb;
use glam::Vec2;
use std::sync::Arc;

#[derive(Debug)]
pub struct UvMaskTex {
    pub mapping: Mapping2D,
    pub inner: Arc<TexNode>,
    pub outer: Arc<TexNode>,
}

impl UvMaskTex {
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        let st = self.mapping.map(si);
        if st.x < 0.0 || st.x > 1.0 || st.y < 0.0 || st.y > 1.0 {
            self.outer.eval(si)
        } else {
            self.inner.eval(si)
        }
    }

    pub fn duv(&self, si: &SurfaceInteraction, delta: f32) -> Vec2 {
        let m = self.mapping.map_duv(si);
        let ds = delta * (m.d_du.x + m.d_dv.x);
        let dt = delta * (m.d_du.y + m.d_dv.y);
        let mut d = Vec2::ZERO;
        if m.st.x.abs() < ds {
            d += Vec2::new(m.d_du.x, m.d_dv.x);
        } else if (m.st.x - 1.0).abs() < ds {
            d -= Vec2::new(m.d_du.x, m.d_dv.x);
        }
        if m.st.y.abs() < dt {
            d += Vec2::new(m.d_du.y, m.d_dv.y);
        } else if (m.st.y - 1.0).abs() < dt {
            d -= Vec2::new(m.d_du.y, m.d_dv.y);
        }
        if d != Vec2::ZERO && delta > 0.0 {
            d *= (self.inner.value(si) - self.outer.value(si)) / delta;
        }
        d
    }
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let inner = set.same_type(t, "innertex", 1.0)?;
    let outer = set.same_type(t, "outertex", 0.0)?;
    Ok(TexNode::UvMask(UvMaskTex {
        mapping: Mapping2D::from_params(t)?,
        inner,
        outer,
    }))
}
