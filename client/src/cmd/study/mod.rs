//! `luxfarm study SCENE [--reference REF.flm|.exr] [--configs C,...] [--farm N]
//! [--budget SECONDS] [--target RMSE]... [-o DIR]`: speed against accuracy, measured.
//!
//! The scene is rendered under several configurations ([`config`]: integrator × sampler, and
//! local farms of 1..N workers), each for an equal share of the budget. Local runs measure
//! their film at increasing render times ([`run`]); each measurement is the error against
//! the reference in linear RGB ([`measure`]: RMSE, relative MSE, share of pixels failing
//! the perceptual test). The reference is given (an FLM, or an image in linear RGB such as
//! an EXR) or rendered first for `--reference-time` seconds and cached in DIR.
//!
//! Output in DIR ([`report`], [`plots`]): `study.csv` (one row per checkpoint),
//! `study.html` (self-contained: tables and the SVG figures inlined), the figures as SVG and
//! PNG, and a one-line recommendation printed last: the configuration that reaches the
//! tightest RMSE target first.
//!
//! Noise-aware sampling is not a dimension of the study: a configuration samples noise-aware
//! when it keeps the scene's Sampler kind and with it the scene's `noiseaware` ([`config`]).

pub mod config;
pub mod measure;
pub mod plots;
pub mod report;
pub mod run;

use anyhow::Context;
use config::Config;
use luxfarm::film::{read_flm_file, FilmParams};
use luxfarm::lxs::ParseOptions;
use measure::Reference;
use report::RunResult;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// The scene file.
    pub scene: PathBuf,
    /// The reference: an FLM, or an image in linear RGB (EXR, HDR). Default: a render of the
    /// scene as written for --reference-time seconds, cached in the output folder.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Configurations, comma separated: `scene`, INTEGRATOR/SAMPLER (path, bidirectional,
    /// directlighting × random, sobol, lowdiscrepancy), `farm:N`. Default: the scene's own,
    /// its integrator with sobol, bidirectional/sobol, and farms of 1..=--farm workers.
    #[arg(long, value_delimiter = ',')]
    pub configs: Vec<String>,
    /// Largest local farm of the default configurations (0: no farm runs).
    #[arg(long, default_value_t = 2)]
    pub farm: usize,
    /// Seconds of rendering over all configurations (each gets an equal share).
    #[arg(long, default_value_t = 120.0)]
    pub budget: f64,
    /// Seconds of the reference render when none is given (default: the budget).
    #[arg(long)]
    pub reference_time: Option<f64>,
    /// RMSE targets of the time-to-target figures (repeatable). Default: what the first
    /// configuration reached at its end, and twice and √2 times that.
    #[arg(long = "target")]
    pub targets: Vec<f64>,
    /// Compare the render's row y - N with the reference's row y (1 for a LuxCore reference;
    /// see `compare-image`).
    #[arg(long, default_value_t = 0, allow_negative_numbers = true)]
    pub shift_rows: i64,
    /// Render threads of local runs (0: all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Seed of the configurations' sample streams.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Output folder (default: SCENE-study in the current folder).
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
}

/// Shortest share of the budget one configuration may get.
const MIN_RUN_SECONDS: f64 = 0.2;

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    if !(args.budget.is_finite() && args.budget > 0.0) {
        return Err(crate::exit::InputError(
            "--budget must be a positive number of seconds".into(),
        )
        .into());
    }
    if let Some(t) = args.targets.iter().find(|t| !(t.is_finite() && **t > 0.0)) {
        return Err(crate::exit::InputError(format!("--target {t} is not a positive RMSE")).into());
    }
    let desc = luxfarm::formats::load(&args.scene, &ParseOptions::default())?;
    let base_dir = args
        .scene
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let configs = if args.configs.is_empty() {
        config::defaults(&desc, args.farm)
    } else {
        let parsed = args
            .configs
            .iter()
            .map(|c| Config::parse(c))
            .collect::<Result<Vec<_>, _>>()
            .map_err(crate::exit::InputError)?;
        config::dedup(&desc, parsed)
    };
    let share = args.budget / configs.len().max(1) as f64;
    if share < MIN_RUN_SECONDS {
        return Err(crate::exit::InputError(format!(
            "a budget of {} s gives each of the {} configurations less than {MIN_RUN_SECONDS} s",
            args.budget,
            configs.len()
        ))
        .into());
    }
    let out = args
        .output
        .clone()
        .unwrap_or_else(|| default_output(&args.scene));
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let tonemap = FilmParams::from_entity(desc.film.as_ref())?.tonemap;
    let reference = load_reference(&args, &desc, &base_dir, &out, &tonemap)?;
    let mut runs = Vec::new();
    for c in &configs {
        let label = c.label(&desc);
        eprintln!("study: {label} for {share:.1} s");
        let result = run_config(
            &args, c, &desc, &base_dir, share, &out, &reference, &tonemap,
        );
        runs.push(match result {
            Ok(checkpoints) => RunResult {
                label,
                workers: c.workers(),
                checkpoints,
                failure: None,
            },
            Err(e) => {
                eprintln!("study: {label} failed: {e:#}");
                RunResult {
                    label,
                    workers: c.workers(),
                    checkpoints: Vec::new(),
                    failure: Some(format!("{e:#}")),
                }
            }
        });
    }
    write_outputs(&args, &out, &reference, &runs)
}

fn default_output(scene: &Path) -> PathBuf {
    let stem = scene
        .file_stem()
        .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    PathBuf::from(format!("{stem}-study"))
}

fn load_reference(
    args: &Args,
    desc: &luxfarm::lxs::SceneDescription,
    base_dir: &Path,
    out: &Path,
    tonemap: &luxfarm::tonemap::TonemapParams,
) -> anyhow::Result<Reference> {
    let path = match &args.reference {
        Some(p) => p.clone(),
        None => {
            let secs = args.reference_time.unwrap_or(args.budget);
            if !(secs.is_finite() && secs > 0.0) {
                return Err(crate::exit::InputError(
                    "--reference-time must be a positive number of seconds".into(),
                )
                .into());
            }
            run::make_reference(&args.scene, desc, base_dir, args.threads, secs, out)?
        }
    };
    let source = path.display().to_string();
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("flm"))
    {
        let (film, _) = read_flm_file(&path).with_context(|| format!("reading {source}"))?;
        return Reference::from_film(&film, tonemap, args.shift_rows, source);
    }
    let (w, h, px) = luxfarm::texture::image_io::load_rgb(&path).map_err(anyhow::Error::msg)?;
    let (w, h) = (u32::try_from(w)?, u32::try_from(h)?);
    Reference::new(
        w,
        h,
        px.iter().map(|p| p.to_array()).collect(),
        args.shift_rows,
        source,
    )
}

#[allow(clippy::too_many_arguments)]
fn run_config(
    args: &Args,
    c: &Config,
    desc: &luxfarm::lxs::SceneDescription,
    base_dir: &Path,
    share: f64,
    out: &Path,
    reference: &Reference,
    tonemap: &luxfarm::tonemap::TonemapParams,
) -> anyhow::Result<Vec<run::Checkpoint>> {
    if let Some(workers) = c.workers() {
        let dir = out.join(format!("farm-{workers}"));
        std::fs::create_dir_all(&dir)?;
        let point = run::run_farm(
            &args.scene,
            workers,
            share,
            args.seed,
            dir.join("render"),
            reference,
            tonemap,
        )?;
        return Ok(vec![point]);
    }
    let scene = c
        .apply(desc)
        .ok_or_else(|| anyhow::anyhow!("not a local configuration"))?;
    let o = run::LocalOptions {
        threads: args.threads,
        seed: args.seed,
        budget: share,
    };
    run::run_local(&scene, base_dir, o, reference)
}

fn write_outputs(
    args: &Args,
    out: &Path,
    reference: &Reference,
    runs: &[RunResult],
) -> anyhow::Result<ExitCode> {
    let targets = if args.targets.is_empty() {
        report::default_targets(runs)
    } else {
        args.targets.clone()
    };
    let sum = report::summarise(runs, targets);
    let csv = out.join("study.csv");
    report::write_csv(&csv, runs).with_context(|| format!("writing {}", csv.display()))?;
    let (svgs, note) = match plots::draw_all(out, &sum.figures) {
        Ok(s) => (s, None),
        Err(e) => {
            eprintln!("study: no figures: {e}");
            (Vec::new(), Some(e))
        }
    };
    let ctx = report::Context {
        scene: &args.scene.display().to_string(),
        reference: &reference.source,
        budget: args.budget,
        figure_note: note,
    };
    let html = out.join("study.html");
    std::fs::write(&html, report::html(&ctx, runs, &sum, &svgs))
        .with_context(|| format!("writing {}", html.display()))?;
    println!("{}", csv.display());
    println!("{}", html.display());
    for (name, _) in &svgs {
        println!("{}", out.join(format!("{name}.svg")).display());
        println!("{}", out.join(format!("{name}.png")).display());
    }
    println!("{}", sum.recommendation);
    Ok(if runs.iter().all(|r| r.failure.is_some()) {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}
