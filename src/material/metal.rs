//! `metal`: a glossy conductor (LuxRender 1.x: microfacet reflection with its Schlick
//! distribution of roughness u·v, anisotropic when they differ, and the conductor Fresnel
//! term). `filename` (or the older `name`) is a preset (`amorphous carbon`, `silver`, `gold`,
//! `copper`, `aluminium`, the default) or an `.nk` file (relative to the scene directory;
//! LuxRender tries the file first). Unknown names fall back to aluminium with a warning, as
//! in LuxRender. The RGB n, k are those that reflect the table's spectral colour (see
//! [`NkTable::to_rgb`]). `uroughness`/`vroughness` default 0.1; the 0.x `roughness` is
//! accepted when neither is given.

use super::bsdf::Lobes;
use super::bxdf::microfacet::{Fresnel, MicrofacetReflection};
use super::bxdf::schlick::SchlickDist;
use super::{Builder, MaterialError};
use crate::fileio::FileError;
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::nk::NkTable;
use crate::spectrum::Rgb;
use crate::texture::{param_loc, FloatTex};

#[derive(Debug)]
pub struct Metal {
    pub n: Rgb,
    pub k: Rgb,
    pub u: FloatTex,
    pub v: FloatTex,
}

/// `uroughness`/`vroughness`. Scenes written for LuxRender 0.x give a single `roughness`: it is
/// used for both when neither of the two newer parameters is present.
pub fn roughness_pair(
    b: &mut Builder,
    e: &Entity,
    default: f32,
) -> Result<(FloatTex, FloatTex), MaterialError> {
    let p = &e.params;
    if p.contains("roughness") && !p.contains("uroughness") && !p.contains("vroughness") {
        let r = b.textures.float_param(p, "roughness", default)?;
        return Ok((r.clone(), r));
    }
    let u = b.textures.float_param(&e.params, "uroughness", default)?;
    let v = b.textures.float_param(&e.params, "vroughness", default)?;
    Ok((u, v))
}

fn load_nk(b: &mut Builder, e: &Entity, name: &str) -> NkTable {
    let key = if e.params.contains("filename") {
        "filename"
    } else {
        "name"
    };
    // A preset name is not a file name; anything else is looked up as a file first (through
    // the scene's confined file access), as LuxRender does.
    let loc = param_loc(&e.params, key, &e.loc);
    match b.ctx.files.read_to_string(name) {
        Ok(text) => match NkTable::parse(&text) {
            Ok(t) => return t,
            Err(err) => b.warn(&loc, format!("nk file \"{name}\": {err}; using aluminium")),
        },
        Err(FileError::NotFound { .. }) if NkTable::preset(name).is_some() => {}
        Err(FileError::NotFound { .. }) => b.warn(
            &loc,
            format!("metal \"{name}\" not found, using the default (aluminium)"),
        ),
        Err(err) => b.warn(&loc, format!("cannot read nk file: {err}; using aluminium")),
    }
    NkTable::preset(name)
        .or_else(|| NkTable::preset("aluminium"))
        .unwrap_or(NkTable {
            wl: vec![550.0],
            n: vec![1.0],
            k: vec![5.0],
        })
}

impl Metal {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<Metal, MaterialError> {
        let p = &e.params;
        let name = p
            .string("filename")
            .or_else(|| p.string("name"))
            .unwrap_or("aluminium")
            .to_string();
        let name = if name.is_empty() {
            "aluminium".to_string()
        } else {
            name
        };
        let table = load_nk(b, e, &name);
        let (n, k) = table.to_rgb();
        let (u, v) = roughness_pair(b, e, 0.1)?;
        Ok(Metal {
            n: Rgb::from_array(n),
            k: Rgb::from_array(k),
            u,
            v,
        })
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        Lobes::Microfacet(MicrofacetReflection {
            scale: Rgb::WHITE,
            fresnel: Fresnel::Conductor {
                n: self.n,
                k: self.k,
            },
            dist: SchlickDist::unclamped(self.u.eval(si), self.v.eval(si)),
        })
    }
}
