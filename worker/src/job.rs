//! Rendering one lease: fetch the bundle (cache), build a render session with the lease's seed
//! and stream id (the scene confined to its bundle), render passes on a dedicated thread
//! within the lease's sample budget, and upload deltas every upload interval, when the budget
//! is spent, and at stop.
//!
//! ```text
//! render thread --(a sweep of passes while rendered < budget, each sweep within the upload
//!   interval at the last sweep's pace; a chain pass until the uploader asks or a stop,
//!   then wrapped up)--> session film
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
//! A pass of metropolis or erpt can last minutes on a big film. It is wrapped up
//! (`luxfarm::render::stops`: ended at its next batch boundary, its work kept and counted)
//! when the uploader asks for a delta, so a job's preview moves every upload interval, and
//! when the lease is told to stop, so the partial pass goes out as the last delta instead of
//! being dropped. A pixel sampler's tile pass is cancelled at a stop instead (it counts only
//! whole) and the deltas hold the passes done; its sweeps already fit the upload interval.
//!
//! An erpt job's energy quantum is estimated by the first lease of the job a worker renders
//! and remembered for its later ones ([`crate::quanta`]), which skip the warm-up (a wrapped-up
//! first pass still runs the whole warm-up, so the memo is filled as before).
//!
//! A worker's session never builds a sampling map from its own film (it only holds the
//! samples since the last delta): a noise-aware job samples uniformly until the master's
//! first map arrives.
//!
//! Retries resend the same bytes under the same sequence number; the master's (lease,
//! sequence) ledger merges each once, so a delta is never lost and never counted twice. The
//! lease ends once its last delta is acknowledged and every acknowledged delta is durable.
//!
//! This file runs the lease and its render thread; the state they share with the uploader and
//! the heartbeats is in `flags.rs`, the upload loop and its queues in `upload.rs`.

use crate::cache::Cache;
use crate::flags::{load_f64, store_f64, Flags};
use crate::link::Link;
use crate::map::MapSlot;
use crate::quanta::{self, Quanta};
use crate::upload::{upload_loop, Delta};
use crate::Config;
use anyhow::Context;
use luxfarm::fileio::SceneFiles;
use luxfarm::lxs::ParseOptions;
use luxfarm::render::{Session, SessionOptions};
use luxfarm_proto as pb;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

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
    let interval = Duration::from_secs_f64(a.upload_interval.clamp(0.05, 3600.0));
    let flags = Arc::new(Flags::new(a.budget, interval.as_secs_f64()));
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
    // A stop cancels a tile pass and wraps up a chain pass (kept: the last delta carries
    // it); the uploader's ask for a delta wraps up a chain pass too (`crate::flags`).
    let chains = session.runs_chains();
    flags.attach(session.cancel_flag(), session.wrap_up_flag(), chains);
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
        if flags.take_want() {
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
        // A sweep of passes within the lease's budget and its upload interval (at least one
        // pass; an unbounded budget sweeps as far as the session allows: the cast saturates).
        let left = (load_f64(&flags.budget) - load_f64(&flags.samples)) / pass;
        let max = if left >= 1.0 { left as u64 } else { 1 };
        let max = max.min(session.passes_within(flags.upload_secs));
        let stats = session.render_passes(max);
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
