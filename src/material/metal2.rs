//! `metal2`: glossy reflection with LuxRender's general Fresnel term (see
//! [`super::bxdf::fresnel::FresnelGeneral`]) and its Schlick distribution. `fresnel` is a
//! fresnel texture input; a constant (`"float fresnel" [v]`, default 5) is a dielectric of
//! index v, as LuxRender's constant fresnel texture. `uroughness`/`vroughness` (default 0.1,
//! as LuxRender's sources; its scene-format page says 0.001).
//!
//! Fresnel textures (fresnelcolor, fresnelname, ...) are the texture module's; until it
//! provides them a `"texture fresnel"` reference falls back to the default with a located
//! warning.

use super::bsdf::Lobes;
use super::bxdf::fresnel::FresnelGeneral;
use super::bxdf::microfacet::{Fresnel, MicrofacetReflection};
use super::bxdf::schlick::SchlickDist;
use super::metal::roughness_pair;
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::{param_loc, FloatTex};

/// LuxRender's default `fresnel` value.
pub const DEFAULT_FRESNEL: f32 = 5.0;

#[derive(Debug)]
pub struct Metal2 {
    pub fresnel: FresnelGeneral,
    pub u: FloatTex,
    pub v: FloatTex,
}

impl Metal2 {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<Metal2, MaterialError> {
        let p = &e.params;
        let value = match p.float("fresnel") {
            Some(v) if v.is_finite() && v > 0.0 => v,
            Some(v) => {
                return Err(MaterialError::BadParam {
                    loc: param_loc(p, "fresnel", &e.loc),
                    message: format!("metal2 \"fresnel\" must be a positive index, got {v}"),
                })
            }
            None => {
                if let Some(name) = p.texture("fresnel") {
                    let loc = param_loc(p, "fresnel", &e.loc);
                    b.warn(
                        &loc,
                        format!(
                            "metal2: fresnel texture \"{name}\" is not available yet: using \
                             the constant {DEFAULT_FRESNEL}"
                        ),
                    );
                }
                DEFAULT_FRESNEL
            }
        };
        let (u, v) = roughness_pair(b, e, 0.1)?;
        Ok(Metal2 {
            fresnel: FresnelGeneral::dielectric(value),
            u,
            v,
        })
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        Lobes::Microfacet(MicrofacetReflection {
            scale: Rgb::WHITE,
            fresnel: Fresnel::General(self.fresnel),
            dist: SchlickDist::unclamped(self.u.eval(si), self.v.eval(si)),
        })
    }
}
