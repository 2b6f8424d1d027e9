//! `hitpointgrey` texture (float): one channel of the vertex colour at the hit: `integer
//! channel` 0 (red), 1 (green), 2 (blue), anything else (the default, -1) the luminance
//! Y = 0.212671 r + 0.715160 g + 0.072169 b.

use super::{TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;

pub const DEFAULT_CHANNEL: i32 = -1;

#[derive(Debug)]
pub struct HitpointGrey {
    /// 0, 1, 2: that channel; `None`: luminance.
    pub channel: Option<usize>,
}

impl HitpointGrey {
    pub fn value(&self, si: &SurfaceInteraction) -> f32 {
        let [r, g, b] = si.hit.color;
        match self.channel {
            Some(c) => si.hit.color.get(c).copied().unwrap_or(0.0),
            None => 0.212_671 * r + 0.715_160 * g + 0.072_169 * b,
        }
    }
}

pub fn build(_set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let c = t.entity.params.int_or("channel", DEFAULT_CHANNEL);
    let channel = (0..=2).contains(&c).then_some(c as usize);
    Ok(TexNode::HitpointGrey(HitpointGrey { channel }))
}
