//! `roughglass`: rough dielectric with `Kr`, `Kt` (default 1), `index` (1.5), `uroughness`
//! and `vroughness` (0.001, clamped to [6e-3, 1] as LuxRender 1.x does, Schlick distribution;
//! unequal u/v roughness is anisotropic). Dispersion through `cauchyb` as [`super::glass`]'s;
//! a `dispersion` flag is not read (a located warning says so).

use super::bsdf::Lobes;
use super::bxdf::rough_dielectric::RoughDielectric;
use super::bxdf::schlick::SchlickDist;
use super::glass::read_cauchyb;
use super::metal::roughness_pair;
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::{param_loc, ColorTex, FloatTex};

#[derive(Debug)]
pub struct RoughGlass {
    pub kr: ColorTex,
    pub kt: ColorTex,
    pub index: FloatTex,
    pub u: FloatTex,
    pub v: FloatTex,
    /// `cauchyb`, when not the constant 0 (see [`super::glass`]).
    pub cauchyb: Option<FloatTex>,
}

impl RoughGlass {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<RoughGlass, MaterialError> {
        let p = &e.params;
        let cauchyb = read_cauchyb(b, e)?;
        if p.bool_or("dispersion", false) {
            let loc = param_loc(p, "dispersion", &e.loc);
            b.warn(
                &loc,
                "roughglass disperses through cauchyb; the dispersion flag is ignored".into(),
            );
        }
        let (u, v) = roughness_pair(b, e, 0.001)?;
        Ok(RoughGlass {
            cauchyb,
            kr: b.textures.color_param(p, "Kr", Rgb::WHITE)?,
            kt: b.textures.color_param(p, "Kt", Rgb::WHITE)?,
            index: b.textures.float_param(p, "index", 1.5)?,
            u,
            v,
        })
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        let clamp = |c: Rgb| c.map(|v| v.clamp(0.0, 1.0));
        let eta = self.index.eval(si);
        Lobes::RoughDielectric(RoughDielectric {
            kr: clamp(self.kr.eval(si)),
            kt: clamp(self.kt.eval(si)),
            eta: if eta > 0.0 { eta } else { 1.0 },
            dist: SchlickDist::from_uv(self.u.eval(si), self.v.eval(si)),
        })
    }
}
