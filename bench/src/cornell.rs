//! `luxfarm bench cornell`: issue 3's speed and accuracy benchmarks side by side with LuxCore,
//! in one run: the Cornell mesh scene rendered alternately by luxfarm (in this process) and by
//! LuxCore (`../shared/bench/luxcore_cornell.py`, needs `pip install pyluxcore numpy`), then
//! samples per second of both (median of the runs, and the ratio) and the RMSE of both against
//! LuxCore's 2048-spp reference.
//!
//! Speed is reported both per wall-clock second and per CPU second (user + system time of this
//! process, or of the LuxCore child): on a shared machine the second is the steadier measure.
//!
//! Same conventions for the error: our image is compared one row up (`--shift-rows 1` of
//! `compare-image`), because LuxCore's cameras map film rows one row lower than LuxRender's
//! (`filmHeight - filmY - 1`); LuxCore's own render is compared over the same pixels.

use crate::image_metrics::{film_rgb, metrics, row_pairs};
use anyhow::{bail, Context};
use luxfarm::lxs::{parse_file, ParseOptions};
use luxfarm::render::{Session, SessionOptions};
use luxfarm::texture::image_io::load_rgb as load_image;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// The shared material (default: ../shared beside the repository, else /work/shared).
    #[arg(long)]
    pub shared: Option<PathBuf>,
    /// Samples per pixel of each render.
    #[arg(long, default_value_t = 64)]
    pub spp: u32,
    /// Runs of each renderer, alternating.
    #[arg(long, default_value_t = 3)]
    pub runs: usize,
    /// Render threads for both (0: all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Python interpreter with pyluxcore.
    #[arg(long, default_value = "python3")]
    pub python: String,
    /// Leave LuxCore out (our numbers only).
    #[arg(long)]
    pub no_luxcore: bool,
}

fn shared_dir(a: &Args) -> PathBuf {
    a.shared.clone().unwrap_or_else(crate::support::shared_dir)
}

/// One render's speed and image (linear RGB, row-major).
struct Run {
    samples_per_sec: f64,
    samples_per_cpu_sec: f64,
    rgb: Vec<[f32; 3]>,
}

/// User + system CPU seconds of this process (`RUSAGE_SELF`) or of its waited-for children.
fn cpu_seconds(who: libc::c_int) -> f64 {
    // SAFETY: getrusage only writes the struct we pass; a zeroed rusage is a valid value.
    let mut u: libc::rusage = unsafe { std::mem::zeroed() };
    if unsafe { libc::getrusage(who, &mut u) } != 0 {
        return f64::NAN;
    }
    let tv = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    tv(u.ru_utime) + tv(u.ru_stime)
}

fn ours(scene: &Path, spp: u32, threads: usize, seed: u64) -> anyhow::Result<Run> {
    let desc = parse_file(scene, &ParseOptions::default())?;
    let base = scene.parent().unwrap_or(Path::new("."));
    let opts = SessionOptions {
        threads,
        seed,
        stream: 0,
    };
    // Scene building is left out, as LuxCore's samples/s statistic leaves it out.
    let mut s = Session::new(&desc, base, opts)?;
    let start = Instant::now();
    let cpu0 = cpu_seconds(libc::RUSAGE_SELF);
    let mut samples = 0u64;
    while s.film().spp() < f64::from(spp) {
        let st = s.render_pass();
        if !st.complete || st.samples == 0 {
            bail!("render pass did not complete");
        }
        samples += st.samples;
    }
    let secs = start.elapsed().as_secs_f64();
    let cpu = cpu_seconds(libc::RUSAGE_SELF) - cpu0;
    Ok(Run {
        samples_per_sec: samples as f64 / secs.max(1e-9),
        samples_per_cpu_sec: samples as f64 / cpu.max(1e-9),
        rgb: film_rgb(s.film()).iter().map(|c| c.to_array()).collect(),
    })
}

/// Runs the LuxCore script at `spp`; returns its samples/s statistic, the samples it rendered,
/// the child's CPU seconds (start-up and scene build included) and its image.
fn luxcore_once(
    a: &Args,
    script: &Path,
    spp: u32,
    out: &Path,
) -> anyhow::Result<(f64, f64, f64, Vec<[f32; 3]>)> {
    let cpu0 = cpu_seconds(libc::RUSAGE_CHILDREN);
    let o = Command::new(&a.python)
        .arg(script)
        .args(["--spp", &spp.to_string(), "--res", "256"])
        .args(["--threads", &a.threads.to_string()])
        .arg("--out")
        .arg(out)
        .output()
        .with_context(|| format!("running {} {}", a.python, script.display()))?;
    let cpu = cpu_seconds(libc::RUSAGE_CHILDREN) - cpu0;
    let text = String::from_utf8_lossy(&o.stdout);
    let field = |name: &str| {
        text.split_whitespace()
            .find_map(|w| w.strip_prefix(name))
            .and_then(|v| v.parse::<f64>().ok())
    };
    let (Some(rate), Some(passes), true) =
        (field("samples_per_s="), field("spp="), o.status.success())
    else {
        bail!(
            "LuxCore run failed ({}): {}{}",
            o.status,
            text,
            String::from_utf8_lossy(&o.stderr)
        );
    };
    let (w, h, px) = load_image(out).map_err(anyhow::Error::msg)?;
    let samples = passes * (w * h) as f64;
    Ok((
        rate,
        samples,
        cpu,
        px.iter().map(|c| c.to_array()).collect(),
    ))
}

/// One LuxCore run. Its CPU time includes Python start-up and scene building, which its
/// samples/s statistic leaves out: `overhead` (the CPU seconds of a 1-spp run, measured once)
/// is subtracted. That run's one pass of rendering is subtracted too, in LuxCore's favour.
fn luxcore(a: &Args, script: &Path, out: &Path, overhead: f64) -> anyhow::Result<Run> {
    let (rate, samples, cpu, rgb) = luxcore_once(a, script, a.spp, out)?;
    Ok(Run {
        samples_per_sec: rate,
        samples_per_cpu_sec: samples / (cpu - overhead).max(1e-9),
        rgb,
    })
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

/// RMSE against the reference over the pixel pairs `pairs` (a, reference).
fn rmse(img: &[[f32; 3]], reference: &[[f32; 3]], pairs: &[(usize, usize)]) -> f64 {
    let a: Vec<[f32; 3]> = pairs.iter().map(|&(i, _)| img[i]).collect();
    let b: Vec<[f32; 3]> = pairs.iter().map(|&(_, j)| reference[j]).collect();
    metrics(&a, &b).rmse
}

fn machine() -> String {
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    format!("{cores} cores, load average {}", crate::support::loadavg())
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let shared = shared_dir(&a);
    let scene = shared.join("scenes/cornell/cornell-mesh.lxs");
    let reference = shared.join("scenes/cornell/luxcore-ref-2048.exr");
    let script = shared.join("bench/luxcore_cornell.py");
    let (w, h, refpx) = load_image(&reference).map_err(anyhow::Error::msg)?;
    let refpx: Vec<[f32; 3]> = refpx.iter().map(|c| c.to_array()).collect();
    let tmp = tempfile::tempdir()?;
    println!("machine: {} (before)", machine());
    let overhead = if a.no_luxcore {
        0.0
    } else {
        let (_, _, cpu, _) = luxcore_once(&a, &script, 1, &tmp.path().join("lc-1spp.exr"))?;
        println!("LuxCore start-up + scene build + 1 spp: {cpu:.2} CPU s (subtracted)");
        cpu
    };
    let (mut ours_runs, mut lc_runs) = (Vec::new(), Vec::new());
    let show = |who: &str, i: usize, r: &Run| {
        println!(
            "run {i}: {who} {:>9.0} samples/s, {:>9.0} samples/CPU-s",
            r.samples_per_sec, r.samples_per_cpu_sec
        )
    };
    for i in 0..a.runs.max(1) {
        if !a.no_luxcore {
            let r = luxcore(
                &a,
                &script,
                &tmp.path().join(format!("lc{i}.exr")),
                overhead,
            )?;
            show("LuxCore", i, &r);
            lc_runs.push(r);
        }
        let r = ours(&scene, a.spp, a.threads, i as u64)?;
        show("luxfarm", i, &r);
        ours_runs.push(r);
    }
    println!("machine: {} (after)", machine());
    // Our row y-1 against the reference's row y; LuxCore's row y against the same rows.
    let shifted = row_pairs(w, h, 1);
    let same: Vec<(usize, usize)> = shifted.iter().map(|&(_, j)| (j, j)).collect();
    let ours_rate = median(ours_runs.iter().map(|r| r.samples_per_sec).collect());
    let ours_cpu = median(ours_runs.iter().map(|r| r.samples_per_cpu_sec).collect());
    let ours_err = median(
        ours_runs
            .iter()
            .map(|r| rmse(&r.rgb, &refpx, &shifted))
            .collect(),
    );
    println!(
        "luxfarm: {ours_rate:.0} samples/s, {ours_cpu:.0} samples/CPU-s (medians), RMSE {ours_err:.5} at {} spp",
        a.spp
    );
    if lc_runs.is_empty() {
        return Ok(ExitCode::SUCCESS);
    }
    let lc_rate = median(lc_runs.iter().map(|r| r.samples_per_sec).collect());
    let lc_cpu = median(lc_runs.iter().map(|r| r.samples_per_cpu_sec).collect());
    let lc_err = median(
        lc_runs
            .iter()
            .map(|r| rmse(&r.rgb, &refpx, &same))
            .collect(),
    );
    println!(
        "LuxCore: {lc_rate:.0} samples/s, {lc_cpu:.0} samples/CPU-s (medians), RMSE {lc_err:.5} at {} spp",
        a.spp
    );
    println!(
        "luxfarm/LuxCore: speed {:.3} per wall second, {:.3} per CPU second (target >= 1.5); \
         RMSE {:.3} (target <= 1.1)",
        ours_rate / lc_rate,
        ours_cpu / lc_cpu,
        ours_err / lc_err
    );
    Ok(ExitCode::SUCCESS)
}
