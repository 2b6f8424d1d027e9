//! `marble` texture (colour): LuxRender's marble over a 3D mapping. With P the mapped point
//! times `scale` (default 1), t = ½ + ½·sin(P.y + `variation` (default 0.2) · FBm(P,
//! `roughness` 0.5, `octaves` 8)) picks a colour on a cubic Bézier spline through LuxRender's
//! nine marble colours (de Casteljau on the segment ⌊6t⌋), scaled by 1.5.

use super::fbm::octaves_roughness;
use super::mapping::Mapping3D;
use super::noise;
use super::{TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;
use crate::spectrum::Rgb;

pub const DEFAULT_SCALE: f32 = 1.0;
pub const DEFAULT_VARIATION: f32 = 0.2;

/// LuxRender's marble colours.
const COLORS: [[f32; 3]; 9] = [
    [0.58, 0.58, 0.6],
    [0.58, 0.58, 0.6],
    [0.58, 0.58, 0.6],
    [0.5, 0.5, 0.5],
    [0.6, 0.59, 0.58],
    [0.58, 0.58, 0.6],
    [0.58, 0.58, 0.6],
    [0.2, 0.2, 0.33],
    [0.58, 0.58, 0.6],
];

#[derive(Debug)]
pub struct MarbleTex {
    pub mapping: Mapping3D,
    pub octaves: i32,
    pub omega: f32,
    pub scale: f32,
    pub variation: f32,
}

fn lerp(t: f32, a: Rgb, b: Rgb) -> Rgb {
    a * (1.0 - t) + b * t
}

/// The marble colour at spline parameter `t` in [0, 1].
pub fn spline(t: f32) -> Rgb {
    let nseg = (COLORS.len() - 3) as f32;
    let first = ((t * nseg).floor().max(0.0) as usize).min(COLORS.len() - 4);
    let t = t * nseg - first as f32;
    let c = |i: usize| Rgb::from_array(COLORS[first + i]);
    let (c0, c1, c2, c3) = (c(0), c(1), c(2), c(3));
    let s0 = lerp(t, c0, c1);
    let s1 = lerp(t, c1, c2);
    let s2 = lerp(t, c2, c3);
    let s0 = lerp(t, s0, s1);
    let s1 = lerp(t, s1, s2);
    lerp(t, s0, s1) * 1.5
}

impl MarbleTex {
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        let p = self.mapping.map(si) * self.scale;
        let marble = p.y + self.variation * noise::fbm(p, self.omega, self.octaves);
        spline(0.5 + 0.5 * marble.sin())
    }
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let (octaves, omega) = octaves_roughness(t)?;
    let p = &t.entity.params;
    let scale = p.float_or("scale", DEFAULT_SCALE);
    let variation = p.float_or("variation", DEFAULT_VARIATION);
    if !(scale.is_finite() && variation.is_finite()) {
        return Err(TextureError::param(
            t,
            "scale",
            "scale and variation must be finite",
        ));
    }
    Ok(TexNode::Marble(MarbleTex {
        mapping: set.mapping3d(t),
        octaves,
        omega,
        scale,
        variation,
    }))
}
