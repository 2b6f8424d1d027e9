//! `luxfarm compare-image A.exr B.exr`: RMSE, relative MSE and mean ratio of two images of
//! the same size (linear RGB; B is the reference). Either side may be an FLM: its
//! weight-normalised XYZ is turned back into the renderer's linear RGB (the inverse of
//! `spectrum::rgb_to_xyz`), without any tonemapping — LuxRender's EXR output is tonemapped by
//! default (`write_exr_applyimaging`), so an FLM is the faithful linear source.
//! `--exclude-above V` leaves out pixels where the reference exceeds V (visible emitters).
//!
//! `--shift-rows N` compares A's row `y - N` with B's row `y` (rows without a partner are left
//! out). Pixel conventions differ between renderers: LuxRender (and luxfarm) map image row `y`
//! to raster rows `[y, y + 1)`, while LuxCore's cameras use `filmHeight - filmY - 1`, so LuxCore's
//! row `y` shows what LuxRender shows in row `y - 1`. `--shift-rows 1` compares a luxfarm image
//! with a LuxCore reference under one convention; the shift is a whole row, so nothing is
//! resampled.

use anyhow::{bail, Context};
use luxfarm::film::flm::read_flm;
use luxfarm::film::Film;
use luxfarm::spectrum::{xyz_to_rgb, Rgb};
use luxfarm::texture::image_io::load_rgb as load_image;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// The image to judge (EXR, HDR, PNG, ... or an FLM).
    pub a: PathBuf,
    /// The reference image.
    pub b: PathBuf,
    /// Leave out pixels where the reference exceeds this value in any channel (directly
    /// visible emitters, whose edges dominate the RMSE).
    #[arg(long)]
    pub exclude_above: Option<f32>,
    /// Compare A's row y - N with B's row y (1 aligns luxfarm/LuxRender images with LuxCore's
    /// pixel convention; see the module docs).
    #[arg(long, default_value_t = 0, allow_negative_numbers = true)]
    pub shift_rows: i64,
}

/// Index pairs (a, b) of pixels compared when A is shifted down by `rows` rows.
pub fn row_pairs(w: usize, h: usize, rows: i64) -> Vec<(usize, usize)> {
    let mut out = Vec::with_capacity(w * h);
    for y in 0..h as i64 {
        let ya = y - rows;
        if ya < 0 || ya >= h as i64 {
            continue;
        }
        for x in 0..w {
            out.push((ya as usize * w + x, y as usize * w + x));
        }
    }
    out
}

/// Error metrics of A against the reference B.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Metrics {
    /// sqrt(mean over pixels and channels of (a − b)²).
    pub rmse: f64,
    /// mean of (a − b)² / (b² + 0.01).
    pub rel_mse: f64,
    /// mean(a) / mean(b).
    pub mean_ratio: f64,
}

pub fn metrics(a: &[[f32; 3]], b: &[[f32; 3]]) -> Metrics {
    let (mut se, mut rel, mut sa, mut sb) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (pa, pb) in a.iter().zip(b) {
        for c in 0..3 {
            let (x, y) = (f64::from(pa[c]), f64::from(pb[c]));
            let d = x - y;
            se += d * d;
            rel += d * d / (y * y + 0.01);
            sa += x;
            sb += y;
        }
    }
    let n = (a.len().min(b.len()) * 3).max(1) as f64;
    Metrics {
        rmse: (se / n).sqrt(),
        rel_mse: rel / n,
        mean_ratio: if sb != 0.0 { sa / sb } else { f64::NAN },
    }
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let load = |p: &PathBuf| {
        if p.extension().is_some_and(|e| e.eq_ignore_ascii_case("flm")) {
            return load_flm(p).with_context(|| format!("reading {}", p.display()));
        }
        load_image(p)
            .map_err(anyhow::Error::msg)
            .with_context(|| format!("reading {}", p.display()))
    };
    let (wa, ha, a) = load(&args.a)?;
    let (wb, hb, b) = load(&args.b)?;
    if (wa, ha) != (wb, hb) {
        bail!("image sizes differ: {wa}x{ha} vs {wb}x{hb}");
    }
    let keep = |(_, ib): &(usize, usize)| {
        args.exclude_above
            .is_none_or(|v| b[*ib].max_component() <= v)
    };
    let idx: Vec<(usize, usize)> = row_pairs(wa, ha, args.shift_rows)
        .into_iter()
        .filter(keep)
        .collect();
    let a: Vec<[f32; 3]> = idx.iter().map(|&(i, _)| a[i].to_array()).collect();
    let b: Vec<[f32; 3]> = idx.iter().map(|&(_, i)| b[i].to_array()).collect();
    let mut out = std::io::stdout().lock();
    if args.exclude_above.is_some() || args.shift_rows != 0 {
        writeln!(out, "pixels      {} of {}", idx.len(), wa * ha)?;
    }
    let m = metrics(&a, &b);
    writeln!(out, "RMSE        {:.6}", m.rmse)?;
    writeln!(out, "relMSE      {:.6}", m.rel_mse)?;
    writeln!(out, "mean ratio  {:.6}", m.mean_ratio)?;
    Ok(ExitCode::SUCCESS)
}

/// Linear RGB of light group 0 of an FLM (all groups summed would need their scales).
fn load_flm(p: &PathBuf) -> anyhow::Result<(usize, usize, Vec<Rgb>)> {
    let file = std::fs::File::open(p)?;
    let (film, _) = read_flm(std::io::BufReader::new(file))?;
    Ok((
        film.width() as usize,
        film.height() as usize,
        film_rgb(&film),
    ))
}

/// Linear RGB of light group 0, buffer 0 of a film: weight-normalised XYZ turned back into the
/// renderer's RGB, row by row.
pub fn film_rgb(film: &Film) -> Vec<Rgb> {
    let mut px = Vec::with_capacity(film.pixel_count());
    for y in 0..film.height() {
        for x in 0..film.width() {
            let v = film.pixel(0, 0, x, y).unwrap_or([0.0; 5]);
            let s = if v[4] != 0.0 { 1.0 / v[4] } else { 0.0 };
            px.push(xyz_to_rgb([
                (v[0] * s) as f32,
                (v[1] * s) as f32,
                (v[2] * s) as f32,
            ]));
        }
    }
    px
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_images_have_zero_error() {
        let a = vec![[0.5, 0.25, 1.0]; 4];
        let m = metrics(&a, &a);
        assert_eq!(m.rmse, 0.0);
        assert_eq!(m.rel_mse, 0.0);
        assert_eq!(m.mean_ratio, 1.0);
    }

    #[test]
    fn row_shift_pairs_a_row_above_with_b() {
        // 2x3 image: shifting by one row pairs A's row 0 with B's row 1, A's 1 with B's 2.
        assert_eq!(row_pairs(2, 3, 1), vec![(0, 2), (1, 3), (2, 4), (3, 5)]);
        assert_eq!(row_pairs(2, 3, -1), vec![(2, 0), (3, 1), (4, 2), (5, 3)]);
        assert_eq!(row_pairs(2, 3, 0).len(), 6);
        assert!(row_pairs(2, 3, 5).is_empty());
    }

    #[test]
    fn known_difference() {
        let a = vec![[1.0, 1.0, 1.0]; 2];
        let b = vec![[0.5, 0.5, 0.5]; 2];
        let m = metrics(&a, &b);
        assert!((m.rmse - 0.5).abs() < 1e-12);
        assert!((m.mean_ratio - 2.0).abs() < 1e-12);
    }
}
