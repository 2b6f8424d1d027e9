//! `glass`: smooth dielectric with `Kr` and `Kt` (default 1, clamped to [0, 1]), `index`
//! (float texture, default 1.5), `architectural` (default false; true: a thin sheet that light
//! crosses without bending, see [`super::bxdf::specular`]) and a thin film on the reflection
//! (`film` nm, default 0 = none; `filmindex` 1.5). Dispersion (`cauchyb` ≠ 0) needs spectral
//! rendering, which is not built: a located warning is given and it is ignored.

use super::bsdf::Lobes;
use super::bxdf::specular::SpecularDielectric;
use super::mirror::FilmParams;
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::{param_loc, ColorTex, FloatTex};

#[derive(Debug)]
pub struct Glass {
    pub kr: ColorTex,
    pub kt: ColorTex,
    pub index: FloatTex,
    pub architectural: bool,
    pub film: FilmParams,
}

/// Reads `cauchyb` and warns when it asks for dispersion.
pub fn check_dispersion(b: &mut Builder, e: &Entity) -> Result<(), MaterialError> {
    let c = b.textures.float_param(&e.params, "cauchyb", 0.0)?;
    if c.as_const() != Some(0.0) {
        let loc = param_loc(&e.params, "cauchyb", &e.loc);
        b.warn(
            &loc,
            "dispersion (cauchyb) needs spectral rendering, which is not built: ignored".into(),
        );
    }
    Ok(())
}

impl Glass {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<Glass, MaterialError> {
        let p = &e.params;
        check_dispersion(b, e)?;
        Ok(Glass {
            kr: b.textures.color_param(p, "Kr", Rgb::WHITE)?,
            kt: b.textures.color_param(p, "Kt", Rgb::WHITE)?,
            index: b.textures.float_param(p, "index", 1.5)?,
            architectural: p.bool_or("architectural", false),
            film: FilmParams::read(b, e)?,
        })
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        let clamp = |c: Rgb| c.map(|v| v.clamp(0.0, 1.0));
        let eta = self.index.eval(si);
        Lobes::Dielectric(SpecularDielectric {
            kr: clamp(self.kr.eval(si)),
            kt: clamp(self.kt.eval(si)),
            eta: if eta > 0.0 { eta } else { 1.0 },
            architectural: self.architectural,
            film: self.film.eval(si),
        })
    }
}
