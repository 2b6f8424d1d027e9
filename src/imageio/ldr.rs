//! Low dynamic range outputs (PNG, TGA) from display values in [0, 1].

use crate::film::flm::write_atomic;
use crate::film::{Channels, FilmError};
use crate::tonemap::{quantize16, quantize8};
use image::{ExtendedColorType, ImageEncoder};
use std::path::Path;

/// Display-ready pixels (clamped, gamma applied) and the gray values for Y outputs.
pub struct LdrImage<'a> {
    pub width: u32,
    pub height: u32,
    pub rgb: &'a [[f32; 3]],
    /// Gray (luminance, display encoded) per pixel, for Y and YA channel sets.
    pub gray: &'a [f32],
    pub alpha: &'a [f32],
}

fn samples8(img: &LdrImage, ch: Channels) -> Vec<u8> {
    let mut out = Vec::with_capacity(img.rgb.len() * 4);
    for i in 0..img.rgb.len() {
        let a = img.alpha.get(i).copied().unwrap_or(1.0);
        let g = img.gray.get(i).copied().unwrap_or(0.0);
        match ch {
            Channels::Y => out.push(quantize8(g)),
            Channels::Ya => out.extend([quantize8(g), quantize8(a)]),
            Channels::Rgb => out.extend(img.rgb[i].map(quantize8)),
            Channels::Rgba => {
                out.extend(img.rgb[i].map(quantize8));
                out.push(quantize8(a));
            }
        }
    }
    out
}

fn samples16(img: &LdrImage, ch: Channels) -> Vec<u8> {
    let mut v: Vec<u16> = Vec::with_capacity(img.rgb.len() * 4);
    for i in 0..img.rgb.len() {
        let a = img.alpha.get(i).copied().unwrap_or(1.0);
        let g = img.gray.get(i).copied().unwrap_or(0.0);
        match ch {
            Channels::Y => v.push(quantize16(g)),
            Channels::Ya => v.extend([quantize16(g), quantize16(a)]),
            Channels::Rgb => v.extend(img.rgb[i].map(quantize16)),
            Channels::Rgba => {
                v.extend(img.rgb[i].map(quantize16));
                v.push(quantize16(a));
            }
        }
    }
    // PNG stores 16-bit samples big-endian; the encoder takes native order.
    v.iter().flat_map(|s| s.to_ne_bytes()).collect()
}

fn color_type(ch: Channels, bit16: bool) -> ExtendedColorType {
    match (ch, bit16) {
        (Channels::Y, false) => ExtendedColorType::L8,
        (Channels::Ya, false) => ExtendedColorType::La8,
        (Channels::Rgb, false) => ExtendedColorType::Rgb8,
        (Channels::Rgba, false) => ExtendedColorType::Rgba8,
        (Channels::Y, true) => ExtendedColorType::L16,
        (Channels::Ya, true) => ExtendedColorType::La16,
        (Channels::Rgb, true) => ExtendedColorType::Rgb16,
        (Channels::Rgba, true) => ExtendedColorType::Rgba16,
    }
}

fn image_err(path: &Path, e: impl std::fmt::Display) -> FilmError {
    FilmError::Image {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Writes a PNG with the channel set, 8 or 16 bits per sample.
pub fn write_png(path: &Path, img: &LdrImage, ch: Channels, bit16: bool) -> Result<(), FilmError> {
    let data = if bit16 {
        samples16(img, ch)
    } else {
        samples8(img, ch)
    };
    write_atomic(path, |w| {
        image::codecs::png::PngEncoder::new(w)
            .write_image(&data, img.width, img.height, color_type(ch, bit16))
            .map_err(|e| image_err(path, e))
    })
}

/// Writes a TGA (Y, RGB or RGBA, 8 bits).
pub fn write_tga(path: &Path, img: &LdrImage, ch: Channels) -> Result<(), FilmError> {
    if ch == Channels::Ya {
        return Err(image_err(path, "TGA output has no YA channel set"));
    }
    let data = samples8(img, ch);
    write_atomic(path, |w| {
        image::codecs::tga::TgaEncoder::new(w)
            .write_image(&data, img.width, img.height, color_type(ch, false))
            .map_err(|e| image_err(path, e))
    })
}
