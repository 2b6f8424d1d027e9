//! `checkerboard` texture: `dimension` 2 (a 2D mapping; `tex1` where floor(s) + floor(t) is
//! even, `tex2` elsewhere) or 3 (the same with the three texture-space coordinates).
//! `tex1` defaults to 1 and `tex2` to 0. Antialiasing (`aamode`) is not done: point sampling.
//! The 3D variant reads the 3D mapping options (see [`Mapping3D`]).

use super::mapping::{Mapping2D, Mapping3D};
use super::{param_loc, TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;
use crate::spectrum::Rgb;
use std::sync::Arc;

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

impl Checker2D {
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        let st = self.mapping.map(si);
        let sum = st.x.floor() as i64 + st.y.floor() as i64;
        if sum.rem_euclid(2) == 0 {
            self.tex1.eval(si)
        } else {
            self.tex2.eval(si)
        }
    }
}

impl Checker3D {
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        let p = self.mapping.map(si);
        let sum = p.x.floor() as i64 + p.y.floor() as i64 + p.z.floor() as i64;
        if sum.rem_euclid(2) == 0 {
            self.tex1.eval(si)
        } else {
            self.tex2.eval(si)
        }
    }
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let p = &t.entity.params;
    let dim = p.int_or("dimension", 2);
    let aa = p.string_or("aamode", "none").to_string();
    if aa != "none" {
        let loc = param_loc(p, "aamode", &t.entity.loc);
        set.warn(
            &loc,
            format!("checkerboard aamode \"{aa}\" is not supported: point sampled"),
        );
    }
    let (tex1, tex2) = set.operands(t, 1.0, 0.0)?;
    match dim {
        2 => Ok(TexNode::Checker2D(Checker2D {
            mapping: Mapping2D::from_params(t)?,
            tex1,
            tex2,
        })),
        3 => {
            let (mapping, warning) = Mapping3D::from_desc(t);
            if let Some(w) = warning {
                let loc = param_loc(p, "coordinates", &t.entity.loc);
                set.warn(&loc, w);
            }
            Ok(TexNode::Checker3D(Checker3D {
                mapping,
                tex1,
                tex2,
            }))
        }
        d => Err(TextureError::BadParam {
            loc: param_loc(p, "dimension", &t.entity.loc),
            message: format!("checkerboard dimension must be 2 or 3, got {d}"),
        }),
    }
}
