//! `wrinkled` texture (float): turbulence (the fractal sum of |noise|) of LuxRender's Perlin
//! noise over a 3D mapping: `octaves` (default 8), `roughness` (default 0.5).

use super::fbm::octaves_roughness;
use super::mapping::Mapping3D;
use super::noise;
use super::{TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;

#[derive(Debug)]
pub struct WrinkledTex {
    pub mapping: Mapping3D,
    pub octaves: i32,
    pub omega: f32,
}

impl WrinkledTex {
    pub fn value(&self, si: &SurfaceInteraction) -> f32 {
        noise::turbulence(self.mapping.map(si), self.omega, self.octaves)
    }
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let (octaves, omega) = octaves_roughness(t)?;
    Ok(TexNode::Wrinkled(WrinkledTex {
        mapping: set.mapping3d(t),
        octaves,
        omega,
    }))
}
