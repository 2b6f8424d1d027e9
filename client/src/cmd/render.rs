//! `luxfarm render SCENE.lxs [--workers N] [--threads N] [--haltspp N] [--halttime S]
//! [--haltthreshold F] [--seed S] [--sampling-map IMAGE]
//! [-o BASENAME]`: renders a scene locally on all cores (or, with `--workers`, on a local farm)
//! with a progress bar, halting at the
//! scene's (or the given) haltspp/halttime/haltthreshold, and writes what the Film asks for.
//!
//! The halt rules are the core's (`luxfarm::halt`, shared with the master): haltspp,
//! halttime, and haltthreshold as LuxRender's (every `convergencestep` spp the display image
//! is compared with the previous snapshot by Yee's perceptual test; the render stops once the
//! fraction of pixels that still change perceptibly is at most the threshold). The outputs
//! are the core's too (`luxfarm::output`): the files the Film asks for, named as on a farm.
//!
//! Passes of the pixel samplers are whole, and a sweep of them is sized to end by halttime;
//! a pass of metropolis or erpt, which can last minutes on a big film, is given halttime as
//! its deadline (`Session::set_deadline`): it ends at the first batch boundary after it
//! (after at least one batch) and keeps its work, so the render stops about on time with
//! the samples it took.
//!
//! `--sampling-map IMAGE` is LuxRender's user sampling map: an image of the film's pixel size
//! (the crop window's, when the Film has one) whose pixels' luminance weigh how many samples
//! each pixel takes (`luxfarm::render::usermap`); with a noise-aware sampler it multiplies the
//! noise-aware map.

use anyhow::{bail, Context};
use indicatif::{ProgressBar, ProgressStyle};
use luxfarm::halt::{Convergence, HaltRules};
use luxfarm::lxs::ParseOptions;
use luxfarm::output;
use luxfarm::render::{usermap, Session, SessionOptions};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::time::{Duration, Instant};

#[derive(clap::Args)]
pub struct Args {
    /// The scene file (.lxs, .igs, .mi, or .lws at `--frame`).
    pub scene: PathBuf,
    /// Render threads (0: all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Stop at this many samples per pixel (overrides the Film's haltspp).
    #[arg(long)]
    pub haltspp: Option<u32>,
    /// Stop after this many seconds (overrides the Film's halttime).
    #[arg(long)]
    pub halttime: Option<f64>,
    /// Stop when at most this fraction of pixels still changes perceptibly between two
    /// convergence tests (overrides the Film's haltthreshold).
    #[arg(long)]
    pub haltthreshold: Option<f64>,
    /// Seed of the sample streams.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Output base name (default: the Film's filename, beside the scene).
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
    /// The animation frame to render (animated scene formats such as LightWave).
    #[arg(long, allow_negative_numbers = true)]
    pub frame: Option<i64>,
    /// Render on a local farm instead: an embedded master in a temporary data directory and
    /// this many worker processes over loopback (`--threads` is then per worker).
    #[arg(long)]
    pub workers: Option<usize>,
    /// The user sampling map: an image (PNG, JPEG, TGA, HDR, EXR) of the film's pixel size
    /// (its crop window's, when it has one) whose luminance weighs each pixel's samples.
    #[arg(long, value_name = "IMAGE")]
    pub sampling_map: Option<PathBuf>,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    for p in render(args)? {
        println!("{}", p.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// Renders as `luxfarm render` does and returns the files written.
pub fn render(args: Args) -> anyhow::Result<Vec<PathBuf>> {
    if let Some(workers) = args.workers {
        if args.sampling_map.is_some() {
            bail!(
                "--sampling-map is not supported with --workers: submit the job and set its \
                 map with PUT /api/v1/jobs/ID/sampling-map"
            );
        }
        return super::farm_render::render(super::farm_render::Options {
            scene: args.scene,
            workers,
            threads: (args.threads > 0).then_some(args.threads),
            haltspp: args.haltspp.map(f64::from),
            halttime: args.halttime,
            haltthreshold: args.haltthreshold,
            seed: Some(args.seed),
            output: args.output,
            upload_interval: 2.0,
            frame: args.frame,
        });
    }
    let parse = ParseOptions {
        frame: args.frame,
        ..ParseOptions::default()
    };
    let desc = luxfarm::formats::load(&args.scene, &parse)?;
    let base_dir = args
        .scene
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let opts = SessionOptions {
        threads: args.threads,
        seed: args.seed,
        stream: 0,
    };
    let mut session = Session::new(&desc, &base_dir, opts)?;
    for w in session.warnings() {
        eprintln!("warning: {w}");
    }
    if let Some(path) = &args.sampling_map {
        set_user_map(&mut session, path)?;
    }
    let fp = session.film_params().clone();
    let rules = HaltRules::from_film(&fp).with_overrides(
        args.haltspp.map(f64::from),
        args.halttime,
        args.haltthreshold,
    );
    rules.validate()?;
    if rules.is_unbounded() {
        bail!(
            "{}: no halt condition: the Film has no haltspp/halttime/haltthreshold; give \
             --haltspp, --halttime or --haltthreshold",
            args.scene.display()
        );
    }
    let mut convergence = Convergence::default();
    let bar = progress_bar(&rules);
    let start = Instant::now();
    let pixels = f64::from(fp.x_pixel_count) * f64::from(fp.y_pixel_count);
    // haltspp counts the samples of the sample extent's pixels, as LuxRender's samplePerPass.
    let pass_pixels = session.renderable().setup.sample_extent().pixels() as f64;
    let pass_samples = session.pass_samples() as f64;
    let mut samples = 0u64;
    // A pass of the chain samplers (metropolis, erpt) can last minutes: halttime ends it at
    // a batch boundary, keeping its work, so the halt check below finds the time reached.
    // (A halttime too large for a deadline is none.)
    let deadline = rules
        .time
        .and_then(|t| Duration::try_from_secs_f64(t).ok())
        .and_then(|d| start.checked_add(d));
    session.set_deadline(deadline);
    loop {
        // A sweep of passes, as many as fit before the next halt check is due.
        let mut max = session.sweep_passes();
        if let Some(n) =
            rules.passes_until_check(&convergence, session.film(), pass_pixels, pass_samples)
        {
            max = max.min(n);
        }
        if let Some(t) = rules.time {
            max = max.min(session.passes_within(t - start.elapsed().as_secs_f64()));
        }
        let stats = session.render_passes(max);
        samples += stats.samples;
        let spp = session.film().spp();
        let secs = start.elapsed().as_secs_f64();
        let rate = samples as f64 / secs.max(1e-9);
        bar.set_position(match rules.spp {
            Some(_) => spp.floor() as u64,
            None => secs as u64,
        });
        let done = rules.check(
            &mut convergence,
            session.film(),
            &fp.tonemap,
            secs,
            pass_pixels,
        );
        bar.set_message(match convergence.last_failing {
            Some(f) => format!(
                "{spp:.1} spp, {:.2} Msamples/s, {:.2}% of pixels changing",
                rate / 1e6,
                100.0 * f
            ),
            None => format!("{spp:.1} spp, {:.2} Msamples/s", rate / 1e6),
        });
        if let Some(reason) = done {
            tracing::info!(%reason, "render done");
            break;
        }
        if pixels == 0.0 {
            break;
        }
    }
    bar.finish();
    let secs = start.elapsed().as_secs_f64();
    let basename = output::basename(&args.scene, &fp, args.output.as_deref());
    let depths = session.exr_depths();
    let written = output::write_outputs_with_z(session.film(), &fp, &basename, depths.as_deref())
        .with_context(|| format!("writing {}", basename.display()))?;
    eprintln!(
        "rendered {:.1} spp ({samples} samples) in {secs:.2} s: {:.0} samples/s; {} samples rejected (NaN/Inf/negative), {} as outliers (outlierrejection_k)",
        session.film().spp(),
        samples as f64 / secs.max(1e-9),
        session.rejected_samples(),
        session.outlier_samples(),
    );
    Ok(written)
}

/// Reads the user sampling map image at `path` and gives it to the session (a warning when
/// the sampler takes no maps).
fn set_user_map(session: &mut Session, path: &Path) -> anyhow::Result<()> {
    let bytes =
        std::fs::read(path).with_context(|| format!("--sampling-map {}", path.display()))?;
    let fp = session.film_params();
    let map = usermap::map_from_image(&bytes, fp.x_pixel_count, fp.y_pixel_count)
        .with_context(|| format!("--sampling-map {}", path.display()))?;
    if !session.set_user_map(Some(Arc::new(map)))? {
        let why = session
            .renderable()
            .setup
            .sampler
            .map_refusal()
            .unwrap_or("the sampler takes no sampling maps");
        eprintln!("warning: --sampling-map {}: {why}", path.display());
    }
    Ok(())
}

fn progress_bar(rules: &HaltRules) -> ProgressBar {
    let (len, unit) = match (rules.spp, rules.time) {
        (Some(s), _) => (s.ceil() as u64, "spp"),
        (None, Some(t)) => (t.ceil() as u64, "s"),
        (None, None) => (0, ""),
    };
    let bar = ProgressBar::new(len);
    let style = ProgressStyle::with_template(&format!(
        "{{bar:40}} {{pos}}/{{len}} {unit} {{msg}} [{{elapsed_precise}}, ETA {{eta}}]"
    ))
    .unwrap_or_else(|_| ProgressStyle::default_bar());
    bar.set_style(style);
    bar.enable_steady_tick(Duration::from_millis(500));
    bar
}
