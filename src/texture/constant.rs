//! `constant` texture: `value`, a float for float textures (default 1), a colour (or a grey
//! float) for colour textures (default white), an index of refraction for fresnel textures
//! (a dielectric, default 1).

use super::{Fresnel, FresnelNode, TexNode, TextureError, TextureSet};
use crate::lxs::{TextureDesc, TextureType};
use crate::spectrum::Rgb;

pub const DEFAULT_VALUE: f32 = 1.0;

pub fn build(_set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let p = &t.entity.params;
    let v = match t.value_type {
        TextureType::Color => p
            .color("value")
            .map(Rgb::from_array)
            .or_else(|| p.float("value").map(Rgb::splat)),
        _ => p.float("value").map(Rgb::splat),
    };
    Ok(TexNode::Const(v.unwrap_or(Rgb::splat(DEFAULT_VALUE))))
}

pub fn build_fresnel(_set: &mut TextureSet, t: &TextureDesc) -> Result<FresnelNode, TextureError> {
    let v = t.entity.params.float_or("value", DEFAULT_VALUE);
    Ok(FresnelNode::Const(Fresnel::dielectric(v)))
}
