//! `imagemap` texture: `filename` (relative to the scene directory), `gamma` (default 2.2),
//! `gain` (default 1), `filtertype` (`bilinear` default, `nearest`; `mipmap_trilinear`,
//! `mipmap_ewa` and `ewa` fall back to bilinear with a warning), `wrap` (`repeat` default,
//! `black`, `clamp`), `channel` for float textures (`mean` default, `red`, `green`, `blue`,
//! `alpha`, `colored_mean`) and a 2D mapping. t = 0 is the top row of the image, as in
//! LuxRender (Blender exporters write `vscale -1` to flip their bottom-up v).

use super::image_io::ImageData;
use super::mapping::Mapping2D;
use super::{param_loc, TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::{TextureDesc, TextureType};
use crate::spectrum::Rgb;
use glam::Vec2;
use std::sync::Arc;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    Bilinear,
    Nearest,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrap {
    Repeat,
    Black,
    Clamp,
}

/// What a texel contributes: its colour, or one float channel (splatted).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Channel {
    Color,
    Mean,
    Red,
    Green,
    Blue,
    Alpha,
}

#[derive(Debug)]
pub struct ImageTex {
    pub image: Arc<ImageData>,
    pub mapping: Mapping2D,
    pub filter: Filter,
    pub wrap: Wrap,
    pub gain: f32,
    pub channel: Channel,
}

impl ImageTex {
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        let st = self.mapping.map(si);
        self.lookup(st)
    }

    /// Filtered value at texture coordinates (s, t).
    pub fn lookup(&self, st: Vec2) -> Rgb {
        let (w, h) = (self.image.width as f32, self.image.height as f32);
        let x = st.x * w - 0.5;
        let y = st.y * h - 0.5;
        let t = match self.filter {
            Filter::Nearest => self.texel((x + 0.5).floor() as i64, (y + 0.5).floor() as i64),
            Filter::Bilinear => {
                let (x0, y0) = (x.floor(), y.floor());
                let (fx, fy) = (x - x0, y - y0);
                let (x0, y0) = (x0 as i64, y0 as i64);
                let mut acc = [0.0f32; 4];
                for (dx, dy, wgt) in [
                    (0, 0, (1.0 - fx) * (1.0 - fy)),
                    (1, 0, fx * (1.0 - fy)),
                    (0, 1, (1.0 - fx) * fy),
                    (1, 1, fx * fy),
                ] {
                    let v = self.texel(x0 + dx, y0 + dy);
                    for i in 0..4 {
                        acc[i] += v[i] * wgt;
                    }
                }
                acc
            }
        };
        self.value(t) * self.gain
    }

    fn value(&self, t: [f32; 4]) -> Rgb {
        match self.channel {
            Channel::Color => Rgb::new(t[0], t[1], t[2]),
            Channel::Mean => Rgb::splat((t[0] + t[1] + t[2]) / 3.0),
            Channel::Red => Rgb::splat(t[0]),
            Channel::Green => Rgb::splat(t[1]),
            Channel::Blue => Rgb::splat(t[2]),
            Channel::Alpha => Rgb::splat(t[3]),
        }
    }

    fn texel(&self, x: i64, y: i64) -> [f32; 4] {
        let (w, h) = (self.image.width as i64, self.image.height as i64);
        let (x, y) = match self.wrap {
            Wrap::Repeat => (x.rem_euclid(w), y.rem_euclid(h)),
            Wrap::Clamp => (x.clamp(0, w - 1), y.clamp(0, h - 1)),
            Wrap::Black => {
                if x < 0 || y < 0 || x >= w || y >= h {
                    return [0.0; 4];
                }
                (x, y)
            }
        };
        self.image.texel(x as usize, y as usize)
    }
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let p = &t.entity.params;
    let loc = &t.entity.loc;
    let Some(name) = p.string("filename").map(str::to_string) else {
        return Err(TextureError::BadParam {
            loc: loc.clone(),
            message: "imagemap needs a \"string filename\"".into(),
        });
    };
    let gamma = p.float_or("gamma", 2.2);
    let gain = p.float_or("gain", 1.0);
    let filter = match p.string_or("filtertype", "bilinear") {
        "bilinear" => Filter::Bilinear,
        "nearest" => Filter::Nearest,
        other => {
            let other = other.to_string();
            set.warn(
                &param_loc(p, "filtertype", loc),
                format!("imagemap filtertype \"{other}\" is not supported: using bilinear"),
            );
            Filter::Bilinear
        }
    };
    // LuxRender 0.x spelled the black wrap mode "black"; "zero" is accepted too.
    let wrap = match p.string_or("wrap", "repeat") {
        "repeat" => Wrap::Repeat,
        "black" | "zero" => Wrap::Black,
        "clamp" => Wrap::Clamp,
        other => {
            return Err(TextureError::BadParam {
                loc: param_loc(p, "wrap", loc),
                message: format!("unknown imagemap wrap \"{other}\" (repeat, black, clamp)"),
            })
        }
    };
    let channel = match t.value_type {
        TextureType::Color => Channel::Color,
        TextureType::Float => match p.string_or("channel", "mean") {
            "mean" | "colored_mean" => Channel::Mean,
            "red" => Channel::Red,
            "green" => Channel::Green,
            "blue" => Channel::Blue,
            "alpha" => Channel::Alpha,
            other => {
                return Err(TextureError::BadParam {
                    loc: param_loc(p, "channel", loc),
                    message: format!("unknown imagemap channel \"{other}\""),
                })
            }
        },
    };
    let mapping = Mapping2D::from_params(t)?;
    let image = set
        .images
        .get(&set.ctx.files, &name, gamma)
        .map_err(|message| TextureError::Image {
            loc: param_loc(p, "filename", loc),
            path: name.clone(),
            message,
        })?;
    Ok(TexNode::Image(ImageTex {
        image,
        mapping,
        filter,
        wrap,
        gain,
        channel,
    }))
}
