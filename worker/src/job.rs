//! Rendering one lease: fetch the bundle (cache), build a render session with the lease's seed
//! and stream id, render passes on a dedicated thread, and upload deltas every upload interval
//! and at stop. The upload queue keeps each encoded delta with its sequence number until the
//! master acknowledges it; retries resend the same bytes under the same number.

use crate::cache::Cache;
use crate::link::{backoff, Link};
use crate::Config;
use anyhow::Context;
use luxfarm::fileio::SceneFiles;
use luxfarm::lxs::ParseOptions;
use luxfarm::render::{Session, SessionOptions};
use luxfarm_proto as pb;
use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};
use tonic::Code;

/// A delta ready to upload.
struct Delta {
    bytes: Vec<u8>,
    last: bool,
}

/// Flags shared by the render thread, the uploader and the heartbeat task.
struct Flags {
    /// The master asked the lease to stop (or shutdown): render no more, send the last delta.
    stop: AtomicBool,
    /// The uploader wants the next delta.
    want: AtomicBool,
    /// Samples rendered so far (f64 bits), for heartbeats.
    samples: AtomicU64,
    /// The session's cancel flag: set on stop so a long pass ends between tiles.
    cancel: std::sync::Mutex<Option<Arc<AtomicBool>>>,
}

impl Flags {
    /// Stops the lease: no more passes, the current one interrupted. True the first time.
    fn request_stop(&self) -> bool {
        let first = !self.stop.swap(true, Ordering::SeqCst);
        if let Some(c) = self
            .cancel
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .as_ref()
        {
            c.store(true, Ordering::SeqCst);
        }
        first
    }
}

/// Renders one lease to its end.
pub async fn run_lease(
    link: &Link,
    cache: &Cache,
    cfg: &Config,
    threads: usize,
    a: pb::Assignment,
) -> anyhow::Result<()> {
    tracing::info!(stream = a.stream, seed = a.seed, "lease started");
    let dir = match cache.get(&a.bundle_hash) {
        Some(d) => d,
        None => {
            let tar = link.fetch_bundle(&a.bundle_hash).await?;
            cache.put(&a.bundle_hash, &tar)?
        }
    };
    let rel = luxfarm_wire::bundle::safe_relative(&a.scene_path)?;
    let scene = dir.join(rel);
    let root = dir.clone();
    let flags = Arc::new(Flags {
        stop: AtomicBool::new(false),
        want: AtomicBool::new(false),
        samples: AtomicU64::new(0),
        cancel: std::sync::Mutex::new(None),
    });
    let (tx, rx) = tokio::sync::mpsc::channel::<Delta>(4);
    let render = {
        let flags = flags.clone();
        let shutdown = link.shutdown.clone();
        let opts = SessionOptions {
            threads,
            seed: a.seed,
            stream: a.stream,
        };
        let frame = a.frame;
        std::thread::Builder::new()
            .name("render".into())
            .spawn(move || render_thread(&root, &scene, frame, opts, &flags, &shutdown, &tx))?
    };
    let hb = tokio::spawn(heartbeat_loop(
        link.clone(),
        a.lease_id.clone(),
        flags.clone(),
    ));
    let interval = Duration::from_secs_f64(a.upload_interval.clamp(0.05, 3600.0));
    let watch = tokio::spawn(shutdown_watch(link.shutdown.clone(), flags.clone()));
    let result = upload_loop(link, cfg, &a.lease_id, interval, &flags, rx).await;
    flags.request_stop();
    watch.abort();
    hb.abort();
    let rendered = tokio::task::spawn_blocking(move || render.join())
        .await
        .context("joining the render thread")?;
    match rendered {
        Ok(Ok(())) => {}
        Ok(Err(e)) => {
            let reason = format!("{e:#}");
            tracing::error!(%reason, "render failed");
            let _ = link.report_failure(&a.lease_id, &reason).await;
            return Err(e);
        }
        Err(_) => anyhow::bail!("the render thread panicked"),
    }
    result
}

/// The render thread: passes until stopped; a delta whenever the uploader asks, and the last
/// one at stop.
fn render_thread(
    root: &Path,
    scene: &Path,
    frame: Option<i64>,
    opts: SessionOptions,
    flags: &Flags,
    shutdown: &AtomicBool,
    tx: &tokio::sync::mpsc::Sender<Delta>,
) -> anyhow::Result<()> {
    let parse = ParseOptions {
        confine_to_root: true,
        frame,
        ..ParseOptions::default()
    };
    // Errors name files relative to the bundle, never the worker's cache path.
    let shown = |e: &dyn std::fmt::Display| {
        anyhow::anyhow!(
            "{}",
            e.to_string().replace(&format!("{}/", root.display()), "")
        )
    };
    let desc = luxfarm::formats::load(scene, &parse).map_err(|e| shown(&e))?;
    let base = scene.parent().unwrap_or(root);
    // Every file the scene names is opened inside the bundle (luxfarm::fileio).
    let files = SceneFiles::confined(root, base).map_err(|e| shown(&e))?;
    let mut session = Session::new(&desc, files, opts).map_err(|e| shown(&e))?;
    *flags.cancel.lock().unwrap_or_else(|p| p.into_inner()) = Some(session.cancel_flag());
    if flags.stop.load(Ordering::SeqCst) {
        session.cancel_flag().store(true, Ordering::SeqCst);
    }
    loop {
        let stopping = flags.stop.load(Ordering::SeqCst) || shutdown.load(Ordering::Relaxed);
        if stopping {
            let film = session.take_film();
            let bytes = encode(&film);
            let _ = tx.blocking_send(Delta { bytes, last: true });
            return Ok(());
        }
        let stats = session.render_pass();
        if stats.complete {
            let prev = f64::from_bits(flags.samples.load(Ordering::Relaxed));
            flags
                .samples
                .store((prev + stats.samples as f64).to_bits(), Ordering::Relaxed);
        }
        if flags.want.swap(false, Ordering::Relaxed) {
            let film = session.take_film();
            let bytes = encode(&film);
            if tx.blocking_send(Delta { bytes, last: false }).is_err() {
                return Ok(());
            }
        }
    }
}

/// A film delta in the transport encoding (`lxd2`: lossless compressed f64, see
/// `luxfarm_wire::codec`).
pub fn encode(film: &luxfarm::film::Film) -> Vec<u8> {
    luxfarm_wire::codec::encode_delta(film)
}

/// Heartbeats while the lease runs; a stop reply stops the lease.
async fn heartbeat_loop(link: Link, lease: String, flags: Arc<Flags>) {
    loop {
        tokio::time::sleep(link.heartbeat_interval()).await;
        let samples = f64::from_bits(flags.samples.load(Ordering::Relaxed));
        if link.heartbeat(&lease, samples).await == Some(true) && flags.request_stop() {
            tracing::info!("master asked to stop");
        }
    }
}

/// Turns a shutdown (SIGTERM) into a stop of the lease.
async fn shutdown_watch(shutdown: Arc<AtomicBool>, flags: Arc<Flags>) {
    while !shutdown.load(Ordering::Relaxed) {
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    flags.request_stop();
}

/// Asks for deltas every interval, uploads them in order, retries with backoff.
async fn upload_loop(
    link: &Link,
    cfg: &Config,
    lease: &str,
    interval: Duration,
    flags: &Flags,
    mut rx: tokio::sync::mpsc::Receiver<Delta>,
) -> anyhow::Result<()> {
    let mut queue: VecDeque<(u64, Delta)> = VecDeque::new();
    let mut next_seq = 1u64;
    let mut last_take = Instant::now();
    let mut requested = false;
    let mut render_done = false;
    let mut attempt = 0u32;
    let mut retry_at = Instant::now();
    let mut shutdown_since: Option<Instant> = None;
    loop {
        if !requested && queue.is_empty() && last_take.elapsed() >= interval {
            flags.want.store(true, Ordering::Relaxed);
            requested = true;
        }
        if !render_done {
            match tokio::time::timeout(Duration::from_millis(50), rx.recv()).await {
                Ok(Some(d)) => {
                    queue.push_back((next_seq, d));
                    next_seq += 1;
                    requested = false;
                    last_take = Instant::now();
                }
                Ok(None) => render_done = true,
                Err(_) => {}
            }
        } else if queue.is_empty() {
            return Ok(());
        } else {
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
        if link.shutdown.load(Ordering::Relaxed) {
            let since = *shutdown_since.get_or_insert_with(Instant::now);
            if render_done && since.elapsed() > Duration::from_secs(30) {
                anyhow::bail!(
                    "shutting down: {} delta(s) could not be uploaded",
                    queue.len()
                );
            }
        }
        let Some((seq, delta)) = queue.front() else {
            continue;
        };
        if Instant::now() < retry_at {
            continue;
        }
        match link.upload(lease, *seq, delta.last, &delta.bytes).await {
            Ok(ack) => {
                tracing::debug!(seq, status = %ack.status, bytes = delta.bytes.len(), "delta acknowledged");
                if let Some(dir) = &cfg.keep_deltas {
                    keep(dir, lease, *seq, &delta.bytes, &ack.status);
                }
                queue.pop_front();
                attempt = 0;
                if ack.stop && flags.request_stop() {
                    tracing::info!("master asked to stop");
                }
            }
            Err(s) if matches!(s.code(), Code::FailedPrecondition | Code::NotFound) => {
                tracing::info!(reason = %s.message(), "lease over; dropping unsent deltas");
                flags.request_stop();
                queue.clear();
                while rx.recv().await.is_some() {}
                return Ok(());
            }
            Err(s) if s.code() == Code::InvalidArgument => {
                tracing::error!(seq, reason = %s.message(), "delta refused by the master");
                queue.pop_front();
            }
            Err(s) => {
                tracing::warn!(seq, attempt, reason = %s.message(), "upload failed; will retry");
                retry_at = Instant::now() + backoff(attempt);
                attempt += 1;
            }
        }
    }
}

/// Saves an acknowledged delta for audits (`--keep-deltas`).
fn keep(dir: &Path, lease: &str, seq: u64, bytes: &[u8], status: &str) {
    let name: PathBuf = dir.join(format!("{lease}-{seq:06}.{status}.lxd"));
    if let Err(e) = std::fs::create_dir_all(dir).and_then(|_| std::fs::write(&name, bytes)) {
        tracing::warn!(error = %e, "could not keep delta");
    }
}
