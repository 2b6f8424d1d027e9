//! `shinymetal`: glossy reflection whose Fresnel term reflects `Ks` at normal incidence plus a
//! mirror reflection whose Fresnel term reflects `Kr` (both default 1, clamped), each an
//! interface of LuxRender's approximate index for that colour (`FresnelApproxEta`/`K`, with
//! the general Fresnel model); `uroughness`/`vroughness` (default 0.1) of LuxRender 1.x's
//! Schlick distribution; `film` (thin-film thickness in nm, default 0 = none) and
//! `filmindex` (1.5) on the mirror part.

use super::bsdf::Lobes;
use super::bxdf::avg;
use super::bxdf::fresnel::{approx_conductor, FresnelGeneral};
use super::bxdf::microfacet::{Fresnel, MicrofacetReflection};
use super::bxdf::schlick::SchlickDist;
use super::bxdf::specular::SpecularReflection;
use super::metal::roughness_pair;
use super::mirror::FilmParams;
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
    pub film: FilmParams,
}

impl ShinyMetal {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<ShinyMetal, MaterialError> {
        let (u, v) = roughness_pair(b, e, 0.1)?;
        Ok(ShinyMetal {
            kr: b.textures.color_param(&e.params, "Kr", Rgb::WHITE)?,
            ks: b.textures.color_param(&e.params, "Ks", Rgb::WHITE)?,
            u,
            v,
            film: FilmParams::read(b, e)?,
        })
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        let clamp = |c: Rgb| c.map(|v| v.clamp(0.0, 1.0));
        let (ks, kr) = (clamp(self.ks.eval(si)), clamp(self.kr.eval(si)));
        let general = |c: Rgb| {
            let (n, k) = approx_conductor(c);
            FresnelGeneral::auto(n, k)
        };
        let glossy = MicrofacetReflection {
            scale: Rgb::WHITE,
            fresnel: Fresnel::General(general(ks)),
            dist: SchlickDist::unclamped(self.u.eval(si), self.v.eval(si)),
        };
        let mirror = SpecularReflection {
            kr: Rgb::WHITE,
            fresnel: Some(general(kr)),
            film: self.film.eval(si),
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
