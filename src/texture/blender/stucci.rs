//! `blender_stucci`: Blender's stucci: the `noisebasis` noise (`noisetype`, `noisesize` 0.25)
//! at the point raised by `turbulence`/200 (times the squared noise for the wall types);
//! `type` `plastic` (the default), `wall_in`, `wall_out` (inverted). As in LuxRender, no
//! brightness/contrast is applied.

use super::noiselib::{g_noise, NoiseBasis};
use super::{BriCont, Params, TexResult};
use crate::texture::TextureError;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Plastic,
    WallIn,
    WallOut,
}

#[derive(Debug)]
pub struct Stucci {
    pub kind: Kind,
    pub hard: bool,
    pub basis: NoiseBasis,
    pub size: f32,
    pub turbulence: f32,
}

impl Stucci {
    pub fn eval(&self, p: [f32; 3], _bc: &BriCont) -> TexResult {
        let n = |z: f32| g_noise(self.size, p[0], p[1], z, self.hard, self.basis);
        let b2 = n(p[2]);
        let mut ofs = self.turbulence / 200.0;
        if self.kind != Kind::Plastic {
            ofs *= b2 * b2;
        }
        let mut tin = n(p[2] + ofs);
        if self.kind == Kind::WallOut {
            tin = 1.0 - tin;
        }
        TexResult::int(tin.max(0.0))
    }
}

pub fn build(p: &mut Params) -> Result<Stucci, TextureError> {
    let kind = p.choice("type", None, ("plastic", Kind::Plastic), |s| {
        Some(match s {
            "plastic" => Kind::Plastic,
            "wall_in" => Kind::WallIn,
            "wall_out" => Kind::WallOut,
            _ => return None,
        })
    });
    Ok(Stucci {
        kind,
        hard: p.hard(),
        basis: p.basis("noisebasis"),
        size: p.noise_size()?,
        turbulence: p.turbulence()?,
    })
}
