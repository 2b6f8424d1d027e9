//! `glossytranslucent`: `Kd`, `Kt` (default 1, clamped), `Ks` (1), `index` (0), `Ka` (0),
//! `d` (0), `uroughness`/`vroughness` (0.1), `multibounce` (false) for the front face;
//! `onesided` (default true) copies them to the back face, otherwise `backface_Ks` (0),
//! `backface_index`, `backface_Ka`, `backface_d`, `backface_uroughness`/`vroughness` (0) and
//! `backface_multibounce` apply there. See [`super::bxdf::glossy_translucent`].

use super::bsdf::Lobes;
use super::bxdf::diffuse::Diffuse;
use super::bxdf::glossy_translucent::GlossyTranslucentLobes;
use super::bxdf::schlick::Coating;
use super::glossy::CoatParams;
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::ColorTex;

#[derive(Debug)]
pub struct GlossyTranslucent {
    pub kd: ColorTex,
    pub kt: ColorTex,
    pub front: CoatParams,
    /// `None` when one-sided: the back face uses the front parameters.
    pub back: Option<CoatParams>,
}

impl GlossyTranslucent {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<GlossyTranslucent, MaterialError> {
        let p = &e.params;
        let t = &mut b.textures;
        let kd = t.color_param(p, "Kd", Rgb::WHITE)?;
        let kt = t.color_param(p, "Kt", Rgb::WHITE)?;
        let front = CoatParams::read(t, p, "", 1.0, 0.1)?;
        let back = if p.bool_or("onesided", true) {
            None
        } else {
            Some(CoatParams::read(t, p, "backface_", 0.0, 0.0)?)
        };
        Ok(GlossyTranslucent {
            kd,
            kt,
            front,
            back,
        })
    }

    fn coating(f: &CoatParams, kd: Rgb, si: &SurfaceInteraction) -> Coating {
        Coating {
            base: Diffuse::lambert(kd),
            coat: f.eval(si),
        }
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        let kd = self.kd.eval(si).map(|v| v.clamp(0.0, 1.0));
        let front = Self::coating(&self.front, kd, si);
        let back = match &self.back {
            Some(b) => Self::coating(b, kd, si),
            None => front,
        };
        Lobes::GlossyTranslucent(GlossyTranslucentLobes {
            front,
            back,
            kt: self.kt.eval(si).map(|v| v.clamp(0.0, 1.0)),
        })
    }
}
