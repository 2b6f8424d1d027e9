//! `glass`: smooth dielectric with `Kr` and `Kt` (default 1, clamped to [0, 1]), `index`
//! (float texture, default 1.5), `architectural` (default false; true: a thin sheet that light
//! crosses without bending, see [`super::bxdf::specular`]) and a thin film on the reflection
//! (`film` nm, default 0 = none; `filmindex` 1.5). Dispersion: `cauchyb` (float texture,
//! default 0) makes the index depend on the wavelength, n(λ) = index + cauchyb/λ² with λ in
//! µm (LuxRender's definition); a scene with such a glass renders its paths through it with
//! one sampled wavelength ([`crate::integrator`]'s spectral note), others stay RGB.

use super::bsdf::Lobes;
use super::bxdf::specular::SpecularDielectric;
use super::mirror::FilmParams;
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::{ColorTex, FloatTex};

#[derive(Debug)]
pub struct Glass {
    pub kr: ColorTex,
    pub kt: ColorTex,
    pub index: FloatTex,
    pub architectural: bool,
    pub film: FilmParams,
    /// `cauchyb`, when not the constant 0.
    pub cauchyb: Option<FloatTex>,
}

/// Reads `cauchyb`: `None` when it is the constant 0 (no dispersion).
pub fn read_cauchyb(b: &mut Builder, e: &Entity) -> Result<Option<FloatTex>, MaterialError> {
    let c = b.textures.float_param(&e.params, "cauchyb", 0.0)?;
    Ok((c.as_const() != Some(0.0)).then_some(c))
}

/// The index shift cauchyb/λ² at wavelength `nm` (λ in µm in Cauchy's formula).
pub fn cauchy_shift(cauchyb: f32, nm: f32) -> f32 {
    let um = nm * 1e-3;
    let d = cauchyb / (um * um);
    if d.is_finite() {
        d
    } else {
        0.0
    }
}

impl Glass {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<Glass, MaterialError> {
        let p = &e.params;
        let cauchyb = read_cauchyb(b, e)?;
        Ok(Glass {
            cauchyb,
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
