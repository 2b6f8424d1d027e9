//! `glass2`: LuxRender's "empty shell" for volumes. The surface is a smooth dielectric whose
//! relative index is the `fresnel` of the shape's Interior volume over that of its Exterior
//! volume (1 for a side without a volume): without an interior volume of another index the
//! shell is invisible. `architectural` (default false) lets light through without bending.
//! The volumes are bound per shape by [`super::MaterialSet::bind_media`], which reads each
//! side's `fresnel` (a float or a fresnel texture, [`crate::volume::read_fresnel`]).
//!
//! ```text
//! Interior/Exterior fresnel (FresnelTex) --Side--> RGB index (hit) --ratio--> lobe's eta
//!                                          \--> index at λ (hit) --ratio--> Dispersion
//! ```
//!
//! Index without dispersion: LuxRender divides the two volumes' indices averaged over the
//! sample's wavelengths (stratified over 380–720 nm), so its expected index is the mean over
//! 380–720 nm ([`crate::texture::FresnelData::mean_index`]); that mean is the RGB index here. A fresnel texture
//! that varies over the surface (a mix, fresnelcolor of a texture) is evaluated per hit and
//! its RGB reading's mean index used.
//!
//! `dispersion` (default false): when a side's index depends on the wavelength (cauchy with
//! b ≠ 0, sellmeier, fresnelname, sopra, luxpop, fresnelcolor, or a combination of them),
//! paths through the shell carry one wavelength λ and refract with the ratio of the indices at
//! λ ([`crate::texture::FresnelNode::index_at`]), as LuxRender's single-wavelength
//! transmission does; the scene then renders spectrally. With indices that do not depend on
//! the wavelength the flag has no effect (a located warning says so).

use super::bsdf::Lobes;
use super::bxdf::specular::SpecularDielectric;
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::{param_loc, Fresnel, FresnelTex};

/// One side's volume index.
#[derive(Debug)]
pub struct Side {
    tex: FresnelTex,
    /// The RGB index when it does not vary over the surface.
    fixed: Option<f32>,
    /// Whether the index depends on the wavelength.
    disperses: bool,
}

impl Side {
    /// A side of index `n` (no volume: 1).
    pub fn constant(n: f32) -> Side {
        Side::new(FresnelTex::constant(Fresnel::dielectric(n)))
    }

    pub fn new(tex: FresnelTex) -> Side {
        let fixed = match tex.data() {
            Some(d) => Some(d.mean_index()),
            None => tex.as_const().map(|f| f.index()),
        };
        let disperses = tex.0.disperses();
        Side {
            tex,
            fixed,
            disperses,
        }
    }

    /// The index without dispersion at a hit.
    pub fn index(&self, si: &SurfaceInteraction) -> f32 {
        self.fixed.unwrap_or_else(|| self.tex.eval(si).index())
    }

    /// The index at a hit at wavelength `nm`.
    fn at(&self, si: &SurfaceInteraction, nm: f32) -> f32 {
        if self.disperses {
            self.tex.0.index_at(si, nm)
        } else {
            self.index(si)
        }
    }
}

/// glass2's relative index at a hit as a function of the wavelength, and the index its lobes
/// were built with.
#[derive(Clone, Copy, Debug)]
pub struct SpectralEta<'a> {
    glass: &'a Glass2,
    si: &'a SurfaceInteraction,
    base: f32,
}

impl SpectralEta<'_> {
    /// How much the lobes' index must change at wavelength `nm`.
    pub fn shift(&self, nm: f32) -> f32 {
        let g = self.glass;
        ratio(g.interior.at(self.si, nm), g.exterior.at(self.si, nm)) - self.base
    }
}

/// Interior over exterior index, 1 when that is not a positive number.
fn ratio(interior: f32, exterior: f32) -> f32 {
    let eta = interior / exterior;
    if eta.is_finite() && eta > 0.0 {
        eta
    } else {
        1.0
    }
}

#[derive(Debug)]
pub struct Glass2 {
    pub architectural: bool,
    pub interior: Side,
    pub exterior: Side,
    /// `dispersion` is on and a side's index depends on the wavelength.
    pub disperses: bool,
}

impl Glass2 {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<Glass2, MaterialError> {
        let p = &e.params;
        let (interior, exterior) = match b.media.clone() {
            Some(m) => (Side::new(m.interior), Side::new(m.exterior)),
            None => (Side::constant(1.0), Side::constant(1.0)),
        };
        let dispersion = p.bool_or("dispersion", false);
        let disperses = dispersion && (interior.disperses || exterior.disperses);
        // The copy built without volumes is never rendered by a shape with volumes: only the
        // copies bound to volumes report on the flag.
        if dispersion && !disperses && b.media.is_some() {
            let loc = param_loc(p, "dispersion", &e.loc);
            b.warn(
                &loc,
                "glass2 \"dispersion\" has no effect: the indices of the shape's volumes do not \
                 depend on the wavelength (give a volume a cauchy or sellmeier fresnel texture)"
                    .into(),
            );
        }
        Ok(Glass2 {
            architectural: p.bool_or("architectural", false),
            interior,
            exterior,
            disperses,
        })
    }

    /// The relative index without dispersion at a hit.
    pub fn eta(&self, si: &SurfaceInteraction) -> f32 {
        ratio(self.interior.index(si), self.exterior.index(si))
    }

    /// The relative index as a function of the wavelength, when the shell disperses.
    pub fn spectral_eta<'a>(&'a self, si: &'a SurfaceInteraction) -> Option<SpectralEta<'a>> {
        self.disperses.then(|| SpectralEta {
            glass: self,
            si,
            base: self.eta(si),
        })
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        Lobes::Dielectric(SpecularDielectric {
            kr: Rgb::WHITE,
            kt: Rgb::WHITE,
            eta: self.eta(si),
            architectural: self.architectural,
            film: None,
        })
    }
}
