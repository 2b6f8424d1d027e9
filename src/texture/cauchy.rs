//! `cauchy` texture (fresnel): a dispersive dielectric by Cauchy's law n(λ) = a + b/λ² (λ in
//! µm). Parameters as LuxRender's: `cauchyb` (default 0) and `cauchya`, whose default is
//! `index − b/(0.38·0.72)` when `index` is given (so that the index is met at the band's
//! geometric middle) and 1.5 otherwise.

use super::fresnel::FresnelData;
use super::{FresnelNode, TextureError, TextureSet};
use crate::lxs::TextureDesc;

pub const DEFAULT_A: f32 = 1.5;

pub fn build(_set: &mut TextureSet, t: &TextureDesc) -> Result<FresnelNode, TextureError> {
    let p = &t.entity.params;
    let b = p.float_or("cauchyb", 0.0);
    let index = p.float_or("index", -1.0);
    let a = if index > 0.0 {
        p.float_or("cauchya", index - b * 1e6 / (720.0 * 380.0))
    } else {
        p.float_or("cauchya", DEFAULT_A)
    };
    if !(a.is_finite() && b.is_finite()) {
        return Err(TextureError::param(
            t,
            "cauchya",
            "cauchya and cauchyb must be finite",
        ));
    }
    Ok(FresnelNode::data(FresnelData::Cauchy { a, b }))
}
