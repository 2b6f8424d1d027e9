//! `blender_marble`: Blender's marble, a wave (`noisebasis2`: `sin`, `saw`, `tri`) of
//! 5·(x + y + z) plus `turbulence` (5) times a turbulence of `noisedepth` (2) octaves of the
//! `noisebasis` at `noisesize` (0.25); `type` `soft`, `sharp` (√) or `sharper` (⁴√).

use super::noiselib::{g_turbulence, NoiseBasis};
use super::wood::Wave;
use super::{BriCont, Params, TexResult};
use crate::texture::TextureError;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sharpness {
    Soft,
    Sharp,
    Sharper,
}

#[derive(Debug)]
pub struct Marble {
    pub sharpness: Sharpness,
    pub wave: Wave,
    pub hard: bool,
    pub basis: NoiseBasis,
    pub size: f32,
    pub depth: i32,
    pub turbulence: f32,
}

impl Marble {
    pub fn eval(&self, p: [f32; 3], bc: &BriCont) -> TexResult {
        let n = 5.0 * (p[0] + p[1] + p[2]);
        let t = g_turbulence(
            self.size, p[0], p[1], p[2], self.depth, self.hard, self.basis,
        );
        let mut mi = self.wave.eval(n + self.turbulence * t);
        match self.sharpness {
            Sharpness::Soft => {}
            Sharpness::Sharp => mi = mi.sqrt(),
            Sharpness::Sharper => mi = mi.sqrt().sqrt(),
        }
        TexResult::int(bc.int(mi))
    }
}

pub fn build(p: &mut Params) -> Result<Marble, TextureError> {
    let sharpness = p.choice("type", None, ("soft", Sharpness::Soft), |s| {
        Some(match s {
            "soft" => Sharpness::Soft,
            "sharp" => Sharpness::Sharp,
            "sharper" => Sharpness::Sharper,
            _ => return None,
        })
    });
    Ok(Marble {
        sharpness,
        wave: Wave::read(p),
        hard: p.hard(),
        basis: p.basis("noisebasis"),
        size: p.noise_size()?,
        depth: p.noise_depth(),
        turbulence: p.float("turbulence", None, 5.0)?,
    })
}
