//! `checkerboard` texture: `dimension` 2 (a 2D mapping: `tex1` where ⌊s⌋ + ⌊t⌋ is even,
//! `tex2` elsewhere) or 3 (the same over the three texture-space coordinates of the 3D
//! mapping). `tex1` defaults to 1 and `tex2` to 0. `aamode` (`closedform`, `supersample`,
//! `none`) is read: LuxRender 1.x evaluates every mode by point sampling (it deprecated the
//! filtered modes), and so does this. The bump derivative is LuxRender's: the inputs' own,
//! plus a step of (tex2 − tex1)/delta within half a sample distance of a cell edge.

use super::mapping::{Mapping2D, Mapping3D};
use super::{TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;
use crate::spectrum::Rgb;
use glam::Vec2;
use std::sync::Arc;

/// Anti-aliasing modes LuxRender accepts (all point sampled in LuxRender 1.x).
pub const AA_MODES: [&str; 3] = ["closedform", "supersample", "none"];

#[derive(Debug)]
pub struct Checker2D {
    pub mapping: Mapping2D,
    pub tex1: Arc<TexNode>,
    pub tex2: Arc<TexNode>,
}

#[derive(Debug)]
pub struct Checker3D {
    pub mapping: Mapping3D,
    pub tex1: Arc<TexNode>,
    pub tex2: Arc<TexNode>,
}

fn even(sum: i64) -> bool {
    sum.rem_euclid(2) == 0
}

/// The edge term of LuxRender's checkerboard derivative along one axis: `x` the coordinate,
/// `ix` its cell, `width` the sample step in that coordinate, `d_du`/`d_dv` its derivatives.
fn edge(first: bool, x: f32, ix: f32, width: f32, d: f32, d_du: f32, d_dv: f32) -> Vec2 {
    let near = x - ix < width / 2.0 || x - ix > 1.0 - width / 2.0;
    if !near {
        return Vec2::ZERO;
    }
    let sign = if first ^ (x - ix < 0.5) { 1.0 } else { -1.0 };
    Vec2::new(d_du, d_dv) * (d * sign)
}

impl Checker2D {
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        let st = self.mapping.map(si);
        if even(st.x.floor() as i64 + st.y.floor() as i64) {
            self.tex1.eval(si)
        } else {
            self.tex2.eval(si)
        }
    }

    pub fn duv(&self, si: &SurfaceInteraction, delta: f32) -> Vec2 {
        let m = self.mapping.map_duv(si);
        let (is, it) = (m.st.x.floor(), m.st.y.floor());
        let first = even(is as i64 + it as i64);
        let mut d = if first {
            self.tex1.duv(si, delta)
        } else {
            self.tex2.duv(si, delta)
        };
        if delta > 0.0 {
            let step = (self.tex2.value(si) - self.tex1.value(si)) / delta;
            let ds = delta * (m.d_du.x + m.d_dv.x);
            let dt = delta * (m.d_du.y + m.d_dv.y);
            d += edge(first, m.st.x, is, ds, step, m.d_du.x, m.d_dv.x);
            d += edge(first, m.st.y, it, dt, step, m.d_du.y, m.d_dv.y);
        }
        d
    }
}

impl Checker3D {
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        let p = self.mapping.map(si);
        if even(p.x.floor() as i64 + p.y.floor() as i64 + p.z.floor() as i64) {
            self.tex1.eval(si)
        } else {
            self.tex2.eval(si)
        }
    }

    pub fn duv(&self, si: &SurfaceInteraction, delta: f32) -> Vec2 {
        let (p, dpdu, dpdv) = self.mapping.map_duv(si);
        let i = p.floor();
        let first = even(i.x as i64 + i.y as i64 + i.z as i64);
        let mut d = if first {
            self.tex1.duv(si, delta)
        } else {
            self.tex2.duv(si, delta)
        };
        if delta > 0.0 {
            let step = (self.tex2.value(si) - self.tex1.value(si)) / delta;
            for axis in 0..3 {
                let w = delta * (dpdu[axis] + dpdv[axis]);
                d += edge(first, p[axis], i[axis], w, step, dpdu[axis], dpdv[axis]);
            }
        }
        d
    }
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let p = &t.entity.params;
    let dim = p.int_or("dimension", 2);
    let aa = p.string_or("aamode", "closedform").to_string();
    if !AA_MODES.contains(&aa.as_str()) {
        set.warn(
            &super::param_loc(p, "aamode", &t.entity.loc),
            format!("checkerboard aamode \"{aa}\" is unknown (closedform, supersample, none): point sampled, as LuxRender does"),
        );
    }
    let (tex1, tex2) = set.operands(t, 1.0, 0.0)?;
    match dim {
        2 => Ok(TexNode::Checker2D(Checker2D {
            mapping: Mapping2D::from_params(t)?,
            tex1,
            tex2,
        })),
        3 => Ok(TexNode::Checker3D(Checker3D {
            mapping: set.mapping3d(t),
            tex1,
            tex2,
        })),
        d => Err(TextureError::param(
            t,
            "dimension",
            format!("checkerboard dimension must be 2 or 3, got {d}"),
        )),
    }
}
