//! `matte`: `Kd` (default 0.9, clamped to [0, 1]) and `sigma` (Oren–Nayar roughness in
//! degrees, default 0 = Lambertian, clamped to [0, 90]).

use super::bsdf::Lobes;
use super::bxdf::diffuse::Diffuse;
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::{ColorTex, FloatTex};

#[derive(Debug)]
pub struct Matte {
    pub kd: ColorTex,
    pub sigma: FloatTex,
}

impl Matte {
    pub fn default_params() -> Matte {
        Matte {
            kd: ColorTex::constant(Rgb::splat(0.9)),
            sigma: FloatTex::constant(0.0),
        }
    }

    pub fn build(b: &mut Builder, e: &Entity) -> Result<Matte, MaterialError> {
        Ok(Matte {
            kd: b.textures.color_param(&e.params, "Kd", Rgb::splat(0.9))?,
            sigma: b.textures.float_param(&e.params, "sigma", 0.0)?,
        })
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        let r = self.kd.eval(si).map(|v| v.clamp(0.0, 1.0));
        let sigma = self.sigma.eval(si).clamp(0.0, 90.0);
        Lobes::Diffuse(if sigma == 0.0 {
            Diffuse::lambert(r)
        } else {
            Diffuse::oren_nayar(r, sigma)
        })
    }
}
