//! `gaussian` texture (colour): `energy · exp(−(λ − wavelength)² / (2 width²))` (defaults 1,
//! 550 nm, 50 nm), sampled over 380–720 nm and clamped at zero as LuxRender's `GaussianSPD`,
//! as a light colour.

use super::spectral::SpectralTex;
use super::{TexNode, TextureError, TextureSet};
use crate::lxs::TextureDesc;
use crate::spectrum::spd::Spd;

pub const DEFAULT_ENERGY: f32 = 1.0;
pub const DEFAULT_WAVELENGTH: f32 = 550.0;
pub const DEFAULT_WIDTH: f32 = 50.0;

/// The sampled curve (1 nm steps).
pub fn spd(energy: f32, mean: f32, width: f32) -> Spd {
    let scale2 = -0.5 / (width * width);
    Spd::from_fn(380.0, 720.0, 1.0, |w| {
        let x = w - mean;
        (energy * (x * x * scale2).exp()).max(0.0)
    })
}

pub fn build(_set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let p = &t.entity.params;
    let energy = p.float_or("energy", DEFAULT_ENERGY);
    let mean = p.float_or("wavelength", DEFAULT_WAVELENGTH);
    let width = p.float_or("width", DEFAULT_WIDTH);
    if !(width.is_finite() && width > 0.0) {
        return Err(TextureError::param(
            t,
            "width",
            format!("gaussian width must be positive, got {width}"),
        ));
    }
    if !(energy.is_finite() && mean.is_finite()) {
        return Err(TextureError::param(
            t,
            "energy",
            "energy and wavelength must be finite",
        ));
    }
    Ok(TexNode::Spectral(SpectralTex::illuminant(spd(
        energy, mean, width,
    ))))
}
