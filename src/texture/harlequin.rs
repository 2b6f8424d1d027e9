//! `harlequin` texture (colour): a test pattern giving each face its own colour from
//! LuxRender's palette of 31: colour i is (radical inverse of 3i + 1 in bases 2, 3 and 5).
//! LuxRender picks the entry from the address of the hit primitive in memory; here it is a
//! hash of the primitive and face index, so neighbouring faces differ and a render repeats.

use super::{TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;
use crate::spectrum::Rgb;

/// Palette size (LuxRender's `HARLEQUIN_TEXTURE_PALETTE_SIZE`).
pub const PALETTE_SIZE: usize = 31;

/// The radical inverse of `i` in base `b`.
pub fn radical_inverse(mut i: u32, b: u32) -> f32 {
    let inv = 1.0 / b as f64;
    let (mut f, mut r) = (inv, 0.0f64);
    while i > 0 {
        r += (i % b) as f64 * f;
        i /= b;
        f *= inv;
    }
    r as f32
}

#[derive(Debug)]
pub struct HarlequinTex {
    pub palette: Box<[Rgb; PALETTE_SIZE]>,
}

impl HarlequinTex {
    pub fn new() -> HarlequinTex {
        let mut palette = Box::new([Rgb::BLACK; PALETTE_SIZE]);
        for (i, c) in palette.iter_mut().enumerate() {
            let n = i as u32 * 3 + 1;
            *c = Rgb::new(
                radical_inverse(n, 2),
                radical_inverse(n, 3),
                radical_inverse(n, 5),
            );
        }
        HarlequinTex { palette }
    }

    /// The palette entry of a face.
    pub fn index(prim: u32, face: u32) -> usize {
        let mut h = (u64::from(prim) << 32 | u64::from(face)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        h ^= h >> 29;
        (h % PALETTE_SIZE as u64) as usize
    }

    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        self.palette[Self::index(si.prim, si.hit.face)]
    }
}

impl Default for HarlequinTex {
    fn default() -> Self {
        HarlequinTex::new()
    }
}

pub fn build(_set: &mut TextureSet, _t: &TextureDesc) -> Result<TexNode, TextureError> {
    Ok(TexNode::Harlequin(HarlequinTex::new()))
}
