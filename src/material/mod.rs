//! Materials and their BSDFs (one file per material, scattering functions in [`bxdf`]).
//!
//! [`MaterialSet::build`] builds only the materials the scene uses (and the ones `mix`
//! materials reference), with LuxRender's parameter names and defaults, and their textures
//! through a [`TextureSet`]. [`Material::bsdf`] applies bump mapping and returns the [`Bsdf`]
//! of a hit. Unsupported material types are reported with their file:line:column and replaced
//! by LuxRender's fallback, a default matte.

pub mod bsdf;
pub mod bump;
pub mod bxdf;
pub mod carpaint;
pub mod glass;
pub mod glossy;
pub mod glossytranslucent;
pub mod matte;
pub mod mattetranslucent;
pub mod metal;
pub mod mirror;
pub mod mix;
pub mod nk_data;
pub mod roughglass;
pub mod shinymetal;
pub mod velvet;

pub use bsdf::{Bsdf, BsdfSample, Lobes};

use crate::fileio::SceneFiles;
use crate::geometry::SurfaceInteraction;
use crate::lxs::{Diagnostic, Entity, Loc, SceneDescription};
use crate::plugin::BuildError;
use crate::texture::{FloatTex, TextureCtx, TextureError, TextureSet};
use std::sync::Arc;
use thiserror::Error;

#[derive(Debug, Error)]
pub enum MaterialError {
    #[error(transparent)]
    Texture(#[from] TextureError),
    #[error("{loc}: no material named \"{name}\"")]
    Missing { loc: Loc, name: String },
    #[error("{loc}: material index {index} does not exist")]
    BadIndex { loc: Loc, index: usize },
    #[error("{loc}: mix material \"{name}\" contains itself")]
    Cycle { loc: Loc, name: String },
    #[error("{loc}: {message}")]
    BadParam { loc: Loc, message: String },
}

impl From<MaterialError> for BuildError {
    /// The one build error type: the location, and the message without it.
    fn from(e: MaterialError) -> BuildError {
        let e = match e {
            MaterialError::Texture(t) => return t.into(),
            other => other,
        };
        let loc = match &e {
            MaterialError::Texture(_) => Loc::default(),
            MaterialError::Missing { loc, .. }
            | MaterialError::BadIndex { loc, .. }
            | MaterialError::Cycle { loc, .. }
            | MaterialError::BadParam { loc, .. } => loc.clone(),
        };
        let full = e.to_string();
        let message = full
            .strip_prefix(&format!("{loc}: "))
            .unwrap_or(&full)
            .to_string();
        BuildError { loc, message }
    }
}

/// Where material files (nk data, images) are found.
#[derive(Clone, Debug, Default)]
pub struct MaterialCtx {
    /// Where material files (nk data) are opened: relative to the scene's directory,
    /// confined to it on a farm.
    pub files: SceneFiles,
}

/// The closed set of materials.
#[derive(Debug)]
pub enum MaterialKind {
    CarPaint(carpaint::CarPaint),
    Matte(matte::Matte),
    MatteTranslucent(mattetranslucent::MatteTranslucent),
    Mirror(mirror::Mirror),
    Glass(glass::Glass),
    RoughGlass(roughglass::RoughGlass),
    Glossy(glossy::Glossy),
    GlossyTranslucent(glossytranslucent::GlossyTranslucent),
    Metal(metal::Metal),
    ShinyMetal(shinymetal::ShinyMetal),
    Velvet(velvet::Velvet),
    Mix(mix::MixMaterial),
    Null,
}

#[derive(Debug)]
pub struct Material {
    pub kind: MaterialKind,
    /// `bumpmap` float texture (displacement along the shading normal).
    pub bump: Option<FloatTex>,
    /// `bumpmapsampledistance` (finite-difference step in u and v).
    pub bump_distance: f32,
    /// Type name as written (for logs).
    pub type_name: String,
}

impl Material {
    /// LuxRender's default material: matte with Kd 0.9.
    pub fn default_matte() -> Material {
        Material {
            kind: MaterialKind::Matte(matte::Matte::default_params()),
            bump: None,
            bump_distance: bump::DEFAULT_DISTANCE,
            type_name: "matte".into(),
        }
    }

    /// Null materials let rays continue unchanged (the integrator skips the hit).
    pub fn is_null(&self) -> bool {
        matches!(self.kind, MaterialKind::Null)
    }

    /// The BSDF at a hit; `u_select` in [0, 1) picks a component of mix materials.
    pub fn bsdf(&self, si: &SurfaceInteraction, u_select: f32) -> Bsdf {
        let bumped;
        let si = match &self.bump {
            Some(b) => {
                bumped = bump::apply(b, self.bump_distance, si);
                &bumped
            }
            None => si,
        };
        let lobes = match &self.kind {
            MaterialKind::CarPaint(m) => m.lobes(si),
            MaterialKind::Matte(m) => m.lobes(si),
            MaterialKind::MatteTranslucent(m) => m.lobes(si),
            MaterialKind::Mirror(m) => m.lobes(si),
            MaterialKind::Glass(m) => m.lobes(si),
            MaterialKind::RoughGlass(m) => m.lobes(si),
            MaterialKind::Glossy(m) => m.lobes(si),
            MaterialKind::GlossyTranslucent(m) => m.lobes(si),
            MaterialKind::Metal(m) => m.lobes(si),
            MaterialKind::ShinyMetal(m) => m.lobes(si),
            MaterialKind::Velvet(m) => m.lobes(si),
            MaterialKind::Null => Lobes::Null,
            MaterialKind::Mix(m) => {
                let (child, u) = m.select(si, u_select);
                return child.bsdf(si, u);
            }
        };
        Bsdf::new(si, lobes)
    }
}

/// Everything a material builder needs.
pub struct Builder<'a, 't> {
    pub desc: &'a SceneDescription,
    pub textures: &'t mut TextureSet<'a>,
    pub ctx: MaterialCtx,
    built: Vec<Option<Arc<Material>>>,
    building: Vec<usize>,
    pub warnings: Vec<Diagnostic>,
}

impl Builder<'_, '_> {
    pub fn warn(&mut self, loc: &Loc, message: String) {
        tracing::warn!("{loc}: {message}");
        self.warnings.push(Diagnostic {
            loc: loc.clone(),
            message,
        });
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

    /// A named material (mix components).
    pub fn named(&mut self, name: &str, loc: &Loc) -> Result<Arc<Material>, MaterialError> {
        let Some(&i) = self.desc.named_materials.get(name) else {
            return Err(MaterialError::Missing {
                loc: loc.clone(),
                name: name.to_string(),
            });
        };
        self.material(i, loc)
    }

    fn build_entity(&mut self, e: &Entity) -> Result<Material, MaterialError> {
        let p = &e.params;
        // MakeNamedMaterial's "type" became `kind`: it is not an unused parameter.
        let _ = p.string("type");
        let kind = match e.kind.as_str() {
            "matte" => MaterialKind::Matte(matte::Matte::build(self, e)?),
            "mattetranslucent" => {
                MaterialKind::MatteTranslucent(mattetranslucent::MatteTranslucent::build(self, e)?)
            }
            "mirror" => MaterialKind::Mirror(mirror::Mirror::build(self, e)?),
            "glass" => MaterialKind::Glass(glass::Glass::build(self, e)?),
            "glass2" => {
                self.warn(
                    &e.loc,
                    "glass2 takes its index from volumes, which are not built: rendered as glass \
                     with index 1.5"
                        .into(),
                );
                if p.bool_or("dispersion", false) {
                    self.warn(
                        &e.loc,
                        "dispersion needs spectral rendering, which is not built: ignored".into(),
                    );
                }
                MaterialKind::Glass(glass::Glass::build(self, e)?)
            }
            "roughglass" => MaterialKind::RoughGlass(roughglass::RoughGlass::build(self, e)?),
            "glossy" | "glossy_lossy" | "plastic" | "substrate" => {
                MaterialKind::Glossy(glossy::Glossy::build(self, e)?)
            }
            "metal" => MaterialKind::Metal(metal::Metal::build(self, e)?),
            "shinymetal" => MaterialKind::ShinyMetal(shinymetal::ShinyMetal::build(self, e)?),
            "glossytranslucent" => MaterialKind::GlossyTranslucent(
                glossytranslucent::GlossyTranslucent::build(self, e)?,
            ),
            "carpaint" => MaterialKind::CarPaint(carpaint::CarPaint::build(self, e)?),
            "velvet" => MaterialKind::Velvet(velvet::Velvet::build(self, e)?),
            "mix" => MaterialKind::Mix(mix::MixMaterial::build(self, e)?),
            "null" => MaterialKind::Null,
            other => {
                self.warn(
                    &e.loc,
                    format!("material \"{other}\" is not supported: using the default matte"),
                );
                return Ok(Material::default_matte());
            }
        };
        let bump = self.textures.optional_float(p, "bumpmap")?;
        let bump_distance = if bump.is_some() {
            p.float_or("bumpmapsampledistance", bump::DEFAULT_DISTANCE)
        } else {
            bump::DEFAULT_DISTANCE
        };
        Ok(Material {
            kind,
            bump,
            bump_distance,
            type_name: e.kind.clone(),
        })
    }
}

/// The materials of a scene, indexed like `SceneDescription::materials`.
pub struct MaterialSet {
    materials: Vec<Option<Arc<Material>>>,
    default: Arc<Material>,
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
        let mut b = Builder {
            desc,
            textures,
            ctx: ctx.clone(),
            built: vec![None; desc.materials.len()],
            building: Vec::new(),
            warnings: Vec::new(),
        };
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
}

#[cfg(test)]
mod tests;
