//! `glass`: smooth dielectric with `Kr` and `Kt` (default 1, clamped to [0, 1]), `index`
//! (float texture, default 1.5), `architectural` (default false; true: a thin sheet that light
//! crosses without bending, see [`super::bxdf::specular`]) and a thin film on the reflection
//! (`film` nm, default 0 = none; `filmindex` 1.5). Dispersion: `cauchyb` (float texture,
//! default 0) makes the index depend on the wavelength, n(λ) = index + cauchyb/λ² with λ in
//! µm (LuxRender's definition; the documentation's spelling `cauchyB` is accepted with a
//! warning); a scene with such a glass renders its paths through it with
//! one sampled wavelength ([`crate::integrator`]'s spectral note), others stay RGB.

use super::bsdf::Lobes;
use super::bxdf::specular::SpecularDielectric;
use super::mirror::FilmParams;
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::{param_loc, ColorTex, FloatTex};

/// How the scene format's documentation spells `cauchyb`.
pub const CAUCHYB_DOC_SPELLING: &str = "cauchyB";

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

/// Reads `cauchyb`: `None` when it is the constant 0 (no dispersion). The scene format's
/// page spells it `cauchyB`; LuxRender reads `cauchyb`: `cauchyB` is taken for it with a
/// located warning, and ignored (with a warning) when `cauchyb` is given too.
pub fn read_cauchyb(b: &mut Builder, e: &Entity) -> Result<Option<FloatTex>, MaterialError> {
    let p = &e.params;
    let name = if p.contains(CAUCHYB_DOC_SPELLING) {
        let loc = param_loc(p, CAUCHYB_DOC_SPELLING, &e.loc);
        if p.contains("cauchyb") {
            p.get(CAUCHYB_DOC_SPELLING);
            b.warn(
                &loc,
                format!(
                    "{} \"cauchyB\" is ignored: LuxRender reads \"cauchyb\", which is given too",
                    e.kind
                ),
            );
            "cauchyb"
        } else {
            b.warn(
                &loc,
                format!(
                    "{} \"cauchyB\" is read as \"cauchyb\" (LuxRender's spelling)",
                    e.kind
                ),
            );
            CAUCHYB_DOC_SPELLING
        }
    } else {
        "cauchyb"
    };
    let c = b.textures.float_param(p, name, 0.0)?;
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
