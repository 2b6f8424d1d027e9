//! `luxfarm regress DIR [--workers N] [--metric mse|rms] [--haltspp N] [-o OUT]`: LuxRender's
//! regression runner for TestSuite-style folders.
//!
//! Every `.cfg` file under DIR describes one test as LuxRender's runner reads it
//! (`sceneFile`, `referenceFilm`, `testFilm`, `errorTreshold` — LuxRender's spelling —, and
//! `cleanFiles`, relative to the .cfg's folder). Each scene is rendered (locally, or on a
//! local farm with `--workers`), its resume FLM is compared with the reference film as
//! luxcomp compares films, and one table row is printed per test.
//!
//! The threshold bounds the MSE by default: LuxRender's runner called `luxcomp -e THRESHOLD`
//! without choosing a metric, and luxcomp's default metric is the MSE. `--metric rms` bounds
//! the RMS instead. Beside the verdict, block-level figures (`luxfarm::film::block_bias`:
//! the overall scale and the 32-pixel block error with and without that scale) show whether
//! a failure is bias or the reference's own noise (an older, spectral LuxRender reference).
//!
//! Outputs go to a temporary folder (removed afterwards) or to `-o OUT`, mirroring DIR's
//! folders; the TestSuite folder itself is never written to. Exit status: 0 when every test
//! with a reference passes, 1 when one fails or cannot render, 2 when a .cfg is malformed.

use crate::exit::InputError;
use anyhow::Context;
use luxfarm::film::{block_bias, compare, read_flm_file, BlockBias, Comparison};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// The folder searched (recursively) for .cfg test descriptions.
    pub dir: PathBuf,
    /// The metric the .cfg's errorTreshold bounds.
    #[arg(long, value_enum, default_value_t = super::flm::Metric::Mse)]
    pub metric: super::flm::Metric,
    /// Render on a local farm of this many workers instead of locally.
    #[arg(long)]
    pub workers: Option<usize>,
    /// Render threads (per worker with --workers; 0: all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Stop at this many samples per pixel instead of the scene's haltspp.
    #[arg(long)]
    pub haltspp: Option<u32>,
    /// Seed of the sample streams.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Keep the rendered outputs in this folder (default: a temporary folder).
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
    /// Block edge in pixels for the block-level figures.
    #[arg(long, default_value_t = 32)]
    pub block: u32,
}

/// One test as a .cfg file describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct TestCfg {
    pub path: PathBuf,
    pub scene: PathBuf,
    pub reference: PathBuf,
    /// The name of the film the scene writes (only its stem is used: outputs are redirected).
    pub test_film: String,
    pub threshold: f64,
}

/// What happened to one test.
enum Outcome {
    Compared { c: Comparison, blocks: BlockBias },
    NoReference,
    Failed(String),
}

/// Maximum depth of folders searched below DIR.
const MAX_DEPTH: usize = 32;

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let mut cfgs = Vec::new();
    find_cfgs(&args.dir, 0, &mut cfgs)
        .with_context(|| format!("searching {}", args.dir.display()))?;
    cfgs.sort();
    if cfgs.is_empty() {
        return Err(InputError(format!(
            "{}: no .cfg test descriptions found",
            args.dir.display()
        ))
        .into());
    }
    let tests = cfgs
        .iter()
        .map(|p| parse_cfg_file(p))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let tmp = tempfile::Builder::new()
        .prefix("luxfarm-regress-")
        .tempdir()?;
    let out_root = args
        .output
        .clone()
        .unwrap_or_else(|| tmp.path().to_path_buf());
    let mut rows = Vec::new();
    for t in &tests {
        eprintln!("regress: {}", t.path.display());
        let start = Instant::now();
        let outcome = run_test(&args, t, &out_root);
        rows.push((t, outcome, start.elapsed().as_secs_f64()));
    }
    print_table(&args, &rows);
    let failed = rows.iter().any(|(t, o, _)| match o {
        Outcome::Compared { c, .. } => metric_value(args.metric, c) > t.threshold,
        Outcome::Failed(_) => true,
        Outcome::NoReference => false,
    });
    Ok(if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

fn find_cfgs(dir: &Path, depth: usize, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    if depth > MAX_DEPTH {
        return Ok(());
    }
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let ty = entry.file_type()?;
        let path = entry.path();
        if ty.is_dir() {
            find_cfgs(&path, depth + 1, out)?;
        } else if ty.is_file()
            && path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("cfg"))
        {
            out.push(path);
        }
    }
    Ok(())
}

fn parse_cfg_file(path: &Path) -> anyhow::Result<TestCfg> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    Ok(parse_cfg(path, &text)?)
}

/// Reads a .cfg: `key = value` lines, values quoted or bare, `#` comments.
pub fn parse_cfg(path: &Path, text: &str) -> Result<TestCfg, InputError> {
    let dir = path.parent().unwrap_or(Path::new(""));
    let at = |line: usize, msg: String| InputError(format!("{}:{line}:1: {msg}", path.display()));
    let (mut scene, mut reference, mut test_film, mut threshold) = (None, None, None, None);
    for (i, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let Some((key, value)) = line.split_once('=') else {
            return Err(at(i + 1, format!("expected key = value, found {line:?}")));
        };
        let value = value.trim().trim_matches('"').to_string();
        match key.trim() {
            "sceneFile" => scene = Some(value),
            "referenceFilm" => reference = Some(value),
            "testFilm" => test_film = Some(value),
            "errorTreshold" | "errorThreshold" => {
                let v: f64 = value
                    .parse()
                    .ok()
                    .filter(|v: &f64| v.is_finite() && *v >= 0.0)
                    .ok_or_else(|| {
                        at(
                            i + 1,
                            format!("errorTreshold {value:?} is not a number >= 0"),
                        )
                    })?;
                threshold = Some(v);
            }
            _ => {}
        }
    }
    let missing = |k: &str| at(1, format!("no {k} line"));
    let scene = scene.ok_or_else(|| missing("sceneFile"))?;
    let reference = reference.ok_or_else(|| missing("referenceFilm"))?;
    let threshold = threshold.ok_or_else(|| missing("errorTreshold"))?;
    Ok(TestCfg {
        path: path.to_path_buf(),
        scene: dir.join(&scene),
        reference: dir.join(reference),
        test_film: test_film.unwrap_or_else(|| {
            Path::new(&scene)
                .with_extension("flm")
                .to_string_lossy()
                .into_owned()
        }),
        threshold,
    })
}

/// Where a test's outputs go: OUT mirroring the .cfg's folder below DIR.
fn output_base(args: &Args, t: &TestCfg, out_root: &Path) -> PathBuf {
    let rel = t
        .path
        .parent()
        .and_then(|p| p.strip_prefix(&args.dir).ok())
        .unwrap_or(Path::new(""));
    let stem = Path::new(&t.test_film)
        .file_stem()
        .map_or_else(|| "test".into(), |s| s.to_os_string());
    out_root.join(rel).join(stem)
}

fn run_test(args: &Args, t: &TestCfg, out_root: &Path) -> Outcome {
    if !t.reference.is_file() {
        return Outcome::NoReference;
    }
    match render_and_compare(args, t, out_root) {
        Ok((c, blocks)) => Outcome::Compared { c, blocks },
        Err(e) => Outcome::Failed(format!("{e:#}")),
    }
}

fn render_and_compare(
    args: &Args,
    t: &TestCfg,
    out_root: &Path,
) -> anyhow::Result<(Comparison, BlockBias)> {
    let base = output_base(args, t, out_root);
    if let Some(parent) = base.parent() {
        std::fs::create_dir_all(parent)?;
    }
    let written = super::render::render(super::render::Args {
        scene: t.scene.clone(),
        threads: args.threads,
        haltspp: args.haltspp,
        halttime: None,
        haltthreshold: None,
        seed: args.seed,
        output: Some(base.clone()),
        frame: None,
        workers: args.workers,
        sampling_map: None,
    })?;
    let flm = written
        .into_iter()
        .find(|p| p.extension().is_some_and(|e| e == "flm"))
        .ok_or_else(|| {
            anyhow::anyhow!("the scene's Film writes no FLM (write_resume_flm is off)")
        })?;
    let (reference, _) = read_flm_file(&t.reference)
        .with_context(|| format!("reading {}", t.reference.display()))?;
    let (test, _) = read_flm_file(&flm).with_context(|| format!("reading {}", flm.display()))?;
    Ok((
        compare(&reference, &test)?,
        block_bias(&reference, &test, args.block)?,
    ))
}

fn metric_value(m: super::flm::Metric, c: &Comparison) -> f64 {
    match m {
        super::flm::Metric::Mse => c.mse,
        super::flm::Metric::Rms => c.rms,
    }
}

fn print_table(args: &Args, rows: &[(&TestCfg, Outcome, f64)]) {
    let metric = match args.metric {
        super::flm::Metric::Mse => "MSE",
        super::flm::Metric::Rms => "RMS",
    };
    println!(
        "{:<6} {:>10} {:>9} {:>8} {:>11} {:>11} {:>8}  test",
        "result",
        metric,
        "threshold",
        "scale",
        format!("blk{}", args.block),
        "blk/scale",
        "seconds"
    );
    for (t, o, secs) in rows {
        let name = t.path.strip_prefix(&args.dir).unwrap_or(&t.path).display();
        match o {
            Outcome::Compared { c, blocks } => {
                let v = metric_value(args.metric, c);
                let verdict = if v <= t.threshold { "PASS" } else { "FAIL" };
                println!(
                    "{verdict:<6} {v:>10.5} {:>9} {:>8.4} {:>11.4} {:>11.4} {secs:>8.1}  {name}",
                    t.threshold, blocks.scale, blocks.rms_rel, blocks.rms_rel_unscaled
                );
            }
            Outcome::NoReference => println!(
                "{:<6} {:>10} {:>9} {:>8} {:>11} {:>11} {:>8}  {name}: no reference film {}",
                "SKIP",
                "-",
                t.threshold,
                "-",
                "-",
                "-",
                "-",
                t.reference.display()
            ),
            Outcome::Failed(e) => println!(
                "{:<6} {:>10} {:>9} {:>8} {:>11} {:>11} {secs:>8.1}  {name}: {e}",
                "ERROR", "-", t.threshold, "-", "-", "-"
            ),
        }
    }
    println!(
        "{metric} bounds the threshold ({}); scale = test/reference luminance; blk{} = RMS of \
         {}-pixel block ratios - 1; blk/scale = the same with the scale divided out",
        match args.metric {
            super::flm::Metric::Mse => "as LuxRender's runner applied it",
            super::flm::Metric::Rms => "--metric rms",
        },
        args.block,
        args.block
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cfg_files_read_as_luxrenders_runner_reads_them() {
        let p = Path::new("/suite/a/simple.cfg");
        let t = parse_cfg(
            p,
            "# a test\nsceneFile = \"default.lxs\"\nreferenceFilm = \"reference.flm\"\n\
             testFilm = \"default.flm\"\nerrorTreshold = 0.25\ncleanFiles = \"x,y\"\n",
        )
        .unwrap();
        assert_eq!(t.scene, Path::new("/suite/a/default.lxs"));
        assert_eq!(t.reference, Path::new("/suite/a/reference.flm"));
        assert_eq!(t.test_film, "default.flm");
        assert_eq!(t.threshold, 0.25);
    }

    #[test]
    fn malformed_cfg_files_are_located() {
        let p = Path::new("t.cfg");
        let e = parse_cfg(p, "sceneFile = \"a.lxs\"\nnonsense\n").unwrap_err();
        assert!(e.0.starts_with("t.cfg:2:1:"), "{}", e.0);
        let e = parse_cfg(
            p,
            "sceneFile = a.lxs\nreferenceFilm = r.flm\nerrorTreshold = x\n",
        )
        .unwrap_err();
        assert!(e.0.starts_with("t.cfg:3:1:"), "{}", e.0);
        let e = parse_cfg(p, "sceneFile = a.lxs\nerrorTreshold = 1\n").unwrap_err();
        assert!(e.0.contains("referenceFilm"), "{}", e.0);
    }
}
