//! `lampspectrum` texture (colour): a measured lamp spectrum by `name` (LuxRender's presets,
//! [`crate::spectrum::lamp`]), as a light colour. As in LuxRender 1.x, `Candle`,
//! `Incandescent1` and `Incandescent2` are blackbodies (1020, 2750 and 2900 K), and so is any
//! other name (LuxRender's fallback, `Incandescent2`, its LuxBlend default): that case is
//! reported with a warning.

use super::spectral::SpectralTex;
use super::{blackbody, param_loc, TexNode, TextureError, TextureSet};
use crate::lxs::TextureDesc;
use crate::spectrum::lamp::{lamp_blackbody, lamp_spd};

pub const DEFAULT_NAME: &str = "Incandescent2";

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let p = &t.entity.params;
    let name = p.string_or("name", DEFAULT_NAME).to_string();
    if let Some(spd) = lamp_spd(&name) {
        return Ok(TexNode::Spectral(SpectralTex::illuminant(spd)));
    }
    let temp = match lamp_blackbody(&name) {
        Some(k) => k,
        None => {
            set.warn(
                &param_loc(p, "name", &t.entity.loc),
                format!(
                    "lampspectrum \"{name}\" is not a LuxRender lamp: using Incandescent2 \
                     (a 2900 K blackbody), as LuxRender does"
                ),
            );
            2900.0
        }
    };
    Ok(blackbody::node(temp))
}
