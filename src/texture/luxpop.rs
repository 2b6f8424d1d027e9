//! `luxpop` texture (fresnel, deprecated in LuxRender 1.0 for `fresnelname`): n and k from a
//! luxpop `.nk` file (`filename`: lines of wavelength in Ångström, n, k; `;` comments). An
//! unreadable file is a located error.

use super::fresnel::{read_data_file, FresnelData};
use super::{FresnelNode, TextureError, TextureSet};
use crate::lxs::TextureDesc;
use crate::spectrum::nk::NkTable;

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<FresnelNode, TextureError> {
    let (text, path) = read_data_file(set, t, "filename")?;
    let table = NkTable::parse_luxpop(&text).map_err(|message| TextureError::Image {
        loc: super::param_loc(&t.entity.params, "filename", &t.entity.loc),
        path,
        message: format!("not a luxpop nk file: {message}"),
    })?;
    Ok(FresnelNode::data(FresnelData::Table(table)))
}
