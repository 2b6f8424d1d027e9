//! From a film to the pixel buffers the encoders take, as the Film's settings ask: the display
//! image of PNG and TGA (tonemapped, LDR clamp, gamma; gray as display-encoded luminance), the
//! linear image of EXR (tonemapped with `write_exr_applyimaging`, else the film's RGB;
//! premultiplied by alpha unless the film already is or `write_exr_straightcolors`), and the
//! two images the master serves from memory (an 8-bit preview PNG and a float linear EXR).
//!
//! Here the film layer's option types (`film::Channels`, `film::ExrCompression`) are mapped
//! onto the encoders' own (`imageio::ChannelSet`, `imageio::ExrCompression`).

use super::OutputError;
use crate::film::{Channels, ExrCompression, Film, FilmParams};
use crate::imageio::{self, ChannelSet, ExrImage, LdrImage};
use crate::tonemap::{self, ColorSystem, RgbImage, TonemapParams};
use std::path::Path;

fn channel_set(c: Channels) -> ChannelSet {
    match c {
        Channels::Y => ChannelSet::Y,
        Channels::Ya => ChannelSet::Ya,
        Channels::Rgb => ChannelSet::Rgb,
        Channels::Rgba => ChannelSet::Rgba,
    }
}

fn exr_compression(c: ExrCompression) -> imageio::ExrCompression {
    match c {
        ExrCompression::Rle => imageio::ExrCompression::Rle,
        ExrCompression::Piz => imageio::ExrCompression::Piz,
        ExrCompression::Zip => imageio::ExrCompression::Zip,
        ExrCompression::Pxr24 => imageio::ExrCompression::Pxr24,
        ExrCompression::None => imageio::ExrCompression::None,
    }
}

/// The display image of the LDR outputs, made once for PNG and TGA.
pub struct Display {
    img: RgbImage,
    gray: Vec<f32>,
}

impl Display {
    /// Tonemaps the film, clamps and applies the gamma; gray values alongside.
    pub fn new(film: &Film, tp: &TonemapParams) -> Display {
        let mut img = tonemap::tonemap(film, tp);
        tonemap::to_display(&mut img, tp);
        let gray = display_gray(&img, tp);
        Display { img, gray }
    }

    fn ldr(&self) -> LdrImage<'_> {
        LdrImage {
            width: self.img.width,
            height: self.img.height,
            rgb: &self.img.rgb,
            gray: &self.gray,
            alpha: &self.img.alpha,
        }
    }
}

/// Gray values of a display image: the luminance of the linear colour, display encoded.
fn display_gray(img: &RgbImage, tp: &TonemapParams) -> Vec<f32> {
    let cs = ColorSystem::new(&tp.colorspace);
    let g = tp.gamma;
    img.rgb
        .iter()
        .map(|p| {
            let lin = p.map(|c| c.max(0.0).powf(g));
            cs.luminance(lin).clamp(0.0, 1.0).powf(1.0 / g)
        })
        .collect()
}

/// Writes the PNG output (`write_png_channels`, `write_png_16bit`).
pub fn write_png(d: &Display, params: &FilmParams, path: &Path) -> Result<(), OutputError> {
    let ch = channel_set(params.png.channels);
    imageio::write_png(path, &d.ldr(), ch, params.png_16bit)?;
    Ok(())
}

/// Writes the TGA output (`write_tga_channels`).
pub fn write_tga(d: &Display, params: &FilmParams, path: &Path) -> Result<(), OutputError> {
    imageio::write_tga(path, &d.ldr(), channel_set(params.tga.channels))?;
    Ok(())
}

/// Writes the EXR output with the Film's channels, sample type and compression, and the Z
/// buffer when given and `write_exr_ZBuf` asks for it.
pub fn write_exr(
    film: &Film,
    params: &FilmParams,
    path: &Path,
    z: Option<&[f32]>,
) -> Result<(), OutputError> {
    let tp = &params.tonemap;
    let mut img = if params.exr_options.applyimaging {
        tonemap::tonemap(film, tp)
    } else {
        tonemap::untonemapped(film, tp)
    };
    let ch = params.exr.channels;
    if ch.has_alpha() && !params.premultiply_alpha && !params.exr_options.straightcolors {
        for (p, &a) in img.rgb.iter_mut().zip(&img.alpha) {
            *p = p.map(|c| c * a);
        }
    }
    let cs = ColorSystem::new(&tp.colorspace);
    let gray: Vec<f32> = img.rgb.iter().map(|&p| cs.luminance(p)).collect();
    let z = if params.exr.zbuf { z } else { None };
    let exr = ExrImage {
        width: img.width,
        height: img.height,
        rgb: &img.rgb,
        gray: &gray,
        alpha: &img.alpha,
        z,
    };
    imageio::write_exr(
        path,
        &exr,
        channel_set(ch),
        params.exr_options.halftype,
        exr_compression(params.exr_options.compression),
    )?;
    Ok(())
}

/// An 8-bit RGB PNG of the film's display image, scaled down so that its longer side is at
/// most `max_size` (the master's previews and `image.png`).
pub fn preview_png(
    film: &Film,
    tp: &TonemapParams,
    max_size: Option<u32>,
) -> Result<Vec<u8>, OutputError> {
    let img = tonemap::tonemap_display(film, tp);
    let ldr = LdrImage {
        width: img.width,
        height: img.height,
        rgb: &img.rgb,
        gray: &[],
        alpha: &img.alpha,
    };
    let mut out = Vec::new();
    imageio::encode_png_preview(&mut out, &ldr, max_size.unwrap_or(0))?;
    Ok(out)
}

/// A float RGB EXR of the film's linear, untonemapped colours (the master's `film.exr`).
pub fn linear_exr(film: &Film, tp: &TonemapParams) -> Result<Vec<u8>, OutputError> {
    let img = tonemap::untonemapped(film, tp);
    let exr = ExrImage {
        width: img.width,
        height: img.height,
        rgb: &img.rgb,
        gray: &[],
        alpha: &img.alpha,
        z: None,
    };
    let mut out = std::io::Cursor::new(Vec::new());
    imageio::encode_exr(
        &mut out,
        &exr,
        ChannelSet::Rgb,
        false,
        imageio::ExrCompression::Rle,
    )?;
    Ok(out.into_inner())
}
