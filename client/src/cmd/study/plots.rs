//! The study's figures, drawn with `plotters`, each as SVG and PNG: RMSE against render time
//! (log–log, one line per configuration, farm runs as single points), time to reach each
//! error target, samples per second per configuration, and farm speed-up against workers.
//!
//! Data flow: [`Figures`] (numbers the report computed) → one generic drawing function per
//! figure → the SVG backend (a string, also inlined in the HTML report) and the bitmap
//! backend (an RGB buffer, written as PNG by `luxfarm::imageio`).
//!
//! Text needs a TrueType font for its metrics and, in PNGs, its glyphs: `LUXFARM_FONT` or
//! the first of the usual system fonts found ([`FONT_PATHS`]). Without one, no figure is
//! drawn and the caller reports why.

use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// Fonts tried when `LUXFARM_FONT` is not set.
const FONT_PATHS: &[&str] = &[
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
    "/usr/share/fonts/liberation/LiberationSans-Regular.ttf",
    "/Library/Fonts/Arial.ttf",
    "/System/Library/Fonts/Supplemental/Arial.ttf",
    "C:\\Windows\\Fonts\\arial.ttf",
];
/// Largest font file read.
const MAX_FONT_BYTES: u64 = 64 << 20;
const SIZE: (u32, u32) = (900, 600);
const FONT: &str = "sans-serif";

/// One configuration's line on the error and target figures.
pub struct Line {
    pub label: String,
    /// (render seconds, RMSE) per checkpoint.
    pub rmse: Vec<(f64, f64)>,
    /// (target RMSE, seconds to reach it) for the targets reached.
    pub to_target: Vec<(f64, f64)>,
}

/// Everything the figures show.
pub struct Figures {
    pub lines: Vec<Line>,
    /// (label, samples per second) per configuration.
    pub rates: Vec<(String, f64)>,
    /// (workers, speed-up against one worker).
    pub speedup: Vec<(usize, f64)>,
}

/// Registers the font once per process.
fn font() -> Result<(), String> {
    static DONE: OnceLock<Result<(), String>> = OnceLock::new();
    DONE.get_or_init(|| {
        let candidates: Vec<PathBuf> = match std::env::var_os("LUXFARM_FONT") {
            Some(p) => vec![PathBuf::from(p)],
            None => FONT_PATHS.iter().map(PathBuf::from).collect(),
        };
        let path = candidates.iter().find(|p| p.is_file()).ok_or_else(|| {
            "no TrueType font found for the figures' text: set LUXFARM_FONT to a .ttf file"
                .to_string()
        })?;
        let len = std::fs::metadata(path).map_err(|e| e.to_string())?.len();
        if len > MAX_FONT_BYTES {
            return Err(format!("{}: font file too large", path.display()));
        }
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        // Registered fonts live as long as the process: leak the one file once.
        let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
        plotters::style::register_font(FONT, FontStyle::Normal, bytes)
            .map_err(|_| format!("{}: not a usable TrueType font", path.display()))
    })
    .clone()
}

fn err(e: impl std::fmt::Display) -> String {
    e.to_string()
}

/// Bounds of positive values for a log axis, widened to whole decades (so that the axis
/// always has labelled ticks).
fn log_range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::MAX, f64::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if lo > hi {
        return 0.1..10.0;
    }
    let lo = 10f64.powf(lo.log10().floor());
    let hi = 10f64.powf(hi.log10().ceil()).max(lo * 10.0);
    lo..hi
}

fn color(i: usize) -> RGBAColor {
    Palette99::pick(i).to_rgba()
}

fn error_figure<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    f: &Figures,
) -> Result<(), String> {
    let axes = LogLog {
        caption: "RMSE against render time (log-log)",
        x: "render seconds",
        y: "RMSE, linear RGB",
    };
    loglog_figure(root, f, &axes, |l| &l.rmse)
}

fn target_figure<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    f: &Figures,
) -> Result<(), String> {
    let axes = LogLog {
        caption: "Time to reach each RMSE target",
        x: "target RMSE",
        y: "render seconds to reach it",
    };
    loglog_figure(root, f, &axes, |l| &l.to_target)
}

/// The caption and axis names of a log–log figure.
struct LogLog {
    caption: &'static str,
    x: &'static str,
    y: &'static str,
}

/// One line with dots per configuration, of the points `series` picks (those with both
/// coordinates positive: the axes are logarithmic); a configuration without any is left out
/// but keeps its colour, so colours agree between figures.
fn loglog_figure<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    f: &Figures,
    axes: &LogLog,
    series: impl Fn(&Line) -> &[(f64, f64)],
) -> Result<(), String> {
    root.fill(&WHITE).map_err(err)?;
    let positive = |l: &Line| -> Vec<(f64, f64)> {
        series(l)
            .iter()
            .copied()
            .filter(|p| p.0 > 0.0 && p.1 > 0.0)
            .collect()
    };
    // (colour index, line, its positive points)
    let lines: Vec<_> = f
        .lines
        .iter()
        .enumerate()
        .map(|(i, l)| (i, l, positive(l)))
        .filter(|(_, _, pts)| !pts.is_empty())
        .collect();
    let pts = || lines.iter().flat_map(|(_, _, p)| p.iter());
    let mut chart = ChartBuilder::on(root)
        .caption(axes.caption, (FONT, 22))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(
            log_range(pts().map(|p| p.0)).log_scale(),
            log_range(pts().map(|p| p.1)).log_scale(),
        )
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(axes.x)
        .y_desc(axes.y)
        .label_style((FONT, 14))
        .draw()
        .map_err(err)?;
    for (i, l, pts) in lines.iter() {
        let c = color(*i);
        chart
            .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
            .map_err(err)?
            .label(l.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 3, c.filled())))
            .map_err(err)?;
    }
    legend(&mut chart)
}

fn legend<'a, DB: DrawingBackend + 'a, X: Ranged, Y: Ranged>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
) -> Result<(), String> {
    chart
        .configure_series_labels()
        .label_font((FONT, 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(err)
}

fn rate_figure<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    f: &Figures,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(err)?;
    let max = f.rates.iter().map(|r| r.1).fold(0.0f64, f64::max).max(1.0);
    let n = f.rates.len().max(1) as f64;
    let mut chart = ChartBuilder::on(root)
        .caption("Samples per second", (FONT, 22))
        .margin(15)
        .x_label_area_size(20)
        .y_label_area_size(90)
        .build_cartesian_2d(-0.5..n - 0.5, 0.0..max * 1.15)
        .map_err(err)?;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(0)
        .y_desc("samples/s")
        .label_style((FONT, 14))
        .draw()
        .map_err(err)?;
    for (i, (label, v)) in f.rates.iter().enumerate() {
        let x = i as f64;
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(x - 0.35, 0.0), (x + 0.35, *v)],
                color(i).filled(),
            )))
            .map_err(err)?;
        chart
            .draw_series(std::iter::once(Text::new(
                format!("{label}: {v:.3e}"),
                (x - 0.35, *v + max * 0.06),
                (FONT, 14),
            )))
            .map_err(err)?;
    }
    Ok(())
}

fn speedup_figure<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    f: &Figures,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(err)?;
    let n = f.speedup.iter().map(|s| s.0).max().unwrap_or(1).max(1) as f64;
    let top = f.speedup.iter().map(|s| s.1).fold(n, f64::max) * 1.15;
    let mut chart = ChartBuilder::on(root)
        .caption("Farm speed-up against workers", (FONT, 22))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(0.5..n + 0.5, 0.0..top)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("local workers")
        .y_desc("samples/s against 1 worker")
        .label_style((FONT, 14))
        .draw()
        .map_err(err)?;
    let ideal = RGBAColor(128, 128, 128, 1.0);
    chart
        .draw_series(LineSeries::new(
            vec![(1.0, 1.0), (n, n)],
            ideal.stroke_width(1),
        ))
        .map_err(err)?
        .label("ideal")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], ideal));
    let pts: Vec<(f64, f64)> = f.speedup.iter().map(|&(w, s)| (w as f64, s)).collect();
    let c = color(0);
    chart
        .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
        .map_err(err)?
        .label("measured")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
    chart
        .draw_series(pts.into_iter().map(|p| Circle::new(p, 4, c.filled())))
        .map_err(err)?;
    legend(&mut chart)
}

/// Draws figure `name` (one of [`NAMES`]) on any backend.
fn draw<DB: DrawingBackend>(
    name: &str,
    root: &DrawingArea<DB, Shift>,
    f: &Figures,
) -> Result<(), String> {
    match name {
        "error_vs_time" => error_figure(root, f),
        "time_to_target" => target_figure(root, f),
        "samples_per_second" => rate_figure(root, f),
        "farm_speedup" => speedup_figure(root, f),
        _ => Err(format!("no figure {name:?}")),
    }
}

/// Draws one figure as `DIR/NAME.svg` and `DIR/NAME.png`; returns the SVG text.
fn figure(dir: &Path, name: &str, f: &Figures) -> Result<String, String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        draw(name, &root, f)?;
        root.present().map_err(err)?;
    }
    let mut buf = vec![0u8; SIZE.0 as usize * SIZE.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, SIZE).into_drawing_area();
        draw(name, &root, f)?;
        root.present().map_err(err)?;
    }
    let svg_path = dir.join(format!("{name}.svg"));
    std::fs::write(&svg_path, &svg).map_err(|e| format!("{}: {e}", svg_path.display()))?;
    write_png(&dir.join(format!("{name}.png")), &buf)?;
    Ok(svg)
}

fn write_png(path: &Path, buf: &[u8]) -> Result<(), String> {
    // Byte b as the display value the 8-bit quantiser turns back into b.
    let rgb: Vec<[f32; 3]> = buf
        .chunks_exact(3)
        .map(|p| [p[0], p[1], p[2]].map(|b| (f32::from(b) + 0.5) / 255.0))
        .collect();
    let img = luxfarm::imageio::ldr::LdrImage {
        width: SIZE.0,
        height: SIZE.1,
        rgb: &rgb,
        gray: &[],
        alpha: &[],
    };
    luxfarm::imageio::ldr::write_png(path, &img, luxfarm::imageio::ChannelSet::Rgb, false)
        .map_err(|e| e.to_string())
}

/// The figures' names, in the order the report shows them.
pub const NAMES: [&str; 4] = [
    "error_vs_time",
    "time_to_target",
    "samples_per_second",
    "farm_speedup",
];

/// Draws every figure into `dir`; returns (name, SVG text) per figure drawn. The speed-up
/// figure needs at least one farm run.
pub fn draw_all(dir: &Path, f: &Figures) -> Result<Vec<(String, String)>, String> {
    font()?;
    let mut out = Vec::new();
    for name in NAMES {
        if name == "farm_speedup" && f.speedup.is_empty() {
            continue;
        }
        out.push((name.to_string(), figure(dir, name, f)?));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_ranges_hold_every_positive_value() {
        let near = |r: std::ops::Range<f64>, lo: f64, hi: f64| {
            assert!((r.start / lo - 1.0).abs() < 1e-12 && (r.end / hi - 1.0).abs() < 1e-12);
        };
        near(
            log_range([0.5, 2.0, 0.0, f64::NAN, -1.0].into_iter()),
            0.1,
            10.0,
        );
        near(log_range([3.0].into_iter()), 1.0, 10.0);
        near(log_range([10.0].into_iter()), 10.0, 100.0);
        assert_eq!(log_range(std::iter::empty()), 0.1..10.0);
    }
}
