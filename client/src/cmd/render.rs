//! `luxfarm render SCENE.lxs [--workers N] [--threads N] [--haltspp N] [--halttime S] [--seed S]
//! [-o BASENAME]`: renders a scene locally on all cores (or, with `--workers`, on a local farm)
//! with a progress bar, halting at the
//! scene's (or the given) haltspp/halttime, and writes what the Film asks for.

use anyhow::{bail, Context};
use indicatif::{ProgressBar, ProgressStyle};
use luxfarm::film::output::write_outputs;
use luxfarm::lxs::{parse_file, ParseOptions};
use luxfarm::render::{Session, SessionOptions};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

#[derive(clap::Args)]
pub struct Args {
    /// The .lxs scene file.
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
    /// Seed of the sample streams.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Output base name (default: the Film's filename, beside the scene).
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
    /// Render on a local farm instead: an embedded master in a temporary data directory and
    /// this many worker processes over loopback (`--threads` is then per worker).
    #[arg(long)]
    pub workers: Option<usize>,
}

/// When to stop.
struct Halt {
    spp: Option<f64>,
    time: Option<f64>,
}

impl Halt {
    fn done(&self, spp: f64, secs: f64) -> bool {
        self.spp.is_some_and(|h| spp >= h) || self.time.is_some_and(|t| secs >= t)
    }
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    if let Some(workers) = args.workers {
        return super::farm_render::run(super::farm_render::Options {
            scene: args.scene,
            workers,
            threads: (args.threads > 0).then_some(args.threads),
            haltspp: args.haltspp.map(f64::from),
            halttime: args.halttime,
            seed: Some(args.seed),
            output: args.output,
            upload_interval: 2.0,
        });
    }
    let desc = parse_file(&args.scene, &ParseOptions::default())?;
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
    for w in &session.scene().warnings {
        eprintln!("warning: {w}");
    }
    let fp = session.film_params().clone();
    let halt = Halt {
        spp: args.haltspp.or(fp.haltspp).map(f64::from),
        time: args.halttime.or(fp.halttime.map(f64::from)),
    };
    if halt.spp.is_none() && halt.time.is_none() {
        bail!(
            "{}: no halt condition: the Film has no haltspp/halttime (haltthreshold is not \
             supported by `luxfarm render` yet); give --haltspp or --halttime",
            args.scene.display()
        );
    }
    let bar = progress_bar(&halt);
    let start = Instant::now();
    let pixels = f64::from(fp.x_pixel_count) * f64::from(fp.y_pixel_count);
    let mut samples = 0u64;
    loop {
        let stats = session.render_pass();
        samples += stats.samples;
        let spp = session.film().spp();
        let secs = start.elapsed().as_secs_f64();
        let rate = samples as f64 / secs.max(1e-9);
        bar.set_position(match halt.spp {
            Some(_) => spp.floor() as u64,
            None => secs as u64,
        });
        bar.set_message(format!("{spp:.1} spp, {:.2} Msamples/s", rate / 1e6));
        if halt.done(spp, secs) || pixels == 0.0 {
            break;
        }
    }
    bar.finish();
    let secs = start.elapsed().as_secs_f64();
    let basename = args
        .output
        .clone()
        .unwrap_or_else(|| base_dir.join(&fp.filename));
    let written = write_outputs(session.film(), &fp, &basename)
        .with_context(|| format!("writing {}", basename.display()))?;
    eprintln!(
        "rendered {:.1} spp ({samples} samples) in {secs:.2} s: {:.0} samples/s; {} samples rejected (NaN/Inf/negative)",
        session.film().spp(),
        samples as f64 / secs.max(1e-9),
        session.rejected_samples(),
    );
    for p in written {
        println!("{}", p.display());
    }
    Ok(ExitCode::SUCCESS)
}

fn progress_bar(halt: &Halt) -> ProgressBar {
    let (len, unit) = match (halt.spp, halt.time) {
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
