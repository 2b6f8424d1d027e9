//! `mix` texture: `(1 - amount) * tex1 + amount * tex2`; `amount` is a float texture
//! (default 0.5), `tex1` defaults to 0 and `tex2` to 1.

use super::{TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::{TextureDesc, TextureType};
use crate::spectrum::Rgb;
use std::sync::Arc;

#[derive(Debug)]
pub struct MixTex {
    pub amount: Arc<TexNode>,
    pub tex1: Arc<TexNode>,
    pub tex2: Arc<TexNode>,
}

impl MixTex {
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        let a = self.amount.eval(si).r;
        self.tex1.eval(si) * (1.0 - a) + self.tex2.eval(si) * a
    }
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let amount = set.node_param(
        TextureType::Float,
        &t.entity.params,
        "amount",
        Rgb::splat(0.5),
    )?;
    let (tex1, tex2) = set.operands(t, 0.0, 1.0)?;
    Ok(TexNode::Mix(MixTex { amount, tex1, tex2 }))
}
