//! Low dynamic range encoders (PNG 8/16 bit, TGA 8 bit) from display values in [0, 1], with
//! LuxRender's quantisation (truncation of 255 v or 65535 v), and the downscaled 8-bit RGB
//! PNG the master serves as a preview.

use super::{ChannelSet, ImageError};
use crate::atomic_write::write_atomic;
use image::{ExtendedColorType, ImageEncoder};
use std::io::Write;
use std::path::Path;

/// Display-ready pixels (clamped, gamma applied) and the gray values for Y outputs, row by
/// row, top row first.
pub struct LdrImage<'a> {
    pub width: u32,
    pub height: u32,
    pub rgb: &'a [[f32; 3]],
    /// Gray (luminance, display encoded) per pixel, for Y and YA channel sets.
    pub gray: &'a [f32],
    pub alpha: &'a [f32],
}

/// 8-bit quantisation as LuxRender writes LDR files: truncate(255 * v), clamped.
pub fn quantize8(v: f32) -> u8 {
    (255.0 * v).clamp(0.0, 255.0) as u8
}

/// 16-bit quantisation: truncate(65535 * v), clamped.
pub fn quantize16(v: f32) -> u16 {
    (65535.0 * v).clamp(0.0, 65535.0) as u16
}

/// The samples of every pixel in the channel set's order, quantised by `q`.
fn samples<T>(img: &LdrImage, ch: ChannelSet, q: impl Fn(f32) -> T) -> Vec<T> {
    let mut out = Vec::with_capacity(img.rgb.len() * 4);
    for (i, rgb) in img.rgb.iter().enumerate() {
        let a = img.alpha.get(i).copied().unwrap_or(1.0);
        let g = img.gray.get(i).copied().unwrap_or(0.0);
        match ch {
            ChannelSet::Y => out.push(q(g)),
            ChannelSet::Ya => out.extend([q(g), q(a)]),
            ChannelSet::Rgb => out.extend(rgb.map(&q)),
            ChannelSet::Rgba => {
                out.extend(rgb.map(&q));
                out.push(q(a));
            }
        }
    }
    out
}

fn samples8(img: &LdrImage, ch: ChannelSet) -> Vec<u8> {
    samples(img, ch, quantize8)
}

fn samples16(img: &LdrImage, ch: ChannelSet) -> Vec<u8> {
    // PNG stores 16-bit samples big-endian; the encoder takes native order.
    samples(img, ch, quantize16)
        .iter()
        .flat_map(|s| s.to_ne_bytes())
        .collect()
}

fn color_type(ch: ChannelSet, bit16: bool) -> ExtendedColorType {
    match (ch, bit16) {
        (ChannelSet::Y, false) => ExtendedColorType::L8,
        (ChannelSet::Ya, false) => ExtendedColorType::La8,
        (ChannelSet::Rgb, false) => ExtendedColorType::Rgb8,
        (ChannelSet::Rgba, false) => ExtendedColorType::Rgba8,
        (ChannelSet::Y, true) => ExtendedColorType::L16,
        (ChannelSet::Ya, true) => ExtendedColorType::La16,
        (ChannelSet::Rgb, true) => ExtendedColorType::Rgb16,
        (ChannelSet::Rgba, true) => ExtendedColorType::Rgba16,
    }
}

fn codec(e: impl std::fmt::Display) -> ImageError {
    ImageError::Codec(e.to_string())
}

/// The encoders panic on a buffer of the wrong size: refuse it first.
fn check_size(img: &LdrImage) -> Result<(), ImageError> {
    super::check_pixels(img.width, img.height, img.rgb.len()).map_err(codec)
}

/// Encodes a PNG with the channel set, 8 or 16 bits per sample.
pub fn encode_png(
    w: impl Write,
    img: &LdrImage,
    ch: ChannelSet,
    bit16: bool,
) -> Result<(), ImageError> {
    check_size(img)?;
    let data = if bit16 {
        samples16(img, ch)
    } else {
        samples8(img, ch)
    };
    image::codecs::png::PngEncoder::new(w)
        .write_image(&data, img.width, img.height, color_type(ch, bit16))
        .map_err(codec)
}

/// Encodes a TGA (Y, RGB or RGBA, 8 bits; TGA has no gray-alpha layout).
pub fn encode_tga(w: impl Write, img: &LdrImage, ch: ChannelSet) -> Result<(), ImageError> {
    if ch == ChannelSet::Ya {
        return Err(codec("TGA output has no YA channel set"));
    }
    check_size(img)?;
    let data = samples8(img, ch);
    image::codecs::tga::TgaEncoder::new(w)
        .write_image(&data, img.width, img.height, color_type(ch, false))
        .map_err(codec)
}

/// Encodes an 8-bit RGB PNG scaled down (triangle filter) so that its longer side is at most
/// `max_size` (0: full size), as the master serves previews.
pub fn encode_png_preview(w: impl Write, img: &LdrImage, max_size: u32) -> Result<(), ImageError> {
    check_size(img)?;
    let data = samples8(img, ChannelSet::Rgb);
    let mut rgb = image::RgbImage::from_raw(img.width, img.height, data)
        .ok_or_else(|| codec("pixel count does not match the image size"))?;
    let longest = img.width.max(img.height);
    if max_size > 0 && longest > max_size {
        let scale = f64::from(max_size) / f64::from(longest);
        let w = ((f64::from(img.width) * scale).round() as u32).max(1);
        let h = ((f64::from(img.height) * scale).round() as u32).max(1);
        rgb = image::imageops::resize(&rgb, w, h, image::imageops::FilterType::Triangle);
    }
    image::codecs::png::PngEncoder::new(w)
        .write_image(
            rgb.as_raw(),
            rgb.width(),
            rgb.height(),
            ExtendedColorType::Rgb8,
        )
        .map_err(codec)
}

/// Writes a PNG file atomically (see [`encode_png`]).
pub fn write_png(
    path: &Path,
    img: &LdrImage,
    ch: ChannelSet,
    bit16: bool,
) -> Result<(), ImageError> {
    write_atomic(path, |w| {
        encode_png(w, img, ch, bit16).map_err(|e| e.at(path))
    })
}

/// Writes a TGA file atomically (see [`encode_tga`]).
pub fn write_tga(path: &Path, img: &LdrImage, ch: ChannelSet) -> Result<(), ImageError> {
    write_atomic(path, |w| encode_tga(w, img, ch).map_err(|e| e.at(path)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(rgb: &[[f32; 3]], w: u32, h: u32) -> LdrImage<'_> {
        LdrImage {
            width: w,
            height: h,
            rgb,
            gray: &[],
            alpha: &[],
        }
    }

    #[test]
    fn quantisation_truncates_and_clamps() {
        assert_eq!(quantize8(1.0), 255);
        assert_eq!(quantize8(0.999), 254);
        assert_eq!(quantize8(-1.0), 0);
        assert_eq!(quantize8(f32::NAN), 0);
        assert_eq!(quantize16(2.0), 65535);
        assert_eq!(quantize16(0.5), 32767);
    }

    #[test]
    fn png_round_trips_and_preview_is_scaled() {
        let rgb: Vec<[f32; 3]> = (0..12).map(|i| [i as f32 / 11.0, 0.5, 1.0]).collect();
        let img = image(&rgb, 4, 3);
        let mut png = Vec::new();
        encode_png(&mut png, &img, ChannelSet::Rgb, false).unwrap();
        let back = image::load_from_memory(&png).unwrap().to_rgb8();
        assert_eq!((back.width(), back.height()), (4, 3));
        assert_eq!(back.get_pixel(3, 2).0, [255, 127, 255]);
        let mut small = Vec::new();
        encode_png_preview(&mut small, &img, 2).unwrap();
        let back = image::load_from_memory(&small).unwrap();
        assert_eq!((back.width(), back.height()), (2, 2));
    }

    #[test]
    fn mismatched_sizes_and_tga_ya_are_errors() {
        let rgb = [[0.0f32; 3]; 3];
        let mut out = Vec::new();
        assert!(encode_png(&mut out, &image(&rgb, 2, 2), ChannelSet::Rgb, false).is_err());
        assert!(encode_png_preview(&mut out, &image(&rgb, 2, 2), 1).is_err());
        let e = encode_tga(&mut out, &image(&rgb, 3, 1), ChannelSet::Ya).unwrap_err();
        assert!(e.to_string().contains("YA"), "{e}");
    }
}
