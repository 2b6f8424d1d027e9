//! `mattetranslucent`: diffuse reflection `Kr` and diffuse transmission `Kt` (both default 1,
//! clamped), `sigma` (Oren–Nayar, default 0) and `energyconserving` (default false; when true
//! the transmission is scaled by `1 - Kr` so that reflection plus transmission stays ≤ 1).

use super::bsdf::Lobes;
use super::bxdf::diffuse::Diffuse;
use super::bxdf::translucent::Translucent;
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::{ColorTex, FloatTex};

#[derive(Debug)]
pub struct MatteTranslucent {
    pub kr: ColorTex,
    pub kt: ColorTex,
    pub sigma: FloatTex,
    pub energy_conserving: bool,
}

impl MatteTranslucent {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<MatteTranslucent, MaterialError> {
        let p = &e.params;
        Ok(MatteTranslucent {
            kr: b.textures.color_param(p, "Kr", Rgb::WHITE)?,
            kt: b.textures.color_param(p, "Kt", Rgb::WHITE)?,
            sigma: b.textures.float_param(p, "sigma", 0.0)?,
            energy_conserving: p.bool_or("energyconserving", false),
        })
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        let clamp = |c: Rgb| c.map(|v| v.clamp(0.0, 1.0));
        let r = clamp(self.kr.eval(si));
        let mut t = clamp(self.kt.eval(si));
        if self.energy_conserving {
            t *= Rgb::WHITE - r;
        }
        let sigma = self.sigma.eval(si).clamp(0.0, 90.0);
        let lobe = |c: Rgb| {
            if sigma == 0.0 {
                Diffuse::lambert(c)
            } else {
                Diffuse::oren_nayar(c, sigma)
            }
        };
        Lobes::Translucent(Translucent::new(lobe(r), lobe(t)))
    }
}
