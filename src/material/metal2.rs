//! `metal2`: glossy reflection with LuxRender's general Fresnel term (see
//! [`super::bxdf::fresnel::FresnelGeneral`]) and its Schlick distribution. `fresnel` is a
//! fresnel texture (fresnelcolor, fresnelname, sopra, luxpop, cauchy, ... and their mixes),
//! evaluated at each hit; a constant (`"float fresnel" [v]`, default 5) is a dielectric of
//! index v, as LuxRender's constant fresnel texture. The texture's (n, k) picks the Fresnel
//! formula as LuxRender's `FresnelGeneral` does. `uroughness`/`vroughness` (default 0.1, as
//! LuxRender's sources; its scene-format page says 0.001).

use super::bsdf::Lobes;
use super::bxdf::fresnel::FresnelGeneral;
use super::bxdf::microfacet::{Fresnel, MicrofacetReflection};
use super::bxdf::schlick::SchlickDist;
use super::metal::roughness_pair;
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::{param_loc, FloatTex, FresnelTex};

/// LuxRender's default `fresnel` value.
pub const DEFAULT_FRESNEL: f32 = 5.0;

#[derive(Debug)]
pub struct Metal2 {
    pub fresnel: FresnelTex,
    pub u: FloatTex,
    pub v: FloatTex,
}

impl Metal2 {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<Metal2, MaterialError> {
        let p = &e.params;
        if let Some(v) = p.float("fresnel") {
            if !(v.is_finite() && v > 0.0) {
                return Err(MaterialError::BadParam {
                    loc: param_loc(p, "fresnel", &e.loc),
                    message: format!("metal2 \"fresnel\" must be a positive index, got {v}"),
                });
            }
        }
        let fresnel = b.textures.fresnel_param(p, "fresnel", DEFAULT_FRESNEL)?;
        let (u, v) = roughness_pair(b, e, 0.1)?;
        Ok(Metal2 { fresnel, u, v })
    }

    /// LuxRender's Fresnel term for the texture's optical constants at this hit.
    fn fresnel_at(&self, si: &SurfaceInteraction) -> FresnelGeneral {
        let f = self.fresnel.eval(si);
        FresnelGeneral::auto(f.n, f.k)
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        Lobes::Microfacet(MicrofacetReflection {
            scale: Rgb::WHITE,
            fresnel: Fresnel::General(self.fresnel_at(si)),
            dist: SchlickDist::unclamped(self.u.eval(si), self.v.eval(si)),
        })
    }
}
