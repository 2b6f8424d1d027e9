//! `constant` texture: `value` (a float for float textures; a colour, or a grey float, for
//! colour textures), default 1.

use super::{TexNode, TextureError, TextureSet};
use crate::lxs::{TextureDesc, TextureType};
use crate::spectrum::Rgb;

pub fn build(_set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let p = &t.entity.params;
    let v = match t.value_type {
        TextureType::Color => p
            .color("value")
            .map(Rgb::from_array)
            .or_else(|| p.float("value").map(Rgb::splat)),
        TextureType::Float => p.float("value").map(Rgb::splat),
    };
    Ok(TexNode::Const(v.unwrap_or(Rgb::WHITE)))
}
