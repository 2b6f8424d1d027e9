//! `luxfarm bench cornell`: the Cornell benchmark scene rendered side by side, in one run, by
//! luxfarm (in this process, once per sampler asked for) and by whichever of LuxCore, Mitsuba 3
//! and Cycles is installed ([`external`]: `pip install pyluxcore mitsuba bpy OpenEXR numpy`),
//! alternating runs. It reports samples per wall second and per CPU second, RMSE against
//! LuxCore's 2048-spp reference at equal samples, the mean ratio to the reference outside the
//! lamp (bias), and RMSE at equal wall time: each renderer given the same budget, as the spp
//! its measured speed reaches in it, its RMSE carried to exactly that budget by the
//! 1/sqrt(time) law when the render took longer or shorter ([`at_exactly`]). The load average
//! is printed before and after.
//!
//! **Path depth.** `--maxdepth D` counts path segments, as LuxCore's `pathdepth.total` and
//! Mitsuba's `max_depth` do. LuxRender 1.x's `maxdepth` samples lights at path vertices
//! 0..maxdepth-1 and so allows maxdepth + 1 segments (`luxfarm::integrator::path`), so
//! luxfarm renders the scene with `maxdepth` D − 1; Cycles' script sets `max_bounces` D − 2.
//!
//! Speed is reported both per wall-clock second and per CPU second (user + system time of this
//! process, or the script's own CPU statistic): on a shared machine the second is the steadier
//! measure.
//!
//! Pixel conventions: LuxCore's cameras map film rows one row lower than LuxRender's
//! (`filmHeight - filmY - 1`), so every other renderer's image is compared one row up against
//! LuxCore's reference (`--shift-rows 1` of `compare-image`).

mod external;
pub(crate) mod ours;

use crate::image_metrics::{metrics, row_pairs};
use external::{Renderer, Runner};
use luxfarm::texture::image_io::load_rgb as load_image;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// The shared material (default: ../shared beside the repository, else /work/shared).
    #[arg(long)]
    pub shared: Option<PathBuf>,
    /// Samples per pixel of each equal-samples render.
    #[arg(long, default_value_t = 64)]
    pub spp: u32,
    /// Runs of each renderer at equal samples, alternating.
    #[arg(long, default_value_t = 3)]
    pub runs: usize,
    /// Render threads for all (0: all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Path depth in segments (LuxCore `pathdepth.total`, Mitsuba `max_depth`).
    #[arg(long, default_value_t = 8)]
    pub maxdepth: u32,
    /// luxfarm's samplers to run, comma-separated (random, lowdiscrepancy, sobol, metropolis;
    /// `NAME:noiseaware` for LuxRender's noise-aware sampling).
    #[arg(
        long,
        default_value = "random,sobol,sobol:noiseaware",
        value_delimiter = ','
    )]
    pub samplers: Vec<String>,
    /// Wall-time budget of the equal-time renders, in seconds (0: leave them out).
    #[arg(long, default_value_t = 10.0)]
    pub budget: f64,
    /// Python interpreter with the renderers' packages.
    #[arg(long, default_value = "python3")]
    pub python: String,
    /// Leave these renderers out (luxcore, mitsuba, cycles), comma-separated.
    #[arg(long, value_delimiter = ',')]
    pub without: Vec<String>,
    /// Leave LuxCore out (same as `--without luxcore`).
    #[arg(long)]
    pub no_luxcore: bool,
    /// Keep every render's linear RGB image in this directory as OpenEXR
    /// (`{contestant}-run{i}.exr`, `{contestant}-equal-time.exr`), for error maps.
    #[arg(long)]
    pub keep: Option<PathBuf>,
}

/// One render's speed and image (linear RGB, row-major).
pub struct Run {
    pub samples_per_sec: f64,
    pub samples_per_cpu_sec: f64,
    /// Render seconds (scene building left out).
    pub seconds: f64,
    pub spp: f64,
    pub rgb: Vec<[f32; 3]>,
}

/// User + system CPU seconds of this process (`RUSAGE_SELF`) or of its waited-for children.
pub fn cpu_seconds(who: libc::c_int) -> f64 {
    // SAFETY: getrusage only writes the struct we pass; a zeroed rusage is a valid value.
    let mut u: libc::rusage = unsafe { std::mem::zeroed() };
    if unsafe { libc::getrusage(who, &mut u) } != 0 {
        return f64::NAN;
    }
    let tv = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    tv(u.ru_utime) + tv(u.ru_stime)
}

/// A contestant: luxfarm with one sampler, or another renderer.
#[derive(Clone, Debug, PartialEq)]
enum Who {
    Luxfarm(String),
    Other(Renderer),
}

impl Who {
    fn label(&self) -> String {
        match self {
            Who::Luxfarm(s) => format!("luxfarm path+{}", s.replace(':', "+")),
            Who::Other(r) => r.name().to_string(),
        }
    }

    fn row_shift(&self) -> i64 {
        match self {
            Who::Luxfarm(_) => 1,
            Who::Other(r) => r.row_shift(),
        }
    }
}

/// The reference and what a contestant's image is measured with.
struct Reference {
    w: usize,
    h: usize,
    rgb: Vec<[f32; 3]>,
}

/// Luminance above which a reference pixel is the lamp (its radiance's luminance is about
/// 12.6; the brightest wall pixels stay below 1).
const LAMP_LUMINANCE: f64 = 2.0;

fn luminance(c: &[f32; 3]) -> f64 {
    0.2126 * f64::from(c[0]) + 0.7152 * f64::from(c[1]) + 0.0722 * f64::from(c[2])
}

impl Reference {
    /// RMSE against the reference, and the ratio of mean luminance outside the lamp.
    fn measure(&self, img: &[[f32; 3]], shift: i64) -> (f64, f64) {
        let pairs = row_pairs(self.w, self.h, shift);
        let (mut a, mut b) = (
            Vec::with_capacity(pairs.len()),
            Vec::with_capacity(pairs.len()),
        );
        let (mut sa, mut sb) = (0.0, 0.0);
        for &(i, j) in &pairs {
            let (Some(p), Some(q)) = (img.get(i), self.rgb.get(j)) else {
                continue;
            };
            a.push(*p);
            b.push(*q);
            if luminance(q) < LAMP_LUMINANCE {
                sa += luminance(p);
                sb += luminance(q);
            }
        }
        (metrics(&a, &b).rmse, sa / sb)
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

/// The medians of a contestant's equal-samples runs.
struct Summary {
    who: Who,
    rate: f64,
    cpu_rate: f64,
    rmse: f64,
    mean_ratio: f64,
    /// RMSE, spp and seconds of the equal-time render.
    at_budget: Option<(f64, f64, f64)>,
}

/// The contestants of this run: luxfarm's samplers, then each installed other renderer.
fn contestants(a: &Args, runner: &Runner) -> Vec<Who> {
    let mut v: Vec<Who> = a.samplers.iter().map(|s| Who::Luxfarm(s.clone())).collect();
    for r in Renderer::ALL {
        let left_out = a.without.iter().any(|w| w.eq_ignore_ascii_case(r.key()))
            || (a.no_luxcore && r == Renderer::LuxCore);
        if left_out {
            continue;
        }
        if runner.available(r) {
            v.push(Who::Other(r));
        } else {
            println!("{}: python module not found, left out", r.name());
        }
    }
    v
}

/// Renders `who` at `spp`; `seed` varies luxfarm's stream between runs.
fn render(
    who: &Who,
    spp: u32,
    seed: u64,
    ctx: &Context,
    overheads: &[(Renderer, f64)],
) -> anyhow::Result<Run> {
    match who {
        Who::Luxfarm(sampler) => ctx.ours.run(sampler, spp, seed),
        Who::Other(r) => {
            let overhead = overheads
                .iter()
                .find(|(o, _)| o == r)
                .map_or(0.0, |(_, c)| *c);
            let out = ctx.tmp.join(format!("{}-{seed}-{spp}.exr", r.key()));
            ctx.runner.run(*r, spp, &out, overhead)
        }
    }
}

struct Context {
    ours: ours::Ours,
    runner: Runner,
    tmp: PathBuf,
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    for spec in &a.samplers {
        ours::sampler_statement(spec)?;
    }
    let shared = a.shared.clone().unwrap_or_else(crate::support::shared_dir);
    let (w, h, refpx) = load_image(&shared.join("scenes/cornell/luxcore-ref-2048.exr"))
        .map_err(anyhow::Error::msg)?;
    let reference = Reference {
        w,
        h,
        rgb: refpx.iter().map(|c| c.to_array()).collect(),
    };
    let depth = a.maxdepth.max(1);
    let tmp = tempfile::tempdir()?;
    let ctx = Context {
        ours: ours::Ours::new(
            &shared.join("scenes/cornell/cornell-mesh.lxs"),
            depth - 1,
            a.threads,
        )?,
        runner: Runner {
            python: a.python.clone(),
            bench_dir: shared.join("bench"),
            threads: a.threads,
            maxdepth: depth,
            res: w as u32,
        },
        tmp: tmp.path().to_path_buf(),
    };
    println!("machine: {} (before)", crate::support::machine());
    println!(
        "path depth: at most {depth} segments = LuxCore pathdepth.total {depth} = Mitsuba max_depth \
         {depth} = Cycles max_bounces {} = luxfarm/LuxRender maxdepth {}; Russian roulette off",
        depth.saturating_sub(2),
        depth - 1
    );
    let who = contestants(&a, &ctx.runner);
    let mut overheads = Vec::new();
    for w in &who {
        if let Who::Other(r) = w {
            if !Runner::prints_cpu(*r) {
                let c = ctx.runner.overhead(*r, &ctx.tmp)?;
                println!(
                    "{}: start-up + scene build + 1 spp: {c:.2} CPU s (subtracted)",
                    r.name()
                );
                overheads.push((*r, c));
            }
        }
    }
    let mut runs: Vec<Vec<Run>> = who.iter().map(|_| Vec::new()).collect();
    for i in 0..a.runs.max(1) {
        for (k, c) in who.iter().enumerate() {
            let r = render(c, a.spp, i as u64, &ctx, &overheads)?;
            println!(
                "run {i}: {:<22} {:>9.0} samples/s, {:>9.0} samples/CPU-s",
                c.label(),
                r.samples_per_sec,
                r.samples_per_cpu_sec
            );
            keep(&a, &format!("run{i}"), c, &r, (w, h));
            runs[k].push(r);
        }
    }
    let mut sums: Vec<Summary> = who
        .iter()
        .zip(&runs)
        .map(|(w, rs)| summarize(w, rs, &reference))
        .collect();
    if a.budget > 0.0 {
        for s in &mut sums {
            let pixels = (w * h) as f64;
            let spp = (s.rate * a.budget / pixels).round().clamp(1.0, 1e6) as u32;
            let r = render(&s.who, spp, 1000, &ctx, &overheads)?;
            let (rmse, _) = reference.measure(&r.rgb, s.who.row_shift());
            println!(
                "equal time: {:<22} {spp:>5} spp in {:.2} s, RMSE {rmse:.5}",
                s.who.label(),
                r.seconds
            );
            keep(&a, "equal-time", &s.who, &r, (w, h));
            s.at_budget = Some((rmse, f64::from(spp), r.seconds));
        }
    }
    println!("machine: {} (after)", crate::support::machine());
    print!("{}", report(&sums, a.spp, a.budget));
    Ok(ExitCode::SUCCESS)
}

/// Writes a render's image into `--keep`'s directory, if given, as rendered (luxfarm's rows
/// sit one row above LuxCore's reference, see `row_shift`); a write that fails is reported
/// and the benchmark goes on.
fn keep(a: &Args, tag: &str, who: &Who, r: &Run, (w, h): (usize, usize)) {
    let Some(dir) = &a.keep else {
        return;
    };
    let name: String = who
        .label()
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect();
    let path = dir.join(format!("{name}-{tag}.exr"));
    let written = std::fs::create_dir_all(dir)
        .map_err(anyhow::Error::from)
        .and_then(|()| crate::image_metrics::write_rgb_exr(&path, w as u32, h as u32, &r.rgb));
    if let Err(e) = written {
        eprintln!("--keep: {}: {e:#}", path.display());
    }
}

fn summarize(who: &Who, runs: &[Run], reference: &Reference) -> Summary {
    let measured: Vec<(f64, f64)> = runs
        .iter()
        .map(|r| reference.measure(&r.rgb, who.row_shift()))
        .collect();
    Summary {
        who: who.clone(),
        rate: median(runs.iter().map(|r| r.samples_per_sec).collect()),
        cpu_rate: median(runs.iter().map(|r| r.samples_per_cpu_sec).collect()),
        rmse: median(measured.iter().map(|m| m.0).collect()),
        mean_ratio: measured.iter().map(|m| m.1).sum::<f64>() / measured.len().max(1) as f64,
        at_budget: None,
    }
}

/// An equal-time render's RMSE `rmse` after `seconds`, carried to exactly `budget` seconds
/// by the 1/sqrt(time) law of unbiased Monte Carlo error: a render's spp is set from its
/// speed at the equal-samples runs, and one that then runs slower or faster (noise-aware
/// sampling spends more samples where paths are long) would otherwise be judged on more or
/// less time than the others.
fn at_exactly(rmse: f64, seconds: f64, budget: f64) -> f64 {
    if seconds > 0.0 && budget > 0.0 {
        rmse * (seconds / budget).sqrt()
    } else {
        rmse
    }
}

/// The table of medians, and luxfarm's best sampler against each other renderer.
fn report(sums: &[Summary], spp: u32, budget: f64) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "\n| renderer | samples/s (wall) | samples/CPU-s | RMSE at {spp} spp | mean / reference outside the lamp | RMSE at {budget} s |"
    );
    let _ = writeln!(out, "|---|---|---|---|---|---|");
    for s in sums {
        let at = s.at_budget.map_or("-".to_string(), |(e, n, t)| {
            format!(
                "{:.5} ({n} spp in {t:.1} s, RMSE {e:.5})",
                at_exactly(e, t, budget)
            )
        });
        let _ = writeln!(
            out,
            "| {} | {:.0} | {:.0} | {:.5} | {:.4} | {at} |",
            s.who.label(),
            s.rate,
            s.cpu_rate,
            s.rmse,
            s.mean_ratio
        );
    }
    let ours = sums.iter().filter(|s| matches!(s.who, Who::Luxfarm(_)));
    let fastest = ours.clone().max_by(|x, y| x.rate.total_cmp(&y.rate));
    let e = |s: &Summary| s.at_budget.map_or(s.rmse, |b| at_exactly(b.0, b.2, budget));
    let best = ours.min_by(|x, y| e(x).total_cmp(&e(y)));
    for other in sums.iter().filter(|s| matches!(s.who, Who::Other(_))) {
        if let Some(f) = fastest {
            let _ = writeln!(
                out,
                "{} / {}: speed {:.3} per wall second, {:.3} per CPU second",
                f.who.label(),
                other.who.label(),
                f.rate / other.rate,
                f.cpu_rate / other.cpu_rate
            );
        }
        if let Some(b) = best {
            // Error falls as 1/sqrt(samples): at equal CPU time the faster renderer has
            // rate_b/rate_o times the samples. A projection from the equal-samples runs, steadier
            // than the equal-time renders on a machine whose load drifts between them.
            let _ = writeln!(
                out,
                "{} / {}: RMSE at equal CPU time, projected from {spp} spp: {:.3}",
                b.who.label(),
                other.who.label(),
                b.rmse / other.rmse * (other.cpu_rate / b.cpu_rate).sqrt()
            );
        }
        if let (Some(b), Some(_)) = (best, other.at_budget) {
            if b.at_budget.is_some() {
                let _ = writeln!(
                    out,
                    "{} / {}: RMSE at equal time {:.3}",
                    b.who.label(),
                    other.who.label(),
                    e(b) / e(other)
                );
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::at_exactly;

    #[test]
    fn equal_time_error_follows_the_square_root_of_time() {
        // Twice the budget's time: the error it would have had at the budget is √2 larger.
        assert!((at_exactly(0.01, 20.0, 10.0) - 0.01 * 2f64.sqrt()).abs() < 1e-12);
        assert!((at_exactly(0.02, 2.5, 10.0) - 0.01).abs() < 1e-12);
        assert_eq!(at_exactly(0.01, 0.0, 10.0), 0.01);
    }
}
