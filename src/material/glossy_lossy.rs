//! `glossy_lossy` and the legacy `plastic` and `substrate` (LuxRender 1.x registers all three
//! as its `Glossy` class): LuxRender's `FresnelBlend` BRDF with a Schlick distribution (see
//! [`super::bxdf::fresnel_blend`]). `Kd` (default 1, clamped), `Ks` (1; times
//! ((index - 1)/(index + 1))² when `index` > 0, then clamped), `Ka` (0), `d` (0), `index` (0),
//! `uroughness`/`vroughness` (0.1, not clamped). Old exporters give `plastic` a single
//! `roughness` (pbrt's plastic): it sets both roughnesses as written, so 0.000571 stays
//! 0.000571. The parser reports the legacy names with their location.

use super::bsdf::Lobes;
use super::bxdf::fresnel_blend::FresnelBlend;
use super::bxdf::schlick::SchlickDist;
use super::metal::roughness_pair;
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::{ColorTex, FloatTex};

#[derive(Debug)]
pub struct GlossyLossy {
    pub kd: ColorTex,
    pub ks: ColorTex,
    pub ka: ColorTex,
    pub depth: FloatTex,
    pub index: FloatTex,
    pub u: FloatTex,
    pub v: FloatTex,
}

impl GlossyLossy {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<GlossyLossy, MaterialError> {
        let p = &e.params;
        let (u, v) = roughness_pair(b, e, 0.1)?;
        let t = &mut b.textures;
        Ok(GlossyLossy {
            kd: t.color_param(p, "Kd", Rgb::WHITE)?,
            ks: t.color_param(p, "Ks", Rgb::WHITE)?,
            ka: t.color_param(p, "Ka", Rgb::BLACK)?,
            depth: t.float_param(p, "d", 0.0)?,
            index: t.float_param(p, "index", 0.0)?,
            u,
            v,
        })
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        let clamp = |c: Rgb| c.map(|v| v.clamp(0.0, 1.0));
        let mut ks = self.ks.eval(si);
        let i = self.index.eval(si);
        if i > 0.0 {
            let r = (i - 1.0) / (i + 1.0);
            ks *= r * r;
        }
        Lobes::FresnelBlend(FresnelBlend {
            kd: clamp(self.kd.eval(si)),
            ks: clamp(ks),
            ka: clamp(self.ka.eval(si)),
            depth: self.depth.eval(si).max(0.0),
            dist: SchlickDist::unclamped(self.u.eval(si), self.v.eval(si)),
        })
    }
}
