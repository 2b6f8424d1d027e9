//! Materials and their BSDFs: one file per LuxRender 1.x material, scattering functions in
//! [`bxdf`], materials made of materials in [`composite`].
//!
//! ```text
//! MaterialDesc --MaterialSet::build (set.rs: only the materials the scene uses, and what
//!   they reference)--> Builder::build_entity (here: dispatch on the type name)
//!   --<material>::build (reads its parameters and textures)--> Material
//! hit --Material::bsdf (bump map, then the kind's lobes; mix picks a component)--> Bsdf
//! ```
//!
//! Every material also reads the common parameters: `bumpmap`/`bumpmapsampledistance`
//! (applied through [`bump`]) and the `compo_*` compositing flags ([`Compositing`]). Legacy
//! names keep their parameters: `plastic` and `substrate` are LuxRender's glossy_lossy (the
//! parser reports them, located), `plastic`'s `roughness` sets both roughnesses. An unknown
//! type is reported with its file:line:column and replaced by LuxRender's fallback, a
//! default matte.

pub mod bsdf;
pub mod bump;
pub mod bxdf;
pub mod carpaint;
pub mod cloth;
pub mod cloth_patterns;
pub mod compositing;
pub mod doubleside;
pub mod glass;
pub mod glass2;
pub mod glossy;
pub mod glossy_lossy;
pub mod glossycoating;
pub mod glossytranslucent;
pub mod layered;
pub mod matte;
pub mod mattetranslucent;
pub mod metal;
pub mod metal2;
pub mod mirror;
pub mod mix;
pub mod roughglass;
pub mod scatter;
pub mod set;
pub mod shinymetal;
pub mod velvet;

pub use bsdf::{Bsdf, BsdfSample, Lobes};
pub use compositing::Compositing;
pub use set::{Builder, MaterialCtx, MaterialSet};

use crate::geometry::SurfaceInteraction;
use crate::lxs::{Entity, Loc};
use crate::plugin::BuildError;
use crate::texture::{FloatTex, TextureError};
use thiserror::Error;

#[derive(Debug, Error)]
pub enum MaterialError {
    #[error(transparent)]
    Texture(#[from] TextureError),
    #[error("{loc}: no material named \"{name}\"")]
    Missing { loc: Loc, name: String },
    #[error("{loc}: material index {index} does not exist")]
    BadIndex { loc: Loc, index: usize },
    #[error("{loc}: material \"{name}\" contains itself")]
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

/// How a dispersing material's index depends on the wavelength at one hit.
#[derive(Clone, Copy, Debug)]
pub enum Dispersion<'a> {
    /// glass, roughglass: the index plus cauchyb/λ² (this is cauchyb).
    Cauchy(f32),
    /// glass2: the ratio of its volumes' indices at λ.
    Volumes(glass2::SpectralEta<'a>),
}

impl Dispersion<'_> {
    /// How much the index of the hit's lobes changes at wavelength `nm`.
    pub fn shift(&self, nm: f32) -> f32 {
        match self {
            Dispersion::Cauchy(b) => glass::cauchy_shift(*b, nm),
            Dispersion::Volumes(s) => s.shift(nm),
        }
    }
}

/// The closed set of materials.
#[derive(Debug)]
pub enum MaterialKind {
    CarPaint(carpaint::CarPaint),
    Cloth(cloth::Cloth),
    DoubleSide(doubleside::DoubleSide),
    Glass(glass::Glass),
    Glass2(glass2::Glass2),
    Glossy(glossy::Glossy),
    GlossyCoating(glossycoating::GlossyCoating),
    GlossyLossy(glossy_lossy::GlossyLossy),
    GlossyTranslucent(glossytranslucent::GlossyTranslucent),
    Layered(layered::Layered),
    Matte(matte::Matte),
    MatteTranslucent(mattetranslucent::MatteTranslucent),
    Metal(metal::Metal),
    Metal2(metal2::Metal2),
    Mirror(mirror::Mirror),
    Mix(mix::MixMaterial),
    RoughGlass(roughglass::RoughGlass),
    Scatter(scatter::Scatter),
    ShinyMetal(shinymetal::ShinyMetal),
    Velvet(velvet::Velvet),
    Null,
}

#[derive(Debug)]
pub struct Material {
    pub kind: MaterialKind,
    /// `bumpmap` float texture (displacement along the shading normal).
    pub bump: Option<FloatTex>,
    /// `bumpmapsampledistance` (finite-difference step in u and v).
    pub bump_distance: f32,
    /// The `compo_*` parameters.
    pub compositing: Compositing,
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
            compositing: Compositing::default(),
            type_name: "matte".into(),
        }
    }

    /// How the index depends on the wavelength at the hit, when the material disperses light:
    /// glass and roughglass with `cauchyb` ≠ 0, glass2 with `dispersion` and a volume index
    /// that depends on the wavelength; in a mix, the component that [`Self::bsdf`] picks with
    /// the same `u_select`. [`Dispersion::shift`] gives the index change at a wavelength,
    /// applied by [`Bsdf::disperse`].
    pub fn dispersion<'a>(
        &'a self,
        si: &'a SurfaceInteraction,
        u_select: f32,
    ) -> Option<Dispersion<'a>> {
        let t = match &self.kind {
            MaterialKind::Glass(g) => g.cauchyb.as_ref(),
            MaterialKind::RoughGlass(g) => g.cauchyb.as_ref(),
            MaterialKind::Glass2(g) => return g.spectral_eta(si).map(Dispersion::Volumes),
            MaterialKind::Mix(m) => {
                let (child, u) = m.select(si, u_select);
                return child.dispersion(si, u);
            }
            _ => None,
        }?;
        let b = t.eval(si);
        (b != 0.0 && b.is_finite()).then_some(Dispersion::Cauchy(b))
    }

    /// Whether the material can disperse light (it then needs spectral paths): a dispersing
    /// glass, or a mix with one among its components.
    pub fn disperses(&self) -> bool {
        match &self.kind {
            MaterialKind::Glass(g) => g.cauchyb.is_some(),
            MaterialKind::RoughGlass(g) => g.cauchyb.is_some(),
            MaterialKind::Glass2(g) => g.disperses,
            MaterialKind::Mix(m) => m.m1.disperses() || m.m2.disperses(),
            _ => false,
        }
    }

    /// Null materials let rays continue unchanged (the integrator skips the hit).
    pub fn is_null(&self) -> bool {
        matches!(self.kind, MaterialKind::Null)
    }

    /// Whether [`Self::bsdf`] and [`Self::dispersion`] read their `u_select` (a mix or a
    /// layered material, or one built on them): an integrator draws that sample only then.
    pub fn uses_select(&self) -> bool {
        match &self.kind {
            MaterialKind::Mix(_) | MaterialKind::Layered(_) => true,
            MaterialKind::DoubleSide(m) => m.front.uses_select() || m.back.uses_select(),
            MaterialKind::GlossyCoating(m) => m.base.uses_select(),
            _ => false,
        }
    }

    /// The BSDF at a hit; `u_select` in [0, 1) picks a component of mix materials (and seeds
    /// the layered material's estimator).
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
            MaterialKind::Cloth(m) => m.lobes(si),
            MaterialKind::DoubleSide(m) => m.lobes(si, u_select),
            MaterialKind::Glass(m) => m.lobes(si),
            MaterialKind::Glass2(m) => m.lobes(si),
            MaterialKind::Glossy(m) => m.lobes(si),
            MaterialKind::GlossyCoating(m) => m.lobes(si, u_select),
            MaterialKind::GlossyLossy(m) => m.lobes(si),
            MaterialKind::GlossyTranslucent(m) => m.lobes(si),
            MaterialKind::Layered(m) => m.lobes(si, u_select),
            MaterialKind::Matte(m) => m.lobes(si),
            MaterialKind::MatteTranslucent(m) => m.lobes(si),
            MaterialKind::Metal(m) => m.lobes(si),
            MaterialKind::Metal2(m) => m.lobes(si),
            MaterialKind::Mirror(m) => m.lobes(si),
            MaterialKind::RoughGlass(m) => m.lobes(si),
            MaterialKind::Scatter(m) => m.lobes(si),
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

impl Builder<'_, '_> {
    /// Builds one material statement: the kind by its type name, then the common parameters.
    pub(crate) fn build_entity(&mut self, e: &Entity) -> Result<Material, MaterialError> {
        let p = &e.params;
        // MakeNamedMaterial's "type" became `kind`: it is not an unused parameter.
        let _ = p.string("type");
        let kind = match e.kind.as_str() {
            "carpaint" => MaterialKind::CarPaint(carpaint::CarPaint::build(self, e)?),
            "cloth" => MaterialKind::Cloth(cloth::Cloth::build(self, e)?),
            "doubleside" => MaterialKind::DoubleSide(doubleside::DoubleSide::build(self, e)?),
            "glass" => MaterialKind::Glass(glass::Glass::build(self, e)?),
            "glass2" => MaterialKind::Glass2(glass2::Glass2::build(self, e)?),
            "glossy" => MaterialKind::Glossy(glossy::Glossy::build(self, e)?),
            "glossycoating" => {
                MaterialKind::GlossyCoating(glossycoating::GlossyCoating::build(self, e)?)
            }
            "glossy_lossy" | "plastic" | "substrate" => {
                MaterialKind::GlossyLossy(glossy_lossy::GlossyLossy::build(self, e)?)
            }
            "glossytranslucent" => MaterialKind::GlossyTranslucent(
                glossytranslucent::GlossyTranslucent::build(self, e)?,
            ),
            "layered" => MaterialKind::Layered(layered::Layered::build(self, e)?),
            "matte" => MaterialKind::Matte(matte::Matte::build(self, e)?),
            "mattetranslucent" => {
                MaterialKind::MatteTranslucent(mattetranslucent::MatteTranslucent::build(self, e)?)
            }
            "metal" => MaterialKind::Metal(metal::Metal::build(self, e)?),
            "metal2" => MaterialKind::Metal2(metal2::Metal2::build(self, e)?),
            "mirror" => MaterialKind::Mirror(mirror::Mirror::build(self, e)?),
            "mix" => MaterialKind::Mix(mix::MixMaterial::build(self, e)?),
            "null" => MaterialKind::Null,
            "roughglass" => MaterialKind::RoughGlass(roughglass::RoughGlass::build(self, e)?),
            "scatter" => MaterialKind::Scatter(scatter::Scatter::build(self, e)?),
            "shinymetal" => MaterialKind::ShinyMetal(shinymetal::ShinyMetal::build(self, e)?),
            "velvet" => MaterialKind::Velvet(velvet::Velvet::build(self, e)?),
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
            compositing: Compositing::read(p),
            type_name: e.kind.clone(),
        })
    }
}

#[cfg(test)]
mod tests;
