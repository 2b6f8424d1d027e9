//! The node of colour textures defined by a spectrum (`blackbody`, `equalenergy`, `gaussian`,
//! `lampspectrum`, `tabulateddata`): the spectrum, kept for spectral rendering, and the RGB the
//! renderer uses, converted once at build time.

use crate::spectrum::spd::Spd;
use crate::spectrum::Rgb;
use std::sync::Arc;

#[derive(Debug)]
pub struct SpectralTex {
    pub spd: Arc<Spd>,
    pub rgb: Rgb,
}

impl SpectralTex {
    /// A light spectrum (emission): the RGB whose film XYZ is the spectrum's.
    pub fn illuminant(spd: Spd) -> SpectralTex {
        SpectralTex {
            rgb: spd.illuminant_rgb(),
            spd: Arc::new(spd),
        }
    }

    /// A reflectance (or transmittance) spectrum: the RGB it has under the white light.
    pub fn reflectance(spd: Spd) -> SpectralTex {
        SpectralTex {
            rgb: spd.reflectance_rgb(),
            spd: Arc::new(spd),
        }
    }
}
