//! Rendering one lease: fetch the bundle (cache), build a render session with the lease's seed
//! and stream id (the scene confined to its bundle), render passes on a dedicated thread
//! within the lease's sample budget, and upload deltas every upload interval, when the budget
//! is spent, and at stop.
//!
//! ```text
//! render thread --(a pass while rendered < budget)--> session film
//!   --take (interval, budget spent, stop)--> encoded delta --channel--> upload loop
//! upload loop: pending (not acknowledged) --ack--> retained (acknowledged, not durable)
//!   --durable_seq from acks and heartbeats--> dropped
//!   master restarted (another instance) --> retained go back in front of pending
//! heartbeat loop: every interval, and at once when the render thread needs more budget:
//!   stop, budget, durable_seq, master instance
//! ack.sampling_map --crate::map::MapSlot--> render thread, before its next pass:
//!   checked against the film, Session::set_sampling_map (noise-aware jobs, and jobs with a
//!   user sampling map: the master sends the maps already combined)
//! ```
//!
//! An erpt job's energy quantum is estimated by the first lease of the job a worker renders
//! and remembered for its later ones ([`crate::quanta`]), which skip the warm-up.
//!
//! A worker's session never builds a sampling map from its own film (it only holds the
//! samples since the last delta): a noise-aware job samples uniformly until the master's
//! first map arrives.
//!
//! Retries resend the same bytes under the same sequence number; the master's (lease,
//! sequence) ledger merges each once, so a delta is never lost and never counted twice. The
//! lease ends once its last delta is acknowledged and every acknowledged delta is durable.

use crate::cache::Cache;
use crate::link::{backoff, Link};
use crate::map::MapSlot;
use crate::quanta::{self, Quanta};
use crate::Config;
use anyhow::Context;
use luxfarm::atomic_write::write_bytes_atomic;
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

/// Acknowledged deltas kept at most while waiting for the master to make them durable (it
/// checkpoints every few uploads; more means its checkpoints fail).
const MAX_RETAINED: usize = 64;

/// How long a lease waits, after its last delta, for the master to make it durable.
const DURABLE_WAIT: Duration = Duration::from_secs(600);

/// A delta ready to upload.
struct Delta {
    bytes: Vec<u8>,
    last: bool,
}

/// State shared by the render thread, the uploader and the heartbeat task.
struct Flags {
    /// The master asked the lease to stop (or shutdown): render no more, send the last delta.
    stop: AtomicBool,
    /// The uploader wants the next delta.
    want: AtomicBool,
    /// Samples rendered so far, and per pass (f64 bits).
    samples: AtomicU64,
    pass_samples: AtomicU64,
    /// Samples the lease may render (f64 bits; +inf: unbounded).
    budget: AtomicU64,
    /// Highest sequence number the master holds durably.
    durable: AtomicU64,
    /// The render thread needs more budget: heartbeat now.
    ask: tokio::sync::Notify,
    /// The session's cancel flag: set on stop so a long pass ends between tiles.
    cancel: std::sync::Mutex<Option<Arc<AtomicBool>>>,
    /// The newest sampling map from the master, until the render thread takes it.
    map: MapSlot,
}

fn load_f64(a: &AtomicU64) -> f64 {
    f64::from_bits(a.load(Ordering::Relaxed))
}

fn store_f64(a: &AtomicU64, v: f64) {
    a.store(v.to_bits(), Ordering::Relaxed);
}

impl Flags {
    fn new(budget: Option<f64>) -> Flags {
        Flags {
            stop: AtomicBool::new(false),
            want: AtomicBool::new(false),
            samples: AtomicU64::new(0f64.to_bits()),
            pass_samples: AtomicU64::new(0f64.to_bits()),
            budget: AtomicU64::new(budget.unwrap_or(f64::INFINITY).to_bits()),
            durable: AtomicU64::new(0),
            ask: tokio::sync::Notify::new(),
            cancel: std::sync::Mutex::new(None),
            map: MapSlot::default(),
        }
    }

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

    /// Applies what the master said about the lease.
    fn apply(&self, stop: bool, budget: Option<f64>, durable: u64) {
        store_f64(&self.budget, budget.unwrap_or(f64::INFINITY));
        self.durable.fetch_max(durable, Ordering::SeqCst);
        if stop && self.request_stop() {
            tracing::info!("master asked to stop");
        }
    }
}

/// Renders one lease to its end.
pub async fn run_lease(
    link: &Link,
    cache: &Cache,
    quanta: &Arc<Quanta>,
    cfg: &Config,
    threads: usize,
    a: pb::Assignment,
) -> anyhow::Result<()> {
    tracing::info!(stream = a.stream, seed = a.seed, budget = ?a.budget, "lease started");
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
    let flags = Arc::new(Flags::new(a.budget));
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
        let memo = (
            quanta.clone(),
            quanta::Key {
                bundle_hash: a.bundle_hash.clone(),
                scene_path: a.scene_path.clone(),
                frame,
                seed: a.seed,
            },
        );
        std::thread::Builder::new()
            .name("render".into())
            .spawn(move || {
                render_thread(&root, &scene, frame, opts, &memo, &flags, &shutdown, &tx)
            })?
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

/// The render thread: passes while within the budget; a delta whenever the uploader asks or
/// the budget is spent, and the last one at stop. An erpt job's quantum is taken from the
/// memo when an earlier lease of the job estimated it, and left there after the first pass.
#[allow(clippy::too_many_arguments)]
fn render_thread(
    root: &Path,
    scene: &Path,
    frame: Option<i64>,
    opts: SessionOptions,
    (quanta, key): &(Arc<Quanta>, quanta::Key),
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
    session.follow_external_maps();
    let mut known = session.erpt_quantum().is_some();
    if let Some(q) = quanta.get(key).filter(|_| !known) {
        session.set_erpt_quantum(q);
        known = true;
        tracing::info!(
            quantum = q,
            "erpt: the job's quantum from an earlier lease, no warm-up"
        );
    }
    // Over the sample extent, as the film counts them (luxfarm::render::extent).
    let pass = session.pass_samples() as f64;
    store_f64(&flags.pass_samples, pass);
    *flags.cancel.lock().unwrap_or_else(|p| p.into_inner()) = Some(session.cancel_flag());
    if flags.stop.load(Ordering::SeqCst) {
        session.cancel_flag().store(true, Ordering::SeqCst);
    }
    let send = |session: &mut Session, last: bool| {
        let bytes = encode(&session.take_film());
        tx.blocking_send(Delta { bytes, last }).is_ok()
    };
    let mut unsent = false;
    let mut asked = false;
    loop {
        if flags.stop.load(Ordering::SeqCst) || shutdown.load(Ordering::Relaxed) {
            send(&mut session, true);
            return Ok(());
        }
        if flags.want.swap(false, Ordering::Relaxed) {
            unsent = false;
            if !send(&mut session, false) {
                return Ok(());
            }
        }
        if load_f64(&flags.samples) >= load_f64(&flags.budget) {
            // The budget is spent: hand over what was rendered at once, ask for more.
            if unsent {
                unsent = false;
                if !send(&mut session, false) {
                    return Ok(());
                }
            }
            if !asked {
                asked = true;
                flags.ask.notify_one();
            }
            std::thread::sleep(Duration::from_millis(20));
            continue;
        }
        asked = false;
        apply_map(&mut session, &flags.map);
        let stats = session.render_pass();
        if let Some(q) = session.erpt_quantum() {
            if !known {
                known = true;
                tracing::info!(quantum = q, "erpt: the warm-up estimated the job's quantum");
            }
            quanta.put(key.clone(), q);
        }
        if stats.complete {
            store_f64(
                &flags.samples,
                load_f64(&flags.samples) + stats.samples as f64,
            );
            unsent = true;
        }
    }
}

/// Hands the newest sampling map from the master, if any, to the session; a map that does
/// not fit the film is logged and dropped.
fn apply_map(session: &mut Session, slot: &MapSlot) {
    let Some(m) = slot.take() else {
        return;
    };
    let fp = session.film_params();
    let map = crate::map::decode(&m, fp.x_pixel_count, fp.y_pixel_count)
        .map_err(|e| e.to_string())
        .and_then(|map| {
            session
                .set_sampling_map(Arc::new(map))
                .map_err(|e| e.to_string())
        });
    match map {
        Ok(true) => tracing::info!(version = m.version, "noise-aware sampling map applied"),
        Ok(false) => tracing::debug!("sampling map ignored: the sampler takes no maps"),
        Err(e) => tracing::warn!(version = m.version, error = %e, "sampling map refused"),
    }
}

/// A film delta in the transport encoding (`lxd2`: lossless compressed f64, see
/// `luxfarm_wire::codec`).
pub fn encode(film: &luxfarm::film::Film) -> Vec<u8> {
    luxfarm_wire::codec::encode_delta(film)
}

/// Heartbeats while the lease runs (every interval, and at once when the render thread asks
/// for budget): they bring stop, budget, the durable sequence number and the master instance.
async fn heartbeat_loop(link: Link, lease: String, flags: Arc<Flags>) {
    loop {
        tokio::select! {
            _ = tokio::time::sleep(link.heartbeat_interval()) => {}
            _ = flags.ask.notified() => {}
        }
        let samples = load_f64(&flags.samples);
        let pass = load_f64(&flags.pass_samples);
        if let Some(r) = link.heartbeat(&lease, samples, pass).await {
            link.observe_instance(&r.master_instance);
            flags.apply(r.stop, r.budget, r.durable_seq);
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

/// The deltas of one lease on their way to durability.
struct Queues {
    /// Not yet acknowledged, in sequence order.
    pending: VecDeque<(u64, Delta)>,
    /// Acknowledged, not yet durable, in sequence order.
    retained: VecDeque<(u64, Delta)>,
    /// The master instance the retained deltas were acknowledged by.
    instance: String,
}

impl Queues {
    /// Drops what the master holds durably; after a master restart, puts what it had not
    /// made durable back in front of the pending deltas.
    fn update(&mut self, durable: u64, instance: &str) {
        while self.retained.front().is_some_and(|(s, _)| *s <= durable) {
            self.retained.pop_front();
        }
        if !instance.is_empty() && instance != self.instance {
            if !self.instance.is_empty() && !self.retained.is_empty() {
                tracing::info!(
                    deltas = self.retained.len(),
                    "the master restarted: uploading again what it had not made durable"
                );
            }
            while let Some(d) = self.retained.pop_back() {
                self.pending.push_front(d);
            }
            self.instance = instance.to_string();
        }
    }

    /// Moves the front pending delta to the retained ones (it was acknowledged).
    fn acknowledged(&mut self) {
        if let Some(d) = self.pending.pop_front() {
            self.retained.push_back(d);
        }
        if self.retained.len() > MAX_RETAINED {
            if let Some((seq, _)) = self.retained.pop_front() {
                tracing::error!(
                    seq,
                    "the master makes no delta durable: forgetting the oldest"
                );
            }
        }
    }
}

/// Asks for deltas every interval, uploads them in order, retries with backoff, keeps the
/// acknowledged ones until they are durable.
async fn upload_loop(
    link: &Link,
    cfg: &Config,
    lease: &str,
    interval: Duration,
    flags: &Flags,
    mut rx: tokio::sync::mpsc::Receiver<Delta>,
) -> anyhow::Result<()> {
    let mut q = Queues {
        pending: VecDeque::new(),
        retained: VecDeque::new(),
        instance: link.instance(),
    };
    let mut next_seq = 1u64;
    let mut last_take = Instant::now();
    let mut requested = false;
    let mut render_done = false;
    let mut attempt = 0u32;
    let mut retry_at = Instant::now();
    let mut done_since: Option<Instant> = None;
    let mut shutdown_since: Option<Instant> = None;
    loop {
        q.update(flags.durable.load(Ordering::SeqCst), &link.instance());
        if !requested && q.pending.is_empty() && last_take.elapsed() >= interval {
            flags.want.store(true, Ordering::Relaxed);
            requested = true;
        }
        if !render_done {
            match tokio::time::timeout(Duration::from_millis(50), rx.recv()).await {
                Ok(Some(d)) => {
                    if let Some(dir) = &cfg.keep_deltas {
                        keep(dir, lease, next_seq, &d.bytes, SENT);
                    }
                    q.pending.push_back((next_seq, d));
                    next_seq += 1;
                    requested = false;
                    last_take = Instant::now();
                }
                Ok(None) => render_done = true,
                Err(_) => {}
            }
        } else if q.pending.is_empty() {
            if q.retained.is_empty() {
                return Ok(());
            }
            // The last delta is acknowledged: wait for the master to make it durable.
            let since = *done_since.get_or_insert_with(Instant::now);
            if since.elapsed() > DURABLE_WAIT {
                anyhow::bail!(
                    "the master did not make {} acknowledged delta(s) durable",
                    q.retained.len()
                );
            }
            flags.ask.notify_one();
            tokio::time::sleep(Duration::from_millis(100)).await;
        } else {
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
        if link.shutdown.load(Ordering::Relaxed) {
            let since = *shutdown_since.get_or_insert_with(Instant::now);
            if render_done && since.elapsed() > Duration::from_secs(30) {
                anyhow::bail!(
                    "shutting down: {} delta(s) not acknowledged, {} not yet durable",
                    q.pending.len(),
                    q.retained.len()
                );
            }
        }
        let Some((seq, delta)) = q.pending.front() else {
            continue;
        };
        if Instant::now() < retry_at {
            continue;
        }
        let seq = *seq;
        match link
            .upload(lease, seq, delta.last, &delta.bytes, flags.map.version())
            .await
        {
            Ok(mut ack) => {
                if let Some(m) = ack.sampling_map.take() {
                    flags.map.offer(m);
                }
                tracing::debug!(seq, status = %ack.status, bytes = delta.bytes.len(), "delta acknowledged");
                if let Some(dir) = &cfg.keep_deltas {
                    keep(dir, lease, seq, &delta.bytes, &ack.status);
                }
                q.acknowledged();
                attempt = 0;
                link.observe_instance(&ack.master_instance);
                flags.apply(ack.stop, ack.budget, ack.durable_seq);
            }
            Err(s) if s.code() == Code::Aborted => {
                // The master restarted: learn its instance, then upload again what it lost.
                tracing::info!(reason = %s.message(), "the master restarted");
                let (samples, pass) = (load_f64(&flags.samples), load_f64(&flags.pass_samples));
                if let Some(r) = link.heartbeat(lease, samples, pass).await {
                    link.observe_instance(&r.master_instance);
                    flags.apply(r.stop, r.budget, r.durable_seq);
                } else {
                    retry_at = Instant::now() + backoff(attempt);
                    attempt += 1;
                }
            }
            Err(s)
                if matches!(
                    s.code(),
                    Code::FailedPrecondition | Code::NotFound | Code::PermissionDenied
                ) =>
            {
                tracing::info!(reason = %s.message(), "lease over; dropping unsent deltas");
                flags.request_stop();
                q.pending.clear();
                while rx.recv().await.is_some() {}
                return Ok(());
            }
            Err(s) if matches!(s.code(), Code::InvalidArgument | Code::ResourceExhausted) => {
                tracing::error!(seq, reason = %s.message(), "delta refused by the master");
                q.pending.pop_front();
            }
            Err(s) => {
                tracing::warn!(seq, attempt, reason = %luxfarm_proto::connect::explain(&s),
                    "upload failed; will retry");
                retry_at = Instant::now() + backoff(attempt);
                attempt += 1;
            }
        }
    }
}

/// The status a kept delta has until the master acknowledges it.
const SENT: &str = "sent";

/// Saves a delta for audits (`--keep-deltas`) as `LEASE-SEQ.STATUS.lxd`, atomically (an
/// auditor reading the folder while the worker runs sees whole deltas only): with status
/// [`SENT`] when it is queued for upload, then with the master's acknowledgement status, which
/// replaces the sent copy. A worker killed between an acknowledgement and its record leaves
/// the sent copy: the folder always holds every delta the master may have merged.
fn keep(dir: &Path, lease: &str, seq: u64, bytes: &[u8], status: &str) {
    let name = |status: &str| -> PathBuf { dir.join(format!("{lease}-{seq:06}.{status}.lxd")) };
    let written = std::fs::create_dir_all(dir)
        .map_err(|e| e.to_string())
        .and_then(|_| write_bytes_atomic(&name(status), bytes).map_err(|e| e.to_string()));
    match written {
        Err(e) => tracing::warn!(error = %e, "could not keep delta"),
        Ok(()) if status != SENT => {
            let _ = std::fs::remove_file(name(SENT));
        }
        Ok(()) => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn delta(last: bool) -> Delta {
        Delta {
            bytes: vec![1, 2, 3],
            last,
        }
    }

    fn seqs(v: &VecDeque<(u64, Delta)>) -> Vec<u64> {
        v.iter().map(|(s, _)| *s).collect()
    }

    #[test]
    fn acknowledged_deltas_wait_for_durability_and_return_after_a_restart() {
        let mut q = Queues {
            pending: (1..=4).map(|s| (s, delta(false))).collect(),
            retained: VecDeque::new(),
            instance: "m1".into(),
        };
        q.acknowledged();
        q.acknowledged();
        q.acknowledged();
        assert_eq!(seqs(&q.retained), [1, 2, 3]);
        // The master made 1 durable.
        q.update(1, "m1");
        assert_eq!(seqs(&q.retained), [2, 3]);
        assert_eq!(seqs(&q.pending), [4]);
        // It restarted: 2 and 3 are uploaded again, before 4.
        q.update(1, "m2");
        assert_eq!(seqs(&q.pending), [2, 3, 4]);
        assert!(q.retained.is_empty());
        // The same instance again changes nothing.
        q.update(1, "m2");
        assert_eq!(seqs(&q.pending), [2, 3, 4]);
    }

    #[test]
    fn budget_defaults_to_unbounded() {
        let f = Flags::new(None);
        assert!(load_f64(&f.budget).is_infinite());
        f.apply(false, Some(100.0), 3);
        assert_eq!(load_f64(&f.budget), 100.0);
        assert_eq!(f.durable.load(Ordering::SeqCst), 3);
        f.apply(false, Some(200.0), 1);
        assert_eq!(f.durable.load(Ordering::SeqCst), 3);
        assert!(!f.stop.load(Ordering::SeqCst));
        f.apply(true, None, 0);
        assert!(f.stop.load(Ordering::SeqCst));
    }
}
