//! `glass2`: LuxRender's "empty shell" for volumes. The surface is a smooth dielectric whose
//! relative index is the `fresnel` index of the shape's Interior volume over that of its
//! Exterior volume (1 for a side without a volume): without an interior volume of another
//! index the shell is invisible. `architectural` (default false) lets light through without
//! bending; `dispersion` (default false) needs spectral rendering and is ignored with a
//! located warning. The volumes' absorption and scattering are the media issue's: the scene
//! build reports every Interior/Exterior it does not render. The index is bound per shape by
//! [`super::MaterialSet::bind_media`].

use super::bsdf::Lobes;
use super::bxdf::specular::SpecularDielectric;
use super::{Builder, MaterialError};
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::param_loc;

#[derive(Debug)]
pub struct Glass2 {
    pub architectural: bool,
    /// Interior index over exterior index.
    pub eta: f32,
}

impl Glass2 {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<Glass2, MaterialError> {
        let p = &e.params;
        if p.bool_or("dispersion", false) {
            let loc = param_loc(p, "dispersion", &e.loc);
            b.warn(
                &loc,
                "glass2 dispersion needs spectral rendering, which is not built: ignored".into(),
            );
        }
        let eta = match b.media {
            Some(m) if m.exterior > 0.0 => m.interior / m.exterior,
            _ => 1.0,
        };
        Ok(Glass2 {
            architectural: p.bool_or("architectural", false),
            eta: if eta.is_finite() && eta > 0.0 {
                eta
            } else {
                1.0
            },
        })
    }

    pub fn lobes(&self) -> Lobes {
        Lobes::Dielectric(SpecularDielectric {
            kr: Rgb::WHITE,
            kt: Rgb::WHITE,
            eta: self.eta,
            architectural: self.architectural,
            film: None,
        })
    }
}
