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
//! resampled. The metrics are `luxfarm_bench::image_metrics`, which `luxfarm bench cornell`
//! reports too.

use anyhow::{bail, Context};
use luxfarm::film::flm::read_flm;
use luxfarm::spectrum::Rgb;
use luxfarm::texture::image_io::load_rgb as load_image;
use luxfarm_bench::image_metrics::{film_rgb, metrics, row_pairs};
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
