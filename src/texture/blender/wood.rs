//! `blender_wood`: Blender's wood: a wave (`noisebasis2`: `sin`, `saw`, `tri`) of
//! 10·(x + y + z) (`type` `bands`, the default) or 20·|P| (`rings`), plus for `bandnoise` and
//! `ringnoise` `turbulence` (5) times the `noisebasis` noise (`noisetype`, `noisesize` 0.25).

use super::noiselib::{g_noise, NoiseBasis};
use super::{BriCont, Params, TexResult};
use crate::texture::TextureError;
use std::f32::consts::PI;

/// Blender's wave forms (`noisebasis2` of wood and marble).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wave {
    Sin,
    Saw,
    Tri,
}

impl Wave {
    pub fn eval(self, a: f32) -> f32 {
        let b = 2.0 * PI;
        match self {
            Wave::Sin => 0.5 + 0.5 * a.sin(),
            Wave::Saw => {
                let n = (a / b) as i32;
                let mut a = a - n as f32 * b;
                if a < 0.0 {
                    a += b;
                }
                a / b
            }
            Wave::Tri => 1.0 - 2.0 * ((a * (1.0 / b) + 0.5).floor() - a * (1.0 / b)).abs(),
        }
    }

    /// The `noisebasis2` parameter.
    pub fn read(p: &mut Params) -> Wave {
        p.choice("noisebasis2", None, ("sin", Wave::Sin), |s| {
            Some(match s {
                "sin" => Wave::Sin,
                "saw" => Wave::Saw,
                "tri" => Wave::Tri,
                _ => return None,
            })
        })
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Bands,
    Rings,
    BandNoise,
    RingNoise,
}

#[derive(Debug)]
pub struct Wood {
    pub kind: Kind,
    pub wave: Wave,
    pub hard: bool,
    pub basis: NoiseBasis,
    pub size: f32,
    pub turbulence: f32,
}

impl Wood {
    pub fn eval(&self, p: [f32; 3], bc: &BriCont) -> TexResult {
        let [x, y, z] = p;
        let noise = || self.turbulence * g_noise(self.size, x, y, z, self.hard, self.basis);
        let wi = match self.kind {
            Kind::Bands => self.wave.eval((x + y + z) * 10.0),
            Kind::Rings => self.wave.eval((x * x + y * y + z * z).sqrt() * 20.0),
            Kind::BandNoise => self.wave.eval((x + y + z) * 10.0 + noise()),
            Kind::RingNoise => self
                .wave
                .eval((x * x + y * y + z * z).sqrt() * 20.0 + noise()),
        };
        TexResult::int(bc.int(wi))
    }
}

pub fn build(p: &mut Params) -> Result<Wood, TextureError> {
    let kind = p.choice("type", None, ("bands", Kind::Bands), |s| {
        Some(match s {
            "bands" => Kind::Bands,
            "rings" => Kind::Rings,
            "bandnoise" => Kind::BandNoise,
            "ringnoise" => Kind::RingNoise,
            _ => return None,
        })
    });
    Ok(Wood {
        kind,
        wave: Wave::read(p),
        hard: p.hard(),
        basis: p.basis("noisebasis"),
        size: p.noise_size()?,
        turbulence: p.float("turbulence", None, 5.0)?,
    })
}
