//! luxfarm master: accepts jobs (REST and gRPC on one port), leases sample streams to workers,
//! merges their film deltas into each job's f64 film, evaluates the halt rules, checkpoints,
//! and serves outputs, metrics and an OpenAPI document.
//!
//! - `config`: command-line options; `serve`: the listener (gRPC + REST, identities, TLS,
//!   the drain at shutdown); `conn`: connection limits and timeouts before authentication.
//! - `farm`: shared state, submission; `datadir`: the data directory's checks at startup;
//!   `admission`: what a job may cost and whether it can render; `auth`: identities, roles,
//!   tokens; `registry`: worker registration (protocol versions, credentials); `lease`:
//!   leases, uploads, heartbeats; `scratch`: the films deltas are decoded into, reused;
//!   `budget`: per-lease sample budgets (precise haltspp); `halt`: halt rules, checkpoints,
//!   job end, cancel; `analysis`: the film's convergence tests and noise-aware maps, on the
//!   tick rather than the upload path, within a share of the master's time; `db`: the SQLite
//!   store (schema versions and upgrades in `db::migrate`); `schedule`: which job a worker
//!   gets (priority, tags, memory, sequence policies); `sequence`: frame sequences;
//!   `blocks`: failing workers blocked from jobs and quarantined; `noisemap`: noise-aware
//!   sampling maps built from the merged film, combined with the job's user sampling map
//!   (`usermap`: set through REST, kept in the store), sent to workers with their
//!   acknowledgements;
//!   `trade`: each running job's error estimate over time, its projection to a target and the
//!   convergence map picture.
//!
//! Durability of acknowledged deltas: a delta is acknowledged once merged into the job's film
//! in memory, and becomes durable with the next checkpoint (the film written atomically, then
//! the ledger rows it holds committed). Workers keep every acknowledged delta the master has
//! not yet reported durable (`durable_seq` in acknowledgements and heartbeats) and upload
//! those again when the master's instance changes (it restarted, after a crash or
//! `kill -9`); the (lease, sequence) ledger merges each delta once, so nothing acknowledged is
//! lost and nothing is counted twice, without the master writing every delta to disk.
//! SIGTERM/SIGINT drain: no new leases or uploads, uploads in flight merged, every job
//! checkpointed, then exit.
//! - Bundles and film deltas are decoded with `luxfarm-wire`, which the client and the workers
//!   share.
//! - `scene`: what the master asks of the render core; `output`: outputs on demand.
//! - `rest`, `grpc`, `views`, `metrics`, `error`; `dashboard`: the web page; `events`: the
//!   Server-Sent Events stream the dashboard listens to; `webhooks`: jobs' ends posted to
//!   hook URLs (signed, retried, from an outbox in the store that survives restarts).
//!
//! The public surface is what the `luxfarm` command needs to run or embed a master
//! ([`Config`], [`run`], [`start`], [`Running`]) and what the capacity benchmark reads through
//! [`Running`] ([`SubmitOptions`], [`MergeReport`]); everything else is internal.

pub(crate) mod admission;
pub(crate) mod analysis;
pub(crate) mod auth;
pub(crate) mod blocks;
pub(crate) mod budget;
pub(crate) mod config;
pub(crate) mod conn;
pub(crate) mod dashboard;
pub(crate) mod datadir;
pub(crate) mod db;
pub(crate) mod error;
pub(crate) mod events;
pub(crate) mod farm;
pub(crate) mod grpc;
pub(crate) mod halt;
pub(crate) mod lease;
pub(crate) mod metrics;
pub(crate) mod noisemap;
#[expect(
    dead_code,
    reason = "`render` and `Output::version` are unused since the module became private; the \
              output module is being rewritten (issue 12 part 2), which uses or removes them"
)]
pub(crate) mod output;
pub(crate) mod registry;
pub(crate) mod rest;
pub(crate) mod scene;
pub(crate) mod schedule;
pub(crate) mod scratch;
pub(crate) mod sequence;
pub(crate) mod serve;
#[cfg(test)]
mod test_util;
pub(crate) mod trade;
pub(crate) mod usermap;
pub(crate) mod views;
pub(crate) mod webhooks;

/// The delta codec, as `crate::codec` (checkpoints are written and read through it).
pub(crate) use luxfarm_wire::codec;

pub use admission::SubmitOptions;
pub use config::Config;
pub use error::ServerError;
pub use metrics::{MergeReport, MergeTiming};
pub use serve::{start, Running};

/// Runs the master until Ctrl-C / SIGTERM, printing `listening on ADDR` once bound; a signal
/// drains the master (see the crate docs) before it exits.
pub async fn run(cfg: Config) -> anyhow::Result<()> {
    let mut running = start(cfg).await?;
    let addr = running.addr();
    println!("listening on {addr}");
    tracing::info!(%addr, "luxfarm master listening");
    let mut term = tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate())?;
    tokio::select! {
        _ = tokio::signal::ctrl_c() => {}
        _ = term.recv() => {}
        r = running.task_mut() => { r?; return Ok(()); }
    }
    tracing::info!("signal received: draining (no new leases or uploads, checkpointing)");
    let failed = running.drain(std::time::Duration::from_secs(30)).await;
    if failed > 0 {
        anyhow::bail!("{failed} job checkpoint(s) failed at shutdown");
    }
    tracing::info!("drained: every job checkpointed");
    Ok(())
}
