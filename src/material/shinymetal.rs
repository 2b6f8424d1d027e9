//! `shinymetal`: a glossy conductor lobe whose Fresnel term reflects `Ks` at normal incidence
//! plus a mirror lobe reflecting `Kr` (both default 1, clamped; conductor indices from
//! LuxRender's `FresnelApproxEta`/`FresnelApproxK`), `uroughness`/`vroughness` default 0.1.
//! Thin-film parameters are not modelled.

use super::bsdf::Lobes;
use super::bxdf::avg;
use super::bxdf::fresnel::approx_conductor;
use super::bxdf::microfacet::{Blinn, MicrofacetReflection};
use super::bxdf::specular::SpecularReflection;
use super::metal::roughness_pair;
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::{ColorTex, FloatTex};

#[derive(Debug)]
pub struct ShinyMetal {
    pub kr: ColorTex,
    pub ks: ColorTex,
    pub u: FloatTex,
    pub v: FloatTex,
}

impl ShinyMetal {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<ShinyMetal, MaterialError> {
        let (u, v) = roughness_pair(b, e, 0.1)?;
        Ok(ShinyMetal {
            kr: b.textures.color_param(&e.params, "Kr", Rgb::WHITE)?,
            ks: b.textures.color_param(&e.params, "Ks", Rgb::WHITE)?,
            u,
            v,
        })
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        let clamp = |c: Rgb| c.map(|v| v.clamp(0.0, 1.0));
        let (ks, kr) = (clamp(self.ks.eval(si)), clamp(self.kr.eval(si)));
        let (sn, sk) = approx_conductor(ks);
        let (rn, rk) = approx_conductor(kr);
        let glossy = MicrofacetReflection {
            scale: Rgb::WHITE,
            n: sn,
            k: sk,
            dist: Blinn::from_uv(self.u.eval(si), self.v.eval(si)),
        };
        let mirror = SpecularReflection {
            kr: Rgb::WHITE,
            conductor: Some((rn, rk)),
        };
        let (wm, wg) = (avg(kr), avg(ks));
        let p_mirror = if wm + wg > 0.0 { wm / (wm + wg) } else { 0.5 };
        Lobes::GlossyMirror {
            glossy,
            mirror,
            p_mirror,
        }
    }
}
