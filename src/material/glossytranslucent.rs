//! `glossytranslucent`: `Kd`, `Kt` (default 1, clamped), `Ks` (1), `index` (0), `Ka` (0),
//! `d` (0), `uroughness`/`vroughness` (0.1), `multibounce` (false) for the front face;
//! `onesided` (default true) copies them to the back face, otherwise `backface_Ks` (0),
//! `backface_index`, `backface_Ka`, `backface_d`, `backface_uroughness`/`vroughness` (0) and
//! `backface_multibounce` apply there. See [`super::bxdf::glossy_translucent`].

use super::bsdf::Lobes;
use super::bxdf::diffuse::Diffuse;
use super::bxdf::glossy_translucent::GlossyTranslucentLobes;
use super::bxdf::schlick::{Coating, SchlickDist};
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::{ColorTex, FloatTex};

/// The coating parameters of one face.
#[derive(Debug)]
pub struct Face {
    pub ks: ColorTex,
    pub index: FloatTex,
    pub ka: ColorTex,
    pub depth: FloatTex,
    pub u: FloatTex,
    pub v: FloatTex,
    pub multibounce: bool,
}

#[derive(Debug)]
pub struct GlossyTranslucent {
    pub kd: ColorTex,
    pub kt: ColorTex,
    pub front: Face,
    /// `None` when one-sided: the back face uses the front parameters.
    pub back: Option<Face>,
}

fn face(b: &mut Builder, e: &Entity, prefix: &str, d: (f32, f32)) -> Result<Face, MaterialError> {
    let p = &e.params;
    let t = &mut b.textures;
    let k = |n: &str| format!("{prefix}{n}");
    Ok(Face {
        ks: t.color_param(p, &k("Ks"), Rgb::splat(d.0))?,
        index: t.float_param(p, &k("index"), 0.0)?,
        ka: t.color_param(p, &k("Ka"), Rgb::BLACK)?,
        depth: t.float_param(p, &k("d"), 0.0)?,
        u: t.float_param(p, &k("uroughness"), d.1)?,
        v: t.float_param(p, &k("vroughness"), d.1)?,
        multibounce: p.bool_or(&k("multibounce"), false),
    })
}

impl GlossyTranslucent {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<GlossyTranslucent, MaterialError> {
        let p = &e.params;
        let kd = b.textures.color_param(p, "Kd", Rgb::WHITE)?;
        let kt = b.textures.color_param(p, "Kt", Rgb::WHITE)?;
        let front = face(b, e, "", (1.0, 0.1))?;
        let back = if p.bool_or("onesided", true) {
            None
        } else {
            Some(face(b, e, "backface_", (0.0, 0.0))?)
        };
        Ok(GlossyTranslucent {
            kd,
            kt,
            front,
            back,
        })
    }

    fn coating(f: &Face, kd: Rgb, si: &SurfaceInteraction) -> Coating {
        let mut ks = f.ks.eval(si);
        let i = f.index.eval(si);
        if i > 0.0 {
            let r = (i - 1.0) / (i + 1.0);
            ks *= r * r;
        }
        Coating {
            base: Diffuse::lambert(kd),
            ks: ks.map(|v| v.clamp(0.0, 1.0)),
            ka: f.ka.eval(si).map(|v| v.clamp(0.0, 1.0)),
            depth: f.depth.eval(si).max(0.0),
            dist: SchlickDist::from_uv(f.u.eval(si), f.v.eval(si)),
            multibounce: f.multibounce,
        }
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        let kd = self.kd.eval(si).map(|v| v.clamp(0.0, 1.0));
        let front = Self::coating(&self.front, kd, si);
        let back = match &self.back {
            Some(b) => Self::coating(b, kd, si),
            None => front,
        };
        Lobes::GlossyTranslucent(GlossyTranslucentLobes {
            front,
            back,
            kt: self.kt.eval(si).map(|v| v.clamp(0.0, 1.0)),
        })
    }
}
