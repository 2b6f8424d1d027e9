//! `luxfarm flm ...`: FLM tools in the spirit of LuxRender's luxmerger and luxcomp.
//!
//! - `info F.flm`: resolution, light groups, buffers, samples and spp, parameters.
//! - `merge A.flm B.flm ... -o OUT.flm`: adds the films (sums and sample counts).
//! - `compare REF.flm TEST.flm [--threshold X] [--metric rms|mse]`: MSE/RMS over normalised XYZ;
//!   exit 1 above X. luxcomp's own default metric is the MSE (`-t 0`), and LuxRender's regression
//!   runner called it without `-t`, so the thresholds in its `.cfg` files bound the MSE.
//! - `tonemap F.flm -o OUT.png|.tga|.exr [--kernel ...]`: the FLM's own imaging parameters
//!   unless overridden.

use anyhow::{bail, Context};
use luxfarm::film::{
    compare, flm, read_flm_file, Channels, ClampMethod, Film, FilmParams, FlmDelta, FlmHeader,
    FlmValue, Kernel, TonemapParams,
};
use luxfarm::output;
use luxfarm::tonemap::{FalseMethod, FalseScale};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    pub command: FlmCommand,
}

#[derive(clap::Subcommand)]
pub enum FlmCommand {
    /// Print an FLM's resolution, groups, buffers, samples and parameters.
    Info {
        file: PathBuf,
        /// Also list every raw header parameter (id, index, value).
        #[arg(long)]
        params: bool,
    },
    /// Add FLM films of the same layout into one.
    Merge {
        #[arg(required = true, num_args = 1..)]
        inputs: Vec<PathBuf>,
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Compare a test film with a reference film (luxcomp's metrics).
    Compare {
        reference: PathBuf,
        test: PathBuf,
        /// Exit with status 1 when the metric exceeds this.
        #[arg(long)]
        threshold: Option<f64>,
        /// The metric the threshold applies to (luxcomp's `-t`: 0 = mse, 1 = rms).
        #[arg(long, value_enum, default_value_t = Metric::Rms)]
        metric: Metric,
    },
    /// Tonemap an FLM to PNG, TGA or OpenEXR.
    Tonemap(TonemapArgs),
}

#[derive(clap::Args)]
pub struct TonemapArgs {
    pub file: PathBuf,
    /// Output file: .png, .tga or .exr.
    #[arg(short, long)]
    pub output: PathBuf,
    /// reinhard, linear, contrast, maxwhite, autolinear or falsecolors.
    #[arg(long)]
    pub kernel: Option<String>,
    /// falsecolors: linear, log or log3.
    #[arg(long)]
    pub false_method: Option<String>,
    /// falsecolors: std, lmk, red, white, yellow or speos.
    #[arg(long)]
    pub false_colorscale: Option<String>,
    /// falsecolors: the luminance shown in the scale's last colour.
    #[arg(long)]
    pub false_max: Option<f32>,
    /// falsecolors: the luminance shown in the scale's first colour.
    #[arg(long)]
    pub false_min: Option<f32>,
    #[arg(long)]
    pub prescale: Option<f32>,
    #[arg(long)]
    pub postscale: Option<f32>,
    #[arg(long)]
    pub burn: Option<f32>,
    #[arg(long)]
    pub sensitivity: Option<f32>,
    #[arg(long)]
    pub exposure: Option<f32>,
    #[arg(long)]
    pub fstop: Option<f32>,
    /// Gamma of the linear kernel.
    #[arg(long)]
    pub linear_gamma: Option<f32>,
    /// Display adaptation luminance of the contrast kernel.
    #[arg(long)]
    pub ywa: Option<f32>,
    /// Output gamma.
    #[arg(long)]
    pub gamma: Option<f32>,
    /// LDR clamp method: lum, hue, cut or darken.
    #[arg(long)]
    pub clamp: Option<String>,
    /// Channels: Y, YA, RGB or RGBA.
    #[arg(long)]
    pub channels: Option<String>,
    /// 16-bit PNG.
    #[arg(long)]
    pub png16: bool,
    /// EXR: write the film's RGB without tonemapping.
    #[arg(long)]
    pub untonemapped: bool,
    /// EXR: 32-bit float instead of half.
    #[arg(long)]
    pub float: bool,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    match args.command {
        FlmCommand::Info { file, params } => info(&file, params),
        FlmCommand::Merge { inputs, output } => merge(&inputs, &output),
        FlmCommand::Compare {
            reference,
            test,
            threshold,
            metric,
        } => compare_cmd(&reference, &test, threshold, metric),
        FlmCommand::Tonemap(a) => tonemap(a),
    }
}

fn load(path: &Path) -> anyhow::Result<(Film, FlmHeader)> {
    read_flm_file(path).with_context(|| format!("reading {}", path.display()))
}

fn info(path: &Path, raw: bool) -> anyhow::Result<ExitCode> {
    let (film, header) = load(path)?;
    let p = FilmParams::from_flm(&header);
    println!("file:        {}", path.display());
    println!("resolution:  {}x{}", film.width(), film.height());
    println!("groups:      {}", film.groups().len());
    for (i, g) in film.groups().iter().enumerate() {
        let gp = p.tonemap.group(i);
        println!(
            "  [{i}] {g:?}: {} samples, enabled {}, scale {}, rgb scale {:?}, temperature {}",
            film.sample_count(i),
            gp.enabled,
            gp.scale,
            gp.rgb_scale,
            gp.temperature
        );
    }
    println!("buffers:     {}", film.buffer_types().len());
    for (i, b) in film.buffer_types().iter().enumerate() {
        println!("  [{i}] type {} ({})", b.id(), b.name());
    }
    println!("samples:     {}", film.total_samples());
    println!("spp:         {:.2}", film.spp());
    print_tonemap(&p.tonemap);
    println!("parameters:  {}", header.params.len());
    if raw {
        for q in &header.params {
            let v = match &q.value {
                FlmValue::Float(v) => format!("{v}"),
                FlmValue::Double(v) => format!("{v} (double)"),
                FlmValue::String(s) => format!("{:?}", String::from_utf8_lossy(s)),
            };
            println!("  id {:>2} index {}: {v}", q.id, q.index);
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn print_tonemap(t: &TonemapParams) {
    println!(
        "tonemapping: {} ({:?} pipeline)",
        t.kernel.name(),
        t.flavour
    );
    match t.kernel {
        Kernel::Reinhard => println!(
            "  reinhard prescale {}, postscale {}, burn {}",
            t.reinhard_prescale, t.reinhard_postscale, t.reinhard_burn
        ),
        Kernel::Linear => println!(
            "  linear sensitivity {}, exposure {}, fstop {}, gamma {}",
            t.linear_sensitivity, t.linear_exposure, t.linear_fstop, t.linear_gamma
        ),
        Kernel::Contrast => println!("  contrast ywa {}", t.contrast_ywa),
        Kernel::FalseColors => {
            let f = &t.false_colors;
            println!(
                "  falsecolors method {}, colour scale {}, min {}, max {}",
                f.method.name(),
                f.scale.name(),
                f.min,
                f.max
            )
        }
        Kernel::MaxWhite | Kernel::AutoLinear => {}
    }
    let c = &t.colorspace;
    println!(
        "  gamma {}, ldr clamp {}, colour space white {:?} red {:?} green {:?} blue {:?}",
        t.gamma,
        t.clamp_method.name(),
        c.white,
        c.red,
        c.green,
        c.blue
    );
}

fn merge(inputs: &[PathBuf], out: &Path) -> anyhow::Result<ExitCode> {
    let Some((first, rest)) = inputs.split_first() else {
        bail!("no input films");
    };
    let (mut film, header) = load(first)?;
    let mut delta = FlmDelta::default();
    for path in rest {
        let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
        let merged = match delta.decode_slice(&bytes) {
            Ok(_) => film.add_delta(&delta),
            Err(e) => Err(e),
        };
        merged.with_context(|| format!("merging {}", path.display()))?;
    }
    let params = FilmParams::from_flm(&header);
    flm::write_flm_file(out, &film, &params)
        .with_context(|| format!("writing {}", out.display()))?;
    println!(
        "merged {} films into {}: {} samples ({:.2} spp)",
        inputs.len(),
        out.display(),
        film.total_samples(),
        film.spp()
    );
    Ok(ExitCode::SUCCESS)
}

/// What `flm compare --threshold` bounds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Metric {
    Rms,
    Mse,
}

fn compare_cmd(
    reference: &Path,
    test: &Path,
    threshold: Option<f64>,
    metric: Metric,
) -> anyhow::Result<ExitCode> {
    let (r, _) = load(reference)?;
    let (t, _) = load(test)?;
    let c = compare(&r, &t)?;
    let pct = |n| 100.0 * c.share(n);
    println!("small diff:  {} ({:.3}%)", c.small, pct(c.small));
    println!("medium diff: {} ({:.3}%)", c.medium, pct(c.medium));
    println!("big diff:    {} ({:.3}%)", c.big, pct(c.big));
    println!("min diff:    {}", c.min_diff);
    println!("max diff:    {}", c.max_diff);
    println!("avg ref:     {}", c.avg_reference);
    println!("avg test:    {}", c.avg_test);
    println!("MSE:         {}", c.mse);
    println!("RMS:         {}", c.rms);
    let (name, value) = match metric {
        Metric::Rms => ("RMS", c.rms),
        Metric::Mse => ("MSE", c.mse),
    };
    match threshold {
        Some(th) if value > th => {
            println!("FAIL: {name} {value} exceeds threshold {th}");
            Ok(ExitCode::from(1))
        }
        Some(th) => {
            println!("PASS: {name} {value} within threshold {th}");
            Ok(ExitCode::SUCCESS)
        }
        None => Ok(ExitCode::SUCCESS),
    }
}

fn apply_overrides(a: &TonemapArgs, p: &mut FilmParams) -> anyhow::Result<()> {
    let t = &mut p.tonemap;
    if let Some(k) = &a.kernel {
        t.kernel = Kernel::from_name(k).with_context(|| format!("unknown kernel {k:?}"))?;
    }
    let set = |dst: &mut f32, v: Option<f32>| {
        if let Some(v) = v {
            *dst = v;
        }
    };
    set(&mut t.reinhard_prescale, a.prescale);
    set(&mut t.reinhard_postscale, a.postscale);
    set(&mut t.reinhard_burn, a.burn);
    set(&mut t.linear_sensitivity, a.sensitivity);
    set(&mut t.linear_exposure, a.exposure);
    set(&mut t.linear_fstop, a.fstop);
    set(&mut t.linear_gamma, a.linear_gamma);
    set(&mut t.contrast_ywa, a.ywa);
    set(&mut t.gamma, a.gamma);
    let f = &mut t.false_colors;
    if let Some(m) = &a.false_method {
        f.method = FalseMethod::from_name(m)
            .with_context(|| format!("unknown falsecolors method {m:?} (linear, log, log3)"))?;
    }
    if let Some(c) = &a.false_colorscale {
        f.scale = FalseScale::from_name(c).with_context(|| {
            format!("unknown falsecolors scale {c:?} (std, lmk, red, white, yellow, speos)")
        })?;
    }
    set(&mut f.max, a.false_max);
    set(&mut f.min, a.false_min);
    if t.kernel == Kernel::FalseColors && !(f.min.is_finite() && f.max.is_finite() && f.min < f.max)
    {
        bail!(
            "the falsecolors kernel needs finite --false-min < --false-max (the FLM gives min {} \
             and max {}; LuxRender's own FLMs carry no range)",
            f.min,
            f.max
        );
    }
    if let Some(c) = &a.clamp {
        t.clamp_method =
            ClampMethod::from_name(c).with_context(|| format!("unknown clamp method {c:?}"))?;
    }
    Ok(())
}

fn tonemap(a: TonemapArgs) -> anyhow::Result<ExitCode> {
    let (film, header) = load(&a.file)?;
    let mut p = FilmParams::from_flm(&header);
    // A camera response named in the FLM is read beside it, when present.
    let dir = a.file.parent().unwrap_or(std::path::Path::new("."));
    let files = luxfarm::fileio::SceneFiles::unconfined(dir);
    if let Err(m) = p.tonemap.effects.load_response(&files) {
        tracing::warn!("camera response not applied: {m}");
    }
    apply_overrides(&a, &mut p)?;
    let ext = a
        .output
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let channels = match &a.channels {
        Some(c) => Channels::from_name(c).with_context(|| format!("unknown channels {c:?}"))?,
        None => Channels::Rgb,
    };
    p.png.enabled = ext == "png";
    p.tga.enabled = ext == "tga";
    p.exr.enabled = ext == "exr";
    p.write_resume_flm = false;
    if !(p.png.enabled || p.tga.enabled || p.exr.enabled) {
        bail!(
            "{}: output must end in .png, .tga or .exr",
            a.output.display()
        );
    }
    p.png.channels = channels;
    p.tga.channels = channels;
    p.exr.channels = channels;
    p.png_16bit = a.png16;
    p.exr_options.applyimaging = !a.untonemapped;
    p.exr_options.halftype = !a.float;
    let base = a.output.with_extension("");
    let written = output::write_outputs(&film, &p, &base)?;
    for w in written {
        println!("wrote {}", w.display());
    }
    Ok(ExitCode::SUCCESS)
}
