//! `fresnelname` texture (fresnel): optical constants by file or by name, in LuxRender's order:
//! `filename` read as a SOPRA file, else as a luxpop file; else the preset `name` (`amorphous
//! carbon`, `silver`, `gold`, `copper`, `aluminium`, the default); else aluminium, with a
//! warning (LuxRender's fallback).

use super::fresnel::{read_data_file, FresnelData};
use super::{param_loc, FresnelNode, TextureError, TextureSet};
use crate::lxs::TextureDesc;
use crate::spectrum::nk::NkTable;

pub const DEFAULT_NAME: &str = "aluminium";

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<FresnelNode, TextureError> {
    let p = &t.entity.params;
    if p.string("filename").is_some_and(|f| !f.is_empty()) {
        match read_data_file(set, t, "filename") {
            Ok((text, path)) => match NkTable::parse(&text) {
                Ok(table) => return Ok(FresnelNode::data(FresnelData::Table(table))),
                Err(e) => set.warn(
                    &param_loc(p, "filename", &t.entity.loc),
                    format!("{path} is neither a SOPRA nor a luxpop nk file ({e}): using the preset name"),
                ),
            },
            Err(e) => {
                let msg = e.to_string();
                set.warn(
                    &param_loc(p, "filename", &t.entity.loc),
                    format!("{msg}: using the preset name"),
                );
            }
        }
    }
    let name = p.string_or("name", DEFAULT_NAME).to_string();
    let table = match NkTable::preset(&name) {
        Some(t) => t,
        None => {
            set.warn(
                &param_loc(p, "name", &t.entity.loc),
                format!(
                    "fresnelname \"{name}\" is not a preset: using aluminium, as LuxRender does"
                ),
            );
            NkTable::preset(DEFAULT_NAME).unwrap_or(NkTable {
                wl: vec![550.0],
                n: vec![1.0],
                k: vec![0.0],
            })
        }
    };
    Ok(FresnelNode::data(FresnelData::Table(table)))
}
