//! `mix`: `namedmaterial1` and `namedmaterial2` blended by the float texture `amount`
//! (default 0.5; the weight of the second material). The BSDF of a hit is one of the two,
//! chosen with probability (1 - amount, amount) by `u_select`, which is then rescaled to
//! [0, 1) for nested mixes: an unbiased stochastic blend.

use super::{Builder, Material, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::texture::{param_loc, FloatTex};
use std::sync::Arc;

#[derive(Debug)]
pub struct MixMaterial {
    pub amount: FloatTex,
    pub m1: Arc<Material>,
    pub m2: Arc<Material>,
}

impl MixMaterial {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<MixMaterial, MaterialError> {
        let p = &e.params;
        let get = |b: &mut Builder, key: &str| -> Result<Arc<Material>, MaterialError> {
            let loc = param_loc(p, key, &e.loc);
            match p.string(key) {
                Some(name) => b.named(name, &loc),
                None => Err(MaterialError::BadParam {
                    loc,
                    message: format!("mix material needs \"string {key}\""),
                }),
            }
        };
        let m1 = get(b, "namedmaterial1")?;
        let m2 = get(b, "namedmaterial2")?;
        let amount = b.textures.float_param(p, "amount", 0.5)?;
        Ok(MixMaterial { amount, m1, m2 })
    }

    /// The component for this sample and the rescaled selector.
    pub fn select(&self, si: &SurfaceInteraction, u: f32) -> (&Material, f32) {
        let a = self.amount.eval(si).clamp(0.0, 1.0);
        if u < a {
            (&self.m2, (u / a).min(0.999_999))
        } else {
            let rest = 1.0 - a;
            let v = if rest > 0.0 { (u - a) / rest } else { 0.0 };
            (&self.m1, v.clamp(0.0, 0.999_999))
        }
    }
}
