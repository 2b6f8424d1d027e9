//! `blender_clouds`: Blender's clouds, a turbulence of `noisedepth` (2) octaves of the
//! `noisebasis` at `noisesize` (0.25), `noisetype` soft or hard; `type` `color` makes a colour
//! from three turbulences of permuted coordinates (`default`: grey).

use super::noiselib::{g_turbulence, NoiseBasis};
use super::{BriCont, Params, TexResult};
use crate::texture::TextureError;

#[derive(Debug)]
pub struct Clouds {
    pub color: bool,
    pub hard: bool,
    pub basis: NoiseBasis,
    pub size: f32,
    pub depth: i32,
}

impl Clouds {
    pub fn eval(&self, p: [f32; 3], bc: &BriCont) -> TexResult {
        let t = |x: f32, y: f32, z: f32| {
            g_turbulence(self.size, x, y, z, self.depth, self.hard, self.basis)
        };
        let tin = t(p[0], p[1], p[2]);
        if self.color {
            let rgb = bc.rgb([tin, t(p[1], p[0], p[2]), t(p[1], p[2], p[0])]);
            return TexResult {
                tin,
                rgb: Some(rgb),
            };
        }
        TexResult::int(bc.int(tin))
    }
}

pub fn build(p: &mut Params) -> Result<Clouds, TextureError> {
    let color = p.choice("type", None, ("default", false), |s| match s {
        "default" => Some(false),
        "color" => Some(true),
        _ => None,
    });
    Ok(Clouds {
        color,
        hard: p.hard(),
        basis: p.basis("noisebasis"),
        size: p.noise_size()?,
        depth: p.noise_depth(),
    })
}
