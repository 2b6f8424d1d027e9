//! `blackbody` texture: the colour of LuxRender's normalised blackbody spectrum at
//! `temperature` kelvin (default 6500), see [`crate::spectrum::blackbody`].

use super::{param_loc, TexNode, TextureError, TextureSet};
use crate::lxs::TextureDesc;
use crate::spectrum::blackbody;

pub fn build(_set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let p = &t.entity.params;
    let temp = p.float_or("temperature", 6500.0);
    if !(temp.is_finite() && temp > 0.0) {
        return Err(TextureError::BadParam {
            loc: param_loc(p, "temperature", &t.entity.loc),
            message: format!("blackbody temperature must be positive, got {temp}"),
        });
    }
    Ok(TexNode::Const(blackbody(temp)))
}
