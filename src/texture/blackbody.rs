//! `blackbody` texture (colour): LuxRender's normalised blackbody spectrum at `temperature`
//! kelvin (default 6500), as a light colour ([`crate::spectrum::blackbody`]).

use super::spectral::SpectralTex;
use super::{TexNode, TextureError, TextureSet};
use crate::lxs::TextureDesc;
use crate::spectrum::blackbody;
use crate::spectrum::spd::Spd;
use std::sync::Arc;

pub const DEFAULT_TEMPERATURE: f32 = 6500.0;

pub fn build(_set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let temp = t.entity.params.float_or("temperature", DEFAULT_TEMPERATURE);
    if !(temp.is_finite() && temp > 0.0) {
        return Err(TextureError::param(
            t,
            "temperature",
            format!("blackbody temperature must be positive, got {temp}"),
        ));
    }
    Ok(node(temp))
}

/// The blackbody node at `temp` kelvin (also what `lampspectrum` gives for its incandescent
/// presets).
pub fn node(temp: f32) -> TexNode {
    TexNode::Spectral(SpectralTex {
        spd: Arc::new(Spd::blackbody(temp)),
        rgb: blackbody(temp),
    })
}
