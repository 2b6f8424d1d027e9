//! `clear`: a medium that only absorbs — `absorption` (colour per metre, default 0) — with the
//! common `fresnel` index. Light is never scattered in it, so rays through it are only
//! attenuated by Beer–Lambert's law, exp(-absorption × distance).

use super::{transmittance, VolumeError};
use crate::geometry::Ray;
use crate::plugin::Stmt;
use crate::spectrum::Rgb;
use crate::texture::TextureSet;

#[derive(Clone, Debug, PartialEq)]
pub struct Clear {
    pub absorption: Rgb,
}

impl Clear {
    pub fn build(s: &mut Stmt, textures: &mut TextureSet) -> Result<Clear, VolumeError> {
        let absorption = super::constant_color(s, textures, "absorption")?;
        super::read_fresnel(s.params(), s.loc(), textures)?;
        Ok(Clear { absorption })
    }

    /// Transmittance over the ray's parametric extent [0, `t_max`].
    pub fn tr(&self, ray: &Ray, t_max: f32) -> Rgb {
        transmittance(self.absorption, t_max * ray.d.length())
    }
}
