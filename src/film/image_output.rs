//! The settings of the Film's image outputs (PNG, TGA, OpenEXR): channel sets, Z-buffer
//! normalisation and EXR compression, with the option names LuxRender's fleximage uses (see
//! [`super::params`], which parses them). Plain data: the `output` module reads them and maps
//! them onto the encoders' own option types in the `imageio` module.

/// Channels of an image output (`write_*_channels`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Channels {
    Y,
    Ya,
    Rgb,
    Rgba,
}

impl Channels {
    pub fn from_name(s: &str) -> Option<Channels> {
        Some(match s {
            "Y" => Channels::Y,
            "YA" => Channels::Ya,
            "RGB" => Channels::Rgb,
            "RGBA" => Channels::Rgba,
            _ => return None,
        })
    }

    pub fn has_alpha(self) -> bool {
        matches!(self, Channels::Ya | Channels::Rgba)
    }

    pub fn is_gray(self) -> bool {
        matches!(self, Channels::Y | Channels::Ya)
    }

    /// The same set with an alpha channel (premultiplied alpha forces one, as LuxRender).
    pub fn with_alpha(self) -> Channels {
        match self {
            Channels::Y | Channels::Ya => Channels::Ya,
            Channels::Rgb | Channels::Rgba => Channels::Rgba,
        }
    }
}

/// Normalisation of a Z buffer output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ZBufNorm {
    None,
    CameraStartEnd,
    MinMax,
}

impl ZBufNorm {
    pub fn from_name(s: &str) -> Option<ZBufNorm> {
        Some(match s {
            "None" => ZBufNorm::None,
            "Camera Start/End clip" => ZBufNorm::CameraStartEnd,
            "Min/Max" => ZBufNorm::MinMax,
            _ => return None,
        })
    }
}

/// OpenEXR compression (`write_exr_compressiontype`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExrCompression {
    Rle,
    Piz,
    Zip,
    Pxr24,
    None,
}

impl ExrCompression {
    pub fn from_name(s: &str) -> Option<ExrCompression> {
        Some(match s {
            "RLE (lossless)" => ExrCompression::Rle,
            "PIZ (lossless)" => ExrCompression::Piz,
            "ZIP (lossless)" => ExrCompression::Zip,
            "Pxr24 (lossy)" => ExrCompression::Pxr24,
            "None" => ExrCompression::None,
            _ => return None,
        })
    }
}

/// One image output format's settings.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageOutput {
    pub enabled: bool,
    pub channels: Channels,
    pub gamutclamp: bool,
    pub zbuf: bool,
    pub zbuf_norm: ZBufNorm,
}

/// OpenEXR settings beyond [`ImageOutput`].
#[derive(Clone, Debug, PartialEq)]
pub struct ExrOptions {
    pub halftype: bool,
    pub compression: ExrCompression,
    pub applyimaging: bool,
    pub straightcolors: bool,
}
