//! `glossycoating`: a glossy coating over another material, `basematerial` (required: a
//! named material, possibly another glossycoating). `Ks` (default 1; times
//! ((index - 1)/(index + 1))² when `index` > 0), `Ka` (0), `d` (0), `index` (0),
//! `uroughness`/`vroughness` (0.1, clamped to [6e-3, 1]), `multibounce` (false); the defaults
//! are LuxRender's sources' (its scene-format page says 0.5 for Ks). The base material's BSDF
//! is built at each hit with its own bump map over this one's; see
//! [`super::bsdf::composite::coated`] for how the two combine.

use super::bsdf::composite::coated::Coated;
use super::bsdf::composite::Composite;
use super::bsdf::Lobes;
use super::glossy::CoatParams;
use super::{Builder, Material, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use std::sync::Arc;

#[derive(Debug)]
pub struct GlossyCoating {
    pub base: Arc<Material>,
    pub coat: CoatParams,
}

impl GlossyCoating {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<GlossyCoating, MaterialError> {
        let base = b.required_named(e, "basematerial")?;
        let coat = CoatParams::read(b.textures, &e.params, "", 1.0, 0.1)?;
        Ok(GlossyCoating { base, coat })
    }

    pub fn lobes(&self, si: &SurfaceInteraction, u_select: f32) -> Lobes {
        let base = self.base.bsdf(si, u_select);
        Lobes::Composite(Box::new(Composite::Coated(Coated {
            coat: self.coat.eval(si),
            base,
        })))
    }
}
