//! Building a scene's materials: [`MaterialSet::build`] builds the materials the scene's
//! shapes use and, on demand, the named materials they reference (mix, glossycoating,
//! doubleside, layered), each once, through a [`Builder`] that carries the description, the
//! texture set and the warnings.
//!
//! glass2 takes its index from the shape's Interior and Exterior volumes:
//! [`MaterialSet::bind_media`] gives, for a material and a pair of volume names, the index of
//! a copy built for those volumes when the material (or one it contains) is a glass2, and the
//! material itself otherwise.

use super::{Material, MaterialError};
use crate::fileio::SceneFiles;
use crate::lxs::{Diagnostic, Entity, Loc, SceneDescription};
use crate::texture::{Fresnel, FresnelTex, TextureCtx, TextureSet};
use std::collections::HashMap;
use std::sync::Arc;

/// Where material files (nk data, images) are found.
#[derive(Clone, Debug, Default)]
pub struct MaterialCtx {
    /// Where material files (nk data, images) are opened: relative to the scene's directory,
    /// confined to it on a farm.
    pub files: SceneFiles,
}

/// The indices of refraction glass2 sees at a shape: `fresnel` of its Interior and Exterior
/// volumes (a float or a fresnel texture; index 1 when a side has none).
#[derive(Clone, Debug)]
pub struct MediaIor {
    pub interior: FresnelTex,
    pub exterior: FresnelTex,
}

/// Everything a material builder needs.
pub struct Builder<'a, 't> {
    pub desc: &'a SceneDescription,
    pub textures: &'t mut TextureSet<'a>,
    pub ctx: MaterialCtx,
    /// The volumes glass2 materials are built for (`None`: no volumes).
    pub media: Option<MediaIor>,
    built: Vec<Option<Arc<Material>>>,
    building: Vec<usize>,
    pub warnings: Vec<Diagnostic>,
}

impl<'a, 't> Builder<'a, 't> {
    pub fn new(
        desc: &'a SceneDescription,
        textures: &'t mut TextureSet<'a>,
        ctx: MaterialCtx,
    ) -> Builder<'a, 't> {
        Builder {
            desc,
            textures,
            ctx,
            media: None,
            built: vec![None; desc.materials.len()],
            building: Vec::new(),
            warnings: Vec::new(),
        }
    }

    pub fn warn(&mut self, loc: &Loc, message: String) {
        crate::plugin::warn(&mut self.warnings, loc, message);
    }

    /// The material at `index` of the description, built once.
    pub fn material(&mut self, index: usize, loc: &Loc) -> Result<Arc<Material>, MaterialError> {
        if let Some(Some(m)) = self.built.get(index) {
            return Ok(m.clone());
        }
        let desc = self.desc;
        let Some(md) = desc.materials.get(index) else {
            return Err(MaterialError::BadIndex {
                loc: loc.clone(),
                index,
            });
        };
        if self.building.contains(&index) {
            return Err(MaterialError::Cycle {
                loc: md.entity.loc.clone(),
                name: md.name.clone().unwrap_or_default(),
            });
        }
        self.building.push(index);
        let m = self.build_entity(&md.entity);
        self.building.pop();
        let m = Arc::new(m?);
        tracing::debug!(
            "built material {} ({})",
            md.name.as_deref().unwrap_or("<anonymous>"),
            m.type_name
        );
        if let Some(slot) = self.built.get_mut(index) {
            *slot = Some(m.clone());
        }
        Ok(m)
    }

    /// A named material (the components of mix, glossycoating, doubleside, layered).
    pub fn named(&mut self, name: &str, loc: &Loc) -> Result<Arc<Material>, MaterialError> {
        let Some(&i) = self.desc.named_materials.get(name) else {
            return Err(MaterialError::Missing {
                loc: loc.clone(),
                name: name.to_string(),
            });
        };
        self.material(i, loc)
    }

    /// The named material of string parameter `key` of `e`, which must be present.
    pub fn required_named(
        &mut self,
        e: &Entity,
        key: &str,
    ) -> Result<Arc<Material>, MaterialError> {
        let loc = crate::texture::param_loc(&e.params, key, &e.loc);
        match e.params.string(key) {
            Some(name) => self.named(name, &loc),
            None => Err(MaterialError::BadParam {
                loc,
                message: format!("{} material needs \"string {key}\"", e.kind),
            }),
        }
    }

    /// The named material of string parameter `key` of `e`, when given (and not empty).
    pub fn optional_named(
        &mut self,
        e: &Entity,
        key: &str,
    ) -> Result<Option<Arc<Material>>, MaterialError> {
        match e.params.string(key) {
            Some(name) if !name.is_empty() => {
                let loc = crate::texture::param_loc(&e.params, key, &e.loc);
                self.named(name, &loc).map(Some)
            }
            _ => Ok(None),
        }
    }
}

/// The materials of a scene, indexed like `SceneDescription::materials`, followed by the
/// copies built for the volumes of glass2 shapes.
pub struct MaterialSet {
    materials: Vec<Option<Arc<Material>>>,
    default: Arc<Material>,
    /// Copies built for volumes: (material index, interior, exterior) -> index.
    bound: HashMap<(usize, Option<String>, Option<String>), usize>,
    ctx: MaterialCtx,
    /// Non-fatal problems found while building (also logged).
    pub warnings: Vec<Diagnostic>,
    /// Number of image files the textures loaded.
    pub images_loaded: usize,
}

impl MaterialSet {
    /// Builds the materials at `used` (indices into `desc.materials`) and what they reference.
    pub fn build(
        desc: &SceneDescription,
        used: &[usize],
        ctx: &MaterialCtx,
    ) -> Result<MaterialSet, MaterialError> {
        let mut textures = TextureSet::new(
            desc,
            TextureCtx {
                files: ctx.files.clone(),
            },
        );
        let mut set = MaterialSet::build_with_textures(desc, used, ctx, &mut textures)?;
        set.warnings.append(&mut textures.warnings);
        Ok(set)
    }

    /// As [`MaterialSet::build`], with a texture set shared with other users (lights), so that
    /// an image referenced by both is loaded once. Texture warnings stay in `textures`.
    pub fn build_with_textures<'a>(
        desc: &'a SceneDescription,
        used: &[usize],
        ctx: &MaterialCtx,
        textures: &mut TextureSet<'a>,
    ) -> Result<MaterialSet, MaterialError> {
        let mut b = Builder::new(desc, textures, ctx.clone());
        for &i in used {
            b.material(i, &Loc::default())?;
        }
        let count = b.built.iter().filter(|m| m.is_some()).count();
        tracing::info!(
            "built {count} of {} materials, {} textures, {} images",
            desc.materials.len(),
            b.textures.built_names().len(),
            b.textures.images_loaded()
        );
        Ok(MaterialSet {
            images_loaded: b.textures.images_loaded(),
            materials: b.built,
            default: Arc::new(Material::default_matte()),
            bound: HashMap::new(),
            ctx: ctx.clone(),
            warnings: b.warnings,
        })
    }

    /// The material at `index`; `None` (or an index that was not built) gives LuxRender's
    /// default matte.
    pub fn get(&self, index: Option<usize>) -> &Material {
        index
            .and_then(|i| self.materials.get(i))
            .and_then(|m| m.as_deref())
            .unwrap_or(&self.default)
    }

    /// Whether the material at `index` was built.
    pub fn is_built(&self, index: usize) -> bool {
        matches!(self.materials.get(index), Some(Some(_)))
    }

    /// The index of the material to use for a shape with these Interior/Exterior volumes:
    /// `index` itself unless the material contains a glass2, which takes its index from the
    /// volumes (a copy is built once per distinct pair).
    pub fn bind_media(
        &mut self,
        desc: &SceneDescription,
        index: usize,
        interior: Option<&str>,
        exterior: Option<&str>,
    ) -> Result<usize, MaterialError> {
        if !uses_media(desc, index, &mut Vec::new()) {
            return Ok(index);
        }
        let key = (
            index,
            interior.map(String::from),
            exterior.map(String::from),
        );
        if let Some(&i) = self.bound.get(&key) {
            return Ok(i);
        }
        let mut textures = TextureSet::new(
            desc,
            TextureCtx {
                files: self.ctx.files.clone(),
            },
        );
        let mut b = Builder::new(desc, &mut textures, self.ctx.clone());
        let media = MediaIor {
            interior: volume_ior(&mut b, interior)?,
            exterior: volume_ior(&mut b, exterior)?,
        };
        b.media = Some(media);
        // Materials without glass2 are shared with the unbound set.
        for (i, slot) in b.built.iter_mut().enumerate() {
            if !uses_media(desc, i, &mut Vec::new()) {
                *slot = self.materials.get(i).cloned().flatten();
            }
        }
        let m = b.material(index, &Loc::default())?;
        // Each pair of volumes builds its copy anew: report each problem once.
        for w in b.warnings.drain(..).chain(textures.warnings.drain(..)) {
            if !self.warnings.contains(&w) {
                self.warnings.push(w);
            }
        }
        self.materials.push(Some(m));
        let i = self.materials.len() - 1;
        self.bound.insert(key, i);
        Ok(i)
    }
}

/// Whether the material at `index` is a glass2 or contains one.
fn uses_media(desc: &SceneDescription, index: usize, seen: &mut Vec<usize>) -> bool {
    let Some(md) = desc.materials.get(index) else {
        return false;
    };
    if seen.contains(&index) {
        return false;
    }
    seen.push(index);
    let p = &md.entity.params;
    let refs: &[&str] = match md.entity.kind.as_str() {
        "glass2" => return true,
        "mix" | "layered" => &[
            "namedmaterial1",
            "namedmaterial2",
            "namedmaterial3",
            "namedmaterial4",
        ],
        "glossycoating" => &["basematerial"],
        "doubleside" => &["frontnamedmaterial", "backnamedmaterial"],
        _ => &[],
    };
    refs.iter().any(|key| {
        p.params
            .iter()
            .filter(|q| q.name == *key)
            .filter_map(|q| match &q.value {
                crate::lxs::ParamValue::String(v) => v.first(),
                _ => None,
            })
            .filter_map(|name| desc.named_materials.get(name))
            .any(|&i| uses_media(desc, i, seen))
    })
}

/// The `fresnel` of a named volume (index 1 without a volume, or for a name no volume has):
/// a float or a fresnel texture, read as the volume reads it ([`crate::volume::read_fresnel`]).
fn volume_ior(b: &mut Builder, name: Option<&str>) -> Result<FresnelTex, MaterialError> {
    let vacuum = || FresnelTex::constant(Fresnel::dielectric(1.0));
    let Some(name) = name else {
        return Ok(vacuum());
    };
    let desc = b.desc;
    let Some(v) = desc
        .named_volumes
        .get(name)
        .and_then(|&i| desc.volumes.get(i))
    else {
        return Ok(vacuum());
    };
    Ok(crate::volume::read_fresnel(
        &v.entity.params,
        &v.entity.loc,
        b.textures,
    )?)
}
