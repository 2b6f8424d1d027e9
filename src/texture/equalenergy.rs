//! `equalenergy` texture (colour): the same `energy` (default 1) at every wavelength, as a
//! light colour (LuxRender's `EqualSPD`).

use super::spectral::SpectralTex;
use super::{TexNode, TextureError, TextureSet};
use crate::lxs::TextureDesc;
use crate::spectrum::spd::Spd;

pub const DEFAULT_ENERGY: f32 = 1.0;

pub fn build(_set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let e = t.entity.params.float_or("energy", DEFAULT_ENERGY);
    if !e.is_finite() {
        return Err(TextureError::param(t, "energy", "energy must be finite"));
    }
    Ok(TexNode::Spectral(SpectralTex::illuminant(Spd::constant(e))))
}
