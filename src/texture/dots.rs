//! `dots` texture: polka dots over a 2D mapping (LuxRender's pattern). Cell (⌊s + ½⌋,
//! ⌊t + ½⌋) holds a dot when noise(cell + ½) > 0; the dot, of radius 0.35, is centred at the
//! cell shifted by 0.15·noise at two fixed offsets. LuxRender 1.x hands its two parameters to
//! the pattern the other way round (its constructor takes them as outside, inside): the dots
//! show `outside` (default 0) and the rest `inside` (default 1). This is what LuxRender
//! renders, so it is what this renders (LuxCore, which fixed the order, shows them swapped).

use super::mapping::Mapping2D;
use super::noise::noise;
use super::{TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;
use crate::spectrum::Rgb;
use std::sync::Arc;

const RADIUS: f32 = 0.35;

#[derive(Debug)]
pub struct DotsTex {
    pub mapping: Mapping2D,
    /// What the dots show (the `outside` parameter, as in LuxRender).
    pub dot: Arc<TexNode>,
    /// What shows between them (the `inside` parameter).
    pub background: Arc<TexNode>,
}

/// Whether (s, t) lies in a dot.
pub fn in_dot(s: f32, t: f32) -> bool {
    let s_cell = (s + 0.5).floor();
    let t_cell = (t + 0.5).floor();
    if noise(s_cell + 0.5, t_cell + 0.5, 0.5) > 0.0 {
        let max_shift = 0.5 - RADIUS;
        let s_center = s_cell + max_shift * noise(s_cell + 1.5, t_cell + 2.8, 0.5);
        let t_center = t_cell + max_shift * noise(s_cell + 4.5, t_cell + 9.8, 0.5);
        let (ds, dt) = (s - s_center, t - t_center);
        return ds * ds + dt * dt < RADIUS * RADIUS;
    }
    false
}

impl DotsTex {
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        let st = self.mapping.map(si);
        if in_dot(st.x, st.y) {
            self.dot.eval(si)
        } else {
            self.background.eval(si)
        }
    }
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let inside = set.same_type(t, "inside", 1.0)?;
    let outside = set.same_type(t, "outside", 0.0)?;
    Ok(TexNode::Dots(DotsTex {
        mapping: Mapping2D::from_params(t)?,
        dot: outside,
        background: inside,
    }))
}
