//! `luxfarm render SCENE.lxs --workers N`: the one-command farm. An embedded master in a
//! temporary data directory, N local worker processes (`luxfarm worker`, spawned from this
//! executable) over loopback, a progress bar, the dashboard URL printed, and the outputs
//! written beside the scene (or at `-o BASENAME`).
//!
//! The render command's argument parsing (client/src/cmd/render.rs) calls [`run`] when
//! `--workers` is given.

use super::farm_remote::{runtime, Remote};
use luxfarm_proto as pb;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitCode, Stdio};

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

/// Renders a scene on a local farm.
pub fn run(o: Options) -> anyhow::Result<ExitCode> {
    let upload = super::farm_bundle::prepare(&o.scene)?;
    let data = tempfile::Builder::new()
        .prefix("luxfarm-render-")
        .tempdir()?;
    let rt = runtime()?;
    let mut cfg = luxfarm_server::Config::local(data.path().to_path_buf());
    cfg.upload_interval = o.upload_interval;
    cfg.checkpoint_interval = 10.0;
    let running = rt.block_on(luxfarm_server::start(cfg))?;
    let url = format!("http://{}", running.addr);
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
    for p in &written {
        println!("{}", p.display());
    }
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
    running.task.abort();
    Ok(ExitCode::SUCCESS)
}

/// Copies the master's outputs beside the scene (or to the `-o` base name).
fn copy_outputs(out_dir: &Path, o: &Options) -> anyhow::Result<Vec<PathBuf>> {
    let scene_dir = o.scene.parent().unwrap_or(Path::new("."));
    let mut written = Vec::new();
    for entry in std::fs::read_dir(out_dir)? {
        let src = entry?.path();
        let Some(ext) = src.extension().and_then(|e| e.to_str()) else {
            continue;
        };
        let dest = match &o.output {
            Some(base) => base.with_extension(ext),
            None => scene_dir.join(src.file_name().unwrap_or_default()),
        };
        std::fs::copy(&src, &dest)?;
        written.push(dest);
    }
    written.sort();
    Ok(written)
}
