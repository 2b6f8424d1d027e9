//! `mirror`: perfect specular reflection of `Kr` (default 1, clamped to [0, 1]). Thin-film
//! parameters (`film`, `filmindex`) are not modelled and stay reported as unused.

use super::bsdf::Lobes;
use super::bxdf::specular::SpecularReflection;
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::ColorTex;

#[derive(Debug)]
pub struct Mirror {
    pub kr: ColorTex,
}

impl Mirror {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<Mirror, MaterialError> {
        Ok(Mirror {
            kr: b.textures.color_param(&e.params, "Kr", Rgb::WHITE)?,
        })
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        Lobes::Mirror(SpecularReflection {
            kr: self.kr.eval(si).map(|v| v.clamp(0.0, 1.0)),
            conductor: None,
        })
    }
}
