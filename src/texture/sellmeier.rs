//! `sellmeier` texture (fresnel): a dispersive dielectric by Sellmeier's law
//! n² = A + Σ Bᵢ λ² / (λ² − Cᵢ) (λ in µm, Cᵢ in µm²): `A` (default 1) and the lists `B` and `C`,
//! which must be as long as each other (LuxRender refuses the texture otherwise).

use super::fresnel::FresnelData;
use super::{FresnelNode, TextureError, TextureSet};
use crate::lxs::TextureDesc;

pub fn build(_set: &mut TextureSet, t: &TextureDesc) -> Result<FresnelNode, TextureError> {
    let p = &t.entity.params;
    let a = p.float_or("A", 1.0);
    let b = p.floats("B").unwrap_or(&[]).to_vec();
    let c = p.floats("C").unwrap_or(&[]).to_vec();
    if b.len() != c.len() {
        return Err(TextureError::param(
            t,
            "B",
            format!(
                "sellmeier: {} B coefficients for {} C coefficients",
                b.len(),
                c.len()
            ),
        ));
    }
    if !a.is_finite() || b.iter().chain(&c).any(|x| !x.is_finite()) {
        return Err(TextureError::param(
            t,
            "A",
            "sellmeier coefficients must be finite",
        ));
    }
    Ok(FresnelNode::data(FresnelData::Sellmeier { a, b, c }))
}
