//! The outputs a Film statement asks for: tonemapped PNG and TGA, OpenEXR (tonemapped or
//! not, `write_exr_applyimaging`), and the resume FLM; and resuming from a resume FLM.
//!
//! File names are `BASENAME.png`, `.tga`, `.exr`, `.flm` where BASENAME is the film's
//! `filename` parameter (or what the caller passes). Every file is written atomically.

use super::flm::{merge_flm, write_flm_file};
use super::{Film, FilmError, FilmParams};
use crate::imageio::{self, ExrImage, LdrImage};
use crate::tonemap::{self, ColorSystem, RgbImage};
use std::fs::File;
use std::path::{Path, PathBuf};

fn with_ext(base: &Path, ext: &str) -> PathBuf {
    let mut s = base.as_os_str().to_os_string();
    s.push(ext);
    PathBuf::from(s)
}

/// Writes every output the parameters enable; returns the files written. Z buffer
/// channels need per-pixel depths, which a `Film` does not carry: see
/// [`write_outputs_with_z`].
pub fn write_outputs(
    film: &Film,
    params: &FilmParams,
    basename: &Path,
) -> Result<Vec<PathBuf>, FilmError> {
    write_outputs_with_z(film, params, basename, None)
}

/// As [`write_outputs`], with an optional Z buffer (depth per buffer pixel) for the
/// `write_*_ZBuf` channels. A Z channel asked for without depths is left out with a warning.
pub fn write_outputs_with_z(
    film: &Film,
    params: &FilmParams,
    basename: &Path,
    z: Option<&[f32]>,
) -> Result<Vec<PathBuf>, FilmError> {
    let mut written = Vec::new();
    let z = z.filter(|z| z.len() == film.pixel_count());
    if params.wants_zbuf() && z.is_none() {
        tracing::warn!("a Z buffer output is enabled but no depth buffer is available: omitted");
    }
    if params.exr.enabled {
        let path = with_ext(basename, ".exr");
        write_exr_output(film, params, &path, z)?;
        written.push(path);
    }
    if params.png.enabled || params.tga.enabled {
        let tp = &params.tonemap;
        let mut img = tonemap::tonemap(film, tp);
        tonemap::to_display(&mut img, tp);
        let gray = display_gray(&img, tp);
        let ldr = LdrImage {
            width: img.width,
            height: img.height,
            rgb: &img.rgb,
            gray: &gray,
            alpha: &img.alpha,
        };
        if params.png.enabled {
            let path = with_ext(basename, ".png");
            imageio::write_png(&path, &ldr, params.png.channels, params.png_16bit)?;
            written.push(path);
        }
        if params.tga.enabled {
            let path = with_ext(basename, ".tga");
            imageio::write_tga(&path, &ldr, params.tga.channels)?;
            written.push(path);
        }
    }
    if params.write_resume_flm {
        let path = with_ext(basename, ".flm");
        write_flm_file(&path, film, params)?;
        written.push(path);
    }
    Ok(written)
}

/// Gray values of a display image: the luminance of the linear colour, display encoded.
fn display_gray(img: &RgbImage, tp: &tonemap::TonemapParams) -> Vec<f32> {
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

/// Writes the EXR output: tonemapped linear RGB with `write_exr_applyimaging`, else the
/// film's RGB; colours premultiplied by alpha when an alpha channel is written (unless the
/// film already premultiplies or `write_exr_straightcolors`).
pub fn write_exr_output(
    film: &Film,
    params: &FilmParams,
    path: &Path,
    z: Option<&[f32]>,
) -> Result<(), FilmError> {
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
        ch,
        params.exr_options.halftype,
        params.exr_options.compression,
    )
}

/// At the start of a render, as LuxRender: with `write_resume_flm` and
/// `restart_resume_flm`, an existing `BASENAME.flm` is moved to `BASENAME.flm1` and the
/// render starts afresh; without `restart_resume_flm`, an existing `BASENAME.flm` is merged
/// into `film` (it must match its layout). Returns the FLM resumed from, if any.
pub fn resume(
    film: &mut Film,
    params: &FilmParams,
    basename: &Path,
) -> Result<Option<PathBuf>, FilmError> {
    if !params.write_resume_flm {
        return Ok(None);
    }
    let path = with_ext(basename, ".flm");
    if !path.exists() {
        return Ok(None);
    }
    if params.restart_resume_flm {
        let old = with_ext(basename, ".flm1");
        std::fs::rename(&path, &old).map_err(|e| FilmError::file(&path, e))?;
        tracing::info!("previous resume film kept as {}", old.display());
        return Ok(None);
    }
    let f = File::open(&path).map_err(|e| FilmError::file(&path, e))?;
    merge_flm(film, std::io::BufReader::new(f))?;
    tracing::info!("resumed from {} ({:.2} spp)", path.display(), film.spp());
    Ok(Some(path))
}
