//! `luxfarm render SCENE.lxs --workers N`: the one-command farm. An embedded master in a
//! temporary data directory, N local worker processes (`luxfarm worker`, spawned from this
//! executable) over loopback, a progress bar, the dashboard URL printed, and the outputs
//! written beside the scene (or at `-o BASENAME`): the master writes the files the Film asks
//! for (`luxfarm::output`) and they are copied to the names a local render gives them.
//!
//! The render command's argument parsing (client/src/cmd/render.rs) calls [`render`] when
//! `--workers` is given.

use super::farm_remote::{runtime, Remote};
use anyhow::Context;
use luxfarm::film::FilmParams;
use luxfarm::lxs::ParseOptions;
use luxfarm::output::{self, OutputKind};
use luxfarm_proto as pb;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

/// What `luxfarm render --workers N` needs.
#[derive(Clone, Debug)]
pub struct Options {
    pub scene: PathBuf,
    pub workers: usize,
    /// Render threads per worker (default: cores / workers, at least 1).
    pub threads: Option<usize>,
    pub haltspp: Option<f64>,
    pub halttime: Option<f64>,
    pub haltthreshold: Option<f64>,
    pub seed: Option<u64>,
    /// Output base name (default: the film's `filename`, beside the scene).
    pub output: Option<PathBuf>,
    /// Seconds between worker uploads (default 2: a local farm can merge often).
    pub upload_interval: f64,
    /// The animation frame to render (animated scene formats).
    pub frame: Option<i64>,
}

/// Worker processes, terminated (SIGTERM, then waited for) when dropped.
struct Workers(Vec<Child>);

impl Drop for Workers {
    fn drop(&mut self) {
        for c in &self.0 {
            // SIGTERM lets a worker upload its last delta and exit cleanly.
            if let Ok(pid) = i32::try_from(c.id()) {
                // SAFETY: kill(2) on a child process id we spawned and still own.
                unsafe {
                    libc::kill(pid, libc::SIGTERM);
                }
            }
        }
        for c in &mut self.0 {
            let _ = c.wait();
        }
    }
}

fn spawn_workers(url: &str, n: usize, threads: usize) -> anyhow::Result<Workers> {
    let exe = std::env::current_exe()?;
    let mut children = Vec::new();
    for i in 0..n {
        let child = Command::new(&exe)
            .args(["worker", "--master", url, "--threads", &threads.to_string()])
            .args(["--name", &format!("local-{}", i + 1)])
            .env_remove("LUXFARM_TOKEN")
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .spawn()?;
        children.push(child);
    }
    Ok(Workers(children))
}

/// What a local farm render did: the files written and the job's last figures.
#[derive(Clone, Debug)]
pub struct Outcome {
    pub written: Vec<PathBuf>,
    pub spp: f64,
    pub samples: f64,
    /// Seconds the job rendered (as the master counts them).
    pub elapsed: f64,
}

/// Renders a scene on a local farm and returns the files written beside the scene (or at
/// `-o`).
pub fn render(o: Options) -> anyhow::Result<Vec<PathBuf>> {
    Ok(render_job(o)?.written)
}

/// [`render`], with the job's figures (`luxfarm study` measures farms with them).
pub fn render_job(o: Options) -> anyhow::Result<Outcome> {
    let upload = luxfarm_wire::bundle::prepare(&o.scene)?;
    let data = tempfile::Builder::new()
        .prefix("luxfarm-render-")
        .tempdir()?;
    let rt = runtime()?;
    let mut cfg = luxfarm_server::Config::local(data.path().to_path_buf());
    cfg.upload_interval = o.upload_interval;
    cfg.checkpoint_interval = 10.0;
    let running = rt.block_on(luxfarm_server::start(cfg))?;
    let url = format!("http://{}", running.addr());
    eprintln!("dashboard: {url}/");
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let threads = o.threads.unwrap_or((cores / o.workers.max(1)).max(1));
    let workers = spawn_workers(&url, o.workers.max(1), threads)?;
    let remote = Remote {
        master: url,
        token: None,
        ca_cert: None,
    };
    let header = pb::SubmitHeader {
        file_name: upload.file_name,
        haltspp: o.haltspp,
        halttime: o.halttime,
        haltthreshold: o.haltthreshold,
        seed: o.seed,
        frame: o.frame,
        ..Default::default()
    };
    let job = rt.block_on(super::submit::submit(&remote, header, upload.bytes))?;
    let last = rt.block_on(super::watch::follow(&remote, &job.id, |_| {}))?;
    drop(workers);
    if last.state != "done" {
        anyhow::bail!("job {} {}: {}", last.id, last.state, last.reason);
    }
    let out_dir = data.path().join("jobs").join(&job.id).join("out");
    let written = copy_outputs(&out_dir, &o)?;
    eprintln!(
        "{:.1} spp in {:.1} s ({:.0} samples/s)",
        last.spp,
        last.elapsed,
        if last.elapsed > 0.0 {
            last.samples / last.elapsed
        } else {
            0.0
        }
    );
    running.stop();
    Ok(Outcome {
        written,
        spp: last.spp,
        samples: last.samples,
        elapsed: last.elapsed,
    })
}

/// The base name of the outputs on this machine: `-o`, else as a local render names them
/// (`luxfarm::output::basename`, from the scene's Film), else (an archive, whose scene only
/// the master read) the master's base name beside the archive.
fn local_basename(o: &Options, master_base: &str) -> anyhow::Result<PathBuf> {
    if let Some(b) = &o.output {
        return Ok(b.clone());
    }
    let is_archive = o
        .scene
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("zip") || e.eq_ignore_ascii_case("tar"));
    if is_archive {
        let dir = o.scene.parent().unwrap_or(Path::new(""));
        return Ok(dir.join(master_base));
    }
    let parse = ParseOptions {
        frame: o.frame,
        ..ParseOptions::default()
    };
    let desc = luxfarm::formats::load(&o.scene, &parse)?;
    let params = FilmParams::from_entity(desc.film.as_ref())?;
    Ok(output::basename(&o.scene, &params, None))
}

/// Copies the outputs the master wrote (`BASE.png`, `.exr`, ... in `out_dir`, as the Film
/// asked) to the same names a local render gives them.
fn copy_outputs(out_dir: &Path, o: &Options) -> anyhow::Result<Vec<PathBuf>> {
    let mut found = Vec::new();
    for entry in std::fs::read_dir(out_dir)? {
        let src = entry?.path();
        let name = src
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or_default()
            .to_string();
        let kind = OutputKind::ALL
            .into_iter()
            .find(|k| name.len() > k.suffix().len() && name.ends_with(k.suffix()));
        if let Some(kind) = kind {
            let base = name[..name.len() - kind.suffix().len()].to_string();
            found.push((src, base, kind));
        }
    }
    let Some((_, master_base, _)) = found.first() else {
        return Ok(Vec::new());
    };
    let local = local_basename(o, master_base)?;
    let mut written = Vec::new();
    for (src, _, kind) in &found {
        let dest = output::path(&local, *kind);
        std::fs::copy(src, &dest)
            .with_context(|| format!("copying {} to {}", src.display(), dest.display()))?;
        written.push(dest);
    }
    written.sort();
    Ok(written)
}
