//! `imagemap` texture: an image over a 2D mapping. Parameters as LuxRender 1.x reads them:
//! `filename` (relative to the scene directory), `filtertype` (`bilinear` default, `nearest`,
//! `mipmap_trilinear`, `mipmap_ewa`; see [`super::mipmap`]), `maxanisotropy` (8),
//! `discardmipmaps` (0: finest levels dropped from the pyramid), `wrap` (`repeat` default,
//! `black`, `white`, `clamp`), `gain` (1), `gamma` (2.2) and, for float textures, `channel`
//! (`mean` default, `red`, `green`, `blue`, `alpha`, `colored_mean` = luminance Y). As in
//! LuxRender the value is `(gain · filtered)^gamma` (alpha is not raised to gamma), the float
//! channel being taken before gain and gamma. t = 0 is the top row of the image (Blender
//! exporters write `vscale -1` to flip their bottom-up v).
//!
//! The bump derivative is LuxRender's: the image's slope at (s, t)
//! ([`MipMap::differentials`], through gain and gamma) times the mapping's (s, t)
//! derivatives — so relief keeps its strength at any uscale/vscale.

use super::mapping::Mapping2D;
use super::mipmap::{FilterType, MipMap, Texel, Wrap};
use super::{param_loc, TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::{TextureDesc, TextureType};
use crate::spectrum::Rgb;
use glam::Vec2;
use std::sync::Arc;

pub const DEFAULT_GAMMA: f32 = 2.2;
pub const DEFAULT_MAX_ANISOTROPY: f32 = 8.0;

/// What a texel contributes: its colour, or one float channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Channel {
    Color,
    Mean,
    /// Luminance (LuxRender's `colored_mean`).
    WeightedMean,
    Red,
    Green,
    Blue,
    Alpha,
}

impl Channel {
    /// The float value of a texel (colour textures: the mean, as LuxRender's `Filter`).
    pub fn of(self, t: Texel) -> f32 {
        match self {
            Channel::Color | Channel::Mean => (t[0] + t[1] + t[2]) / 3.0,
            Channel::WeightedMean => 0.212_671 * t[0] + 0.715_160 * t[1] + 0.072_169 * t[2],
            Channel::Red => t[0],
            Channel::Green => t[1],
            Channel::Blue => t[2],
            Channel::Alpha => t[3],
        }
    }
}

/// An image lookup with LuxRender's gain and gamma.
#[derive(Debug)]
pub struct ImageLookup {
    pub map: Arc<MipMap>,
    pub gain: f32,
    pub gamma: f32,
    pub channel: Channel,
}

impl ImageLookup {
    #[inline]
    fn tone(&self, v: f32) -> f32 {
        let g = self.gain * v;
        if self.gamma == 1.0 {
            g
        } else {
            g.max(0.0).powf(self.gamma)
        }
    }

    /// The value at (s, t).
    pub fn lookup(&self, st: Vec2) -> Rgb {
        let t = self.map.lookup(st.x, st.y);
        match self.channel {
            Channel::Color => Rgb::new(self.tone(t[0]), self.tone(t[1]), self.tone(t[2])),
            c => Rgb::splat(self.tone(c.of(t))),
        }
    }

    /// The slope of the float value at (s, t) (LuxRender's `GetDifferentials` with gain and
    /// gamma).
    pub fn slope(&self, st: Vec2) -> Vec2 {
        let ch = self.channel;
        let (ds, dt) = self.map.differentials(st.x, st.y, |t| ch.of(t));
        let mut d = Vec2::new(ds, dt) * self.gain;
        if self.gamma != 1.0 {
            let raw = ch.of(self.map.lookup(st.x, st.y));
            d *= self.gamma * raw.max(0.0).powf(self.gamma - 1.0);
        }
        if d.is_finite() {
            d
        } else {
            Vec2::ZERO
        }
    }
}

#[derive(Debug)]
pub struct ImageTex {
    pub image: ImageLookup,
    pub mapping: Mapping2D,
}

impl ImageTex {
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        self.image.lookup(self.mapping.map(si))
    }

    pub fn duv(&self, si: &SurfaceInteraction) -> Vec2 {
        let m = self.mapping.map_duv(si);
        let d = self.image.slope(m.st);
        Vec2::new(d.dot(m.d_du), d.dot(m.d_dv))
    }
}

/// The image of an `imagemap` or `normalmap` statement: file, filter, wrap, gain, gamma and
/// channel read from its parameters (`default_gamma` differs between the two).
pub fn image_lookup(
    set: &mut TextureSet,
    t: &TextureDesc,
    default_gamma: f32,
    channel: Channel,
) -> Result<ImageLookup, TextureError> {
    let p = &t.entity.params;
    let loc = &t.entity.loc;
    let Some(name) = p.string("filename").map(str::to_string) else {
        return Err(TextureError::BadParam {
            loc: loc.clone(),
            message: format!("{} needs a \"string filename\"", t.entity.kind),
        });
    };
    let gamma = p.float_or("gamma", default_gamma);
    let gain = p.float_or("gain", 1.0);
    if !(gamma.is_finite() && gain.is_finite()) {
        return Err(TextureError::param(
            t,
            "gamma",
            "gain and gamma must be finite",
        ));
    }
    let filter = match p.string_or("filtertype", "bilinear") {
        "bilinear" => FilterType::Bilinear,
        "nearest" => FilterType::Nearest,
        "mipmap_trilinear" => FilterType::Trilinear,
        "mipmap_ewa" | "ewa" => FilterType::Ewa,
        other => {
            let other = other.to_string();
            set.warn(
                &param_loc(p, "filtertype", loc),
                format!(
                    "unknown filtertype \"{other}\" (bilinear, nearest, mipmap_trilinear, \
                     mipmap_ewa): bilinear, as LuxRender uses"
                ),
            );
            FilterType::Bilinear
        }
    };
    // The 0.x option that chose trilinear over EWA.
    let filter = match (filter, p.bool("trilinear")) {
        (FilterType::Ewa, Some(true)) => FilterType::Trilinear,
        (f, _) => f,
    };
    let max_aniso = p.float_or("maxanisotropy", DEFAULT_MAX_ANISOTROPY);
    if !(max_aniso.is_finite() && max_aniso > 0.0) {
        return Err(TextureError::param(
            t,
            "maxanisotropy",
            format!("maxanisotropy must be positive, got {max_aniso}"),
        ));
    }
    let discard = p.int_or("discardmipmaps", 0).clamp(0, 64) as usize;
    // LuxRender 0.x spelled the black wrap mode "black"; "zero" is accepted too.
    let wrap = match p.string_or("wrap", "repeat") {
        "repeat" => Wrap::Repeat,
        "black" | "zero" => Wrap::Black,
        "white" => Wrap::White,
        "clamp" => Wrap::Clamp,
        other => {
            return Err(TextureError::BadParam {
                loc: param_loc(p, "wrap", loc),
                message: format!("unknown wrap \"{other}\" (repeat, black, white, clamp)"),
            })
        }
    };
    let map = set
        .images
        .mipmap(&set.ctx.files, &name, filter, wrap, max_aniso, discard)
        .map_err(|message| TextureError::Image {
            loc: param_loc(p, "filename", loc),
            path: name.clone(),
            message,
        })?;
    Ok(ImageLookup {
        map,
        gain,
        gamma,
        channel,
    })
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let p = &t.entity.params;
    let channel = match t.value_type {
        TextureType::Float => match p.string_or("channel", "mean") {
            "mean" => Channel::Mean,
            "colored_mean" => Channel::WeightedMean,
            "red" => Channel::Red,
            "green" => Channel::Green,
            "blue" => Channel::Blue,
            "alpha" => Channel::Alpha,
            other => {
                return Err(TextureError::BadParam {
                    loc: param_loc(p, "channel", &t.entity.loc),
                    message: format!(
                        "unknown imagemap channel \"{other}\" (mean, colored_mean, red, green, \
                         blue, alpha)"
                    ),
                })
            }
        },
        _ => Channel::Color,
    };
    let image = image_lookup(set, t, DEFAULT_GAMMA, channel)?;
    Ok(TexNode::Image(ImageTex {
        image,
        mapping: Mapping2D::from_params(t)?,
    }))
}
