//! `scatter`: a surface that scatters like the inside of a volume (LuxRender's
//! `SchlickScatter`): `Kd` (colour texture, default 0.9 as LuxRender's sources; its
//! scene-format page says 1) and `g` (asymmetry in [-1, 1], default 0; LuxRender reads it as
//! a colour texture, a float works too). See [`super::bxdf::scatter`].

use super::bsdf::Lobes;
use super::bxdf::scatter::SchlickScatter;
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::ColorTex;

#[derive(Debug)]
pub struct Scatter {
    pub kd: ColorTex,
    pub g: ColorTex,
}

impl Scatter {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<Scatter, MaterialError> {
        let p = &e.params;
        Ok(Scatter {
            kd: b.textures.color_param(p, "Kd", Rgb::splat(0.9))?,
            g: b.textures.color_param(p, "g", Rgb::BLACK)?,
        })
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        Lobes::Scatter(SchlickScatter::new(self.kd.eval(si), self.g.eval(si)))
    }
}
