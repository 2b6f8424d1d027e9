//! `windy` texture (float): LuxRender's wave pattern, |FBm(0.1·P, ω 0.5, 3 octaves)| (the wind
//! strength) times FBm(P, ω 0.5, 6 octaves) (the wave height) over a 3D mapping. No parameters
//! beyond the mapping's.

use super::mapping::Mapping3D;
use super::noise;
use super::{TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;

#[derive(Debug)]
pub struct WindyTex {
    pub mapping: Mapping3D,
}

/// The windy pattern at texture-space point `p`.
pub fn windy(p: glam::Vec3A) -> f32 {
    let wind = noise::fbm(0.1 * p, 0.5, 3);
    let wave = noise::fbm(p, 0.5, 6);
    wind.abs() * wave
}

impl WindyTex {
    pub fn value(&self, si: &SurfaceInteraction) -> f32 {
        windy(self.mapping.map(si))
    }
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    Ok(TexNode::Windy(WindyTex {
        mapping: set.mapping3d(t),
    }))
}
