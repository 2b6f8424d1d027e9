//! `fbm` texture (float): fractional Brownian motion of LuxRender's Perlin noise over a 3D
//! mapping: `octaves` (default 8) octaves, `roughness` (default 0.5) the weight ratio between
//! octaves ([`super::noise::fbm`]).

use super::mapping::Mapping3D;
use super::noise;
use super::{TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;

pub const DEFAULT_OCTAVES: i32 = 8;
pub const DEFAULT_ROUGHNESS: f32 = 0.5;
/// Most octaves honoured (each is 1.99 times finer: beyond this they are below float
/// resolution and cost time only).
pub const MAX_OCTAVES: i32 = 64;

#[derive(Debug)]
pub struct FbmTex {
    pub mapping: Mapping3D,
    pub octaves: i32,
    pub omega: f32,
}

impl FbmTex {
    pub fn value(&self, si: &SurfaceInteraction) -> f32 {
        noise::fbm(self.mapping.map(si), self.omega, self.octaves)
    }
}

/// `octaves` and `roughness` of the noise textures, checked.
pub fn octaves_roughness(t: &TextureDesc) -> Result<(i32, f32), TextureError> {
    let p = &t.entity.params;
    let octaves = p.int_or("octaves", DEFAULT_OCTAVES).clamp(0, MAX_OCTAVES);
    let omega = p.float_or("roughness", DEFAULT_ROUGHNESS);
    if !omega.is_finite() {
        return Err(TextureError::param(
            t,
            "roughness",
            "roughness must be finite",
        ));
    }
    Ok((octaves, omega))
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let (octaves, omega) = octaves_roughness(t)?;
    Ok(TexNode::Fbm(FbmTex {
        mapping: set.mapping3d(t),
        octaves,
        omega,
    }))
}
