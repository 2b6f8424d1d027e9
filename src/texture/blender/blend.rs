//! `blender_blend`: Blender's gradient. `type`: `lin` ((1 + x)/2, the default), `quad` (its
//! square), `ease` (smoothstep of it), `diag` ((2 + x + y)/4), `sphere` (1 − |P|),
//! `halo` (its square), `radial` (atan2(y, x)/2π + ½); `flipxy` swaps x and y.

use super::{BriCont, Params, TexResult};
use crate::texture::TextureError;
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BlendType {
    Lin,
    Quad,
    Ease,
    Diag,
    Sphere,
    Halo,
    Radial,
}

#[derive(Debug)]
pub struct Blend {
    pub kind: BlendType,
    pub flip: bool,
}

impl Blend {
    pub fn eval(&self, p: [f32; 3], bc: &BriCont) -> TexResult {
        let (x, y) = if self.flip {
            (p[1], p[0])
        } else {
            (p[0], p[1])
        };
        let tin = match self.kind {
            BlendType::Lin => (1.0 + x) / 2.0,
            BlendType::Quad => {
                let t = (1.0 + x) / 2.0;
                if t < 0.0 {
                    0.0
                } else {
                    t * t
                }
            }
            BlendType::Ease => {
                let t = (1.0 + x) / 2.0;
                if t <= 0.0 {
                    0.0
                } else if t >= 1.0 {
                    1.0
                } else {
                    let t2 = t * t;
                    3.0 * t2 - 2.0 * t2 * t
                }
            }
            BlendType::Diag => (2.0 + x + y) / 4.0,
            BlendType::Radial => y.atan2(x) / (2.0 * PI) + 0.5,
            BlendType::Sphere | BlendType::Halo => {
                let t = (1.0 - (x * x + y * y + p[2] * p[2]).sqrt()).max(0.0);
                if self.kind == BlendType::Halo {
                    t * t
                } else {
                    t
                }
            }
        };
        TexResult::int(bc.int(tin))
    }
}

pub fn build(p: &mut Params) -> Result<Blend, TextureError> {
    let kind = p.choice("type", None, ("lin", BlendType::Lin), |s| {
        Some(match s {
            "lin" => BlendType::Lin,
            "quad" => BlendType::Quad,
            "ease" => BlendType::Ease,
            "diag" => BlendType::Diag,
            "sphere" => BlendType::Sphere,
            "halo" => BlendType::Halo,
            "radial" => BlendType::Radial,
            _ => return None,
        })
    });
    let flip = p.t.entity.params.bool_or("flipxy", false);
    Ok(Blend { kind, flip })
}
