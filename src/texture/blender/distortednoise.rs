//! `blender_distortednoise`: Blender's distorted noise (variable lacunarity noise): the `type`
//! basis (Blender's `noisebasis2`) sampled at a point displaced by `distamount` (1) times a
//! vector of `noisebasis` noise, the point scaled by 1/`noisesize` (0.25). This is the order of
//! LuxRender's code (`mg_VLNoise(…, noisebasis, noisebasis2)`), although the scene format
//! document describes `type` as the distorting pattern. `nabla` (0.025) is read, as in LuxRender (Blender
//! uses it for normals only).

use super::noiselib::{vl_noise, NoiseBasis};
use super::{BriCont, Params, TexResult};
use crate::texture::TextureError;

#[derive(Debug)]
pub struct DistortedNoise {
    /// `noisebasis`: the noise whose values displace the point.
    pub basis: NoiseBasis,
    /// `type`: the noise sampled at the displaced point.
    pub distorted: NoiseBasis,
    pub size: f32,
    pub amount: f32,
}

impl DistortedNoise {
    pub fn eval(&self, p: [f32; 3], bc: &BriCont) -> TexResult {
        let q = p.map(|c| c / self.size);
        let tin = vl_noise(q, self.amount, self.basis, self.distorted);
        TexResult::int(bc.int(tin))
    }
}

pub fn build(p: &mut Params) -> Result<DistortedNoise, TextureError> {
    let distorted = p.basis("type");
    let basis = p.basis("noisebasis");
    let _nabla = p.float("nabla", None, 0.025)?;
    Ok(DistortedNoise {
        basis,
        distorted,
        size: p.noise_size()?,
        amount: p.float("distamount", None, 1.0)?,
    })
}
