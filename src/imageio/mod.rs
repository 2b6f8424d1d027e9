//! Image encoding, the leaf of the back end: PNG (8/16 bit), TGA and OpenEXR (half/float)
//! from plain pixel buffers, with LuxRender's channel sets (Y, YA, RGB, RGBA) and its LDR
//! quantisation.
//!
//! The data comes in already imaged: display values in [0, 1] for PNG/TGA ([`LdrImage`]),
//! linear values for EXR ([`ExrImage`]); the `output` module prepares them from a film through
//! the `tonemap` module. This module imports neither the film nor the tonemapper, only its own
//! option types ([`ChannelSet`], [`ExrCompression`]) and the atomic file write every writer
//! shares ([`crate::atomic_write`]). Each format has an encoder into any writer (the master
//! serves images from memory) and a file writer that writes atomically.

pub mod exr;
pub mod ldr;

pub use self::exr::{encode_exr, write_exr, ExrCompression, ExrImage};
pub use ldr::{
    encode_png, encode_png_preview, encode_tga, quantize16, quantize8, write_png, write_tga,
    LdrImage,
};

use crate::atomic_write::FileError;
use std::path::{Path, PathBuf};

/// The channels an image file holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ChannelSet {
    /// Gray (luminance).
    Y,
    /// Gray and alpha.
    Ya,
    Rgb,
    Rgba,
}

impl ChannelSet {
    pub fn has_alpha(self) -> bool {
        matches!(self, ChannelSet::Ya | ChannelSet::Rgba)
    }

    pub fn is_gray(self) -> bool {
        matches!(self, ChannelSet::Y | ChannelSet::Ya)
    }
}

/// Everything that can go wrong while encoding or writing an image.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// The encoder refused the image (written to a file).
    #[error("image output failed for {path}: {message}")]
    Encode { path: PathBuf, message: String },
    /// The encoder refused the image (encoded in memory).
    #[error("image encoding failed: {0}")]
    Codec(String),
    #[error(transparent)]
    File(#[from] FileError),
}

impl ImageError {
    /// The error of an encoder as the error of writing the file `path`.
    fn at(self, path: &Path) -> ImageError {
        match self {
            ImageError::Codec(message) => ImageError::Encode {
                path: path.to_path_buf(),
                message,
            },
            other => other,
        }
    }
}

/// Refuses a pixel buffer whose length is not width x height (the encoders would panic)
/// and an empty image.
fn check_pixels(width: u32, height: u32, len: usize) -> Result<(), String> {
    let expected = u64::from(width) * u64::from(height);
    if expected == 0 || expected != len as u64 {
        return Err(format!("{len} pixels for a {width}x{height} image"));
    }
    Ok(())
}
