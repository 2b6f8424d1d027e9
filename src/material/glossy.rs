//! `glossy`: a Schlick coating over a diffuse base (LuxRender 1.x's glossy2). `Kd` (default
//! 1, clamped), `Ks` (default 1; multiplied by ((index - 1) / (index + 1))² when `index` > 0,
//! then clamped), `Ka` (absorption, default 0), `d` (coating depth, default 0), `index`
//! (default 0), `uroughness`/`vroughness` (default 0.1, clamped to [6e-3, 1]), `multibounce`
//! (default false), `separable` (default true) and, when separable, `sigma` (Oren–Nayar base,
//! default 0). Separable glossy is LuxRender's `SchlickBSDF` (a coating over a matte BSDF);
//! `separable` false is its single `SchlickBRDF`, which has no `sigma`. The defaults are
//! LuxRender's sources' (its scene-format page says 0.5 for Kd and Ks). See
//! [`super::bxdf::schlick`] for the models.

use super::bsdf::Lobes;
use super::bxdf::diffuse::Diffuse;
use super::bxdf::schlick::{Coating, SchlickBrdf, SchlickCoat, SchlickDist};
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::{Entity, ParamSet};
use crate::spectrum::Rgb;
use crate::texture::{ColorTex, FloatTex, TextureSet};

/// The coating parameters glossy, glossycoating and glossytranslucent share.
#[derive(Debug)]
pub struct CoatParams {
    pub ks: ColorTex,
    pub ka: ColorTex,
    pub depth: FloatTex,
    pub index: FloatTex,
    pub u: FloatTex,
    pub v: FloatTex,
    pub multibounce: bool,
}

impl CoatParams {
    /// Reads `{prefix}Ks`, `Ka`, `d`, `index`, `uroughness`, `vroughness`, `multibounce`.
    pub fn read(
        t: &mut TextureSet,
        p: &ParamSet,
        prefix: &str,
        ks: f32,
        roughness: f32,
    ) -> Result<CoatParams, MaterialError> {
        let k = |n: &str| format!("{prefix}{n}");
        Ok(CoatParams {
            ks: t.color_param(p, &k("Ks"), Rgb::splat(ks))?,
            ka: t.color_param(p, &k("Ka"), Rgb::BLACK)?,
            depth: t.float_param(p, &k("d"), 0.0)?,
            index: t.float_param(p, &k("index"), 0.0)?,
            u: t.float_param(p, &k("uroughness"), roughness)?,
            v: t.float_param(p, &k("vroughness"), roughness)?,
            multibounce: p.bool_or(&k("multibounce"), false),
        })
    }

    /// The coating at a hit: `Ks` scaled by the index's reflectance, clamped; roughness
    /// clamped to [6e-3, 1].
    pub fn eval(&self, si: &SurfaceInteraction) -> SchlickCoat {
        let clamp = |c: Rgb| c.map(|v| v.clamp(0.0, 1.0));
        let mut ks = self.ks.eval(si);
        let i = self.index.eval(si);
        if i > 0.0 {
            let r = (i - 1.0) / (i + 1.0);
            ks *= r * r;
        }
        SchlickCoat {
            ks: clamp(ks),
            ka: clamp(self.ka.eval(si)),
            depth: self.depth.eval(si).max(0.0),
            dist: SchlickDist::from_uv(self.u.eval(si), self.v.eval(si)),
            multibounce: self.multibounce,
        }
    }
}

#[derive(Debug)]
pub struct Glossy {
    pub kd: ColorTex,
    pub coat: CoatParams,
    /// `None` when not separable (no Oren–Nayar base).
    pub sigma: Option<FloatTex>,
}

impl Glossy {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<Glossy, MaterialError> {
        let p = &e.params;
        let t = &mut b.textures;
        let kd = t.color_param(p, "Kd", Rgb::WHITE)?;
        let coat = CoatParams::read(t, p, "", 1.0, 0.1)?;
        let sigma = if p.bool_or("separable", true) {
            Some(t.float_param(p, "sigma", 0.0)?)
        } else {
            None
        };
        Ok(Glossy { kd, coat, sigma })
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        let kd = self.kd.eval(si).map(|v| v.clamp(0.0, 1.0));
        let coat = self.coat.eval(si);
        let Some(sigma) = &self.sigma else {
            return Lobes::SchlickBrdf(SchlickBrdf { kd, coat });
        };
        let sigma = sigma.eval(si).clamp(0.0, 90.0);
        let base = if sigma == 0.0 {
            Diffuse::lambert(kd)
        } else {
            Diffuse::oren_nayar(kd, sigma)
        };
        Lobes::Coating(Coating { base, coat })
    }
}
