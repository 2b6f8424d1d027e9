//! `glossy` (also `glossy_lossy`, and the legacy `plastic` and `substrate`, which LuxRender maps
//! to it): a Schlick coating over a diffuse base. `Kd` (default 1, clamped), `Ks` (default 1;
//! multiplied by ((index - 1) / (index + 1))² when `index` > 0, then clamped), `Ka` (absorption,
//! default 0), `d` (coating depth, default 0), `index` (default 0), `uroughness`/`vroughness`
//! (default 0.1, clamped to [6e-3, 1]), `multibounce` (default false), `sigma` (Oren–Nayar base,
//! default 0). See [`super::bxdf::schlick`] for the model.

use super::bsdf::Lobes;
use super::bxdf::diffuse::Diffuse;
use super::bxdf::schlick::{Coating, SchlickDist};
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::{ColorTex, FloatTex};

#[derive(Debug)]
pub struct Glossy {
    pub kd: ColorTex,
    pub ks: ColorTex,
    pub ka: ColorTex,
    pub depth: FloatTex,
    pub index: FloatTex,
    pub u: FloatTex,
    pub v: FloatTex,
    pub sigma: FloatTex,
    pub multibounce: bool,
}

impl Glossy {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<Glossy, MaterialError> {
        let p = &e.params;
        let t = &mut b.textures;
        Ok(Glossy {
            kd: t.color_param(p, "Kd", Rgb::WHITE)?,
            ks: t.color_param(p, "Ks", Rgb::WHITE)?,
            ka: t.color_param(p, "Ka", Rgb::BLACK)?,
            depth: t.float_param(p, "d", 0.0)?,
            index: t.float_param(p, "index", 0.0)?,
            u: t.float_param(p, "uroughness", 0.1)?,
            v: t.float_param(p, "vroughness", 0.1)?,
            sigma: t.float_param(p, "sigma", 0.0)?,
            multibounce: p.bool_or("multibounce", false),
        })
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        let clamp = |c: Rgb| c.map(|v| v.clamp(0.0, 1.0));
        let kd = clamp(self.kd.eval(si));
        let mut ks = self.ks.eval(si);
        let i = self.index.eval(si);
        if i > 0.0 {
            let r = (i - 1.0) / (i + 1.0);
            ks *= r * r;
        }
        let sigma = self.sigma.eval(si).clamp(0.0, 90.0);
        let base = if sigma == 0.0 {
            Diffuse::lambert(kd)
        } else {
            Diffuse::oren_nayar(kd, sigma)
        };
        Lobes::Coating(Coating {
            base,
            ks: clamp(ks),
            ka: clamp(self.ka.eval(si)),
            depth: self.depth.eval(si).max(0.0),
            dist: SchlickDist::from_uv(self.u.eval(si), self.v.eval(si)),
            multibounce: self.multibounce,
        })
    }
}
