//! `blender_noise`: Blender's white noise: a random value in [0, 1] quantised by
//! `noisedepth` (2) rounds of Blender's `(r & 3)` products. Blender and LuxRender draw it from
//! one global random generator, so it changes from evaluation to evaluation and between
//! renders; here the generator (Blender's `BLI_rand`, a 48-bit LCG) is seeded from the point,
//! so the pattern is white noise over the surface and a render repeats exactly.

use super::{BriCont, Params, TexResult};
use crate::texture::TextureError;

#[derive(Debug)]
pub struct Noise {
    pub depth: i32,
}

/// Blender's `BLI_rand` step from state `x`: (value, next state).
fn bli_rand(x: u64) -> (i32, u64) {
    let next = (0x5_DEEC_E66D_u64.wrapping_mul(x).wrapping_add(0xB)) & 0x0000_FFFF_FFFF_FFFF;
    ((next >> 17) as i32, next)
}

impl Noise {
    pub fn eval(&self, p: [f32; 3], bc: &BriCont) -> TexResult {
        let seed = p.iter().fold(0x9E37_79B9_7F4A_7C15u64, |h, c| {
            (h ^ u64::from(c.to_bits())).wrapping_mul(0x100_0000_01B3)
        });
        let (mut ran, _) = bli_rand(seed);
        let mut val = ran & 3;
        let mut div = 3.0f32;
        for _ in 0..self.depth.clamp(0, 15) {
            ran >>= 2;
            val *= ran & 3;
            div *= 3.0;
        }
        TexResult::int(bc.int(val as f32 / div))
    }
}

pub fn build(p: &mut Params) -> Result<Noise, TextureError> {
    Ok(Noise {
        depth: p.noise_depth(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lcg_step_and_quantised_values() {
        // From state 0: X = 0xB, value 0xB >> 17 = 0.
        assert_eq!(bli_rand(0), (0, 0xB));
        let n = Noise { depth: 0 };
        let bc = BriCont {
            bright: 1.0,
            contrast: 1.0,
        };
        for i in 0..50 {
            let v = n.eval([i as f32 * 0.1, 0.2, 0.3], &bc).tin;
            // One of 0, ⅓, ⅔, 1 (up to the rounding of brightness/contrast 1).
            assert!((v * 3.0 - (v * 3.0).round()).abs() < 1e-5, "{v}");
            assert!((0.0..=1.0).contains(&v), "{v}");
        }
    }
}
