//! luxfarm master: accepts jobs (REST and gRPC on one port), leases sample streams to workers,
//! merges their film deltas into each job's f64 film, evaluates the halt rules, checkpoints,
//! and serves outputs, metrics and an OpenAPI document.
//!
//! - `config`: command-line options; `serve`: the listener (gRPC + REST, token, TLS).
//! - `farm`: shared state, submission, cancel; `lease`: workers, leases, uploads;
//!   `halt`: halt rules, checkpoints, job end; `db`: the SQLite store.
//! - Bundles and film deltas are decoded with `luxfarm-wire`, which the client and the workers
//!   share.
//! - `scene`: what the master asks of the render core; `output`: outputs on demand.
//! - `rest`, `grpc`, `views`, `metrics`, `error`; `dashboard`: the web page.
//!
//! The public surface is what the `luxfarm` command needs to run or embed a master
//! ([`Config`], [`run`], [`start`], [`Running`]) and what the capacity benchmark reads through
//! [`Running`] ([`SubmitOptions`], [`MergeReport`]); everything else is internal.

pub(crate) mod config;
pub(crate) mod dashboard;
pub(crate) mod db;
pub(crate) mod error;
pub(crate) mod farm;
pub(crate) mod grpc;
pub(crate) mod halt;
pub(crate) mod lease;
pub(crate) mod metrics;
#[expect(
    dead_code,
    reason = "`render` and `Output::version` are unused since the module became private; the \
              output module is being rewritten (issue 12 part 2), which uses or removes them"
)]
pub(crate) mod output;
pub(crate) mod rest;
pub(crate) mod scene;
pub(crate) mod serve;
pub(crate) mod views;

/// The delta codec, as `crate::codec` (checkpoints are written and read through it).
pub(crate) use luxfarm_wire::codec;

pub use config::Config;
pub use error::ServerError;
pub use farm::SubmitOptions;
pub use metrics::{MergeReport, MergeTiming};
pub use serve::{start, Running};

/// Runs the master until Ctrl-C / SIGTERM, printing `listening on ADDR` once bound.
pub async fn run(cfg: Config) -> anyhow::Result<()> {
    let mut running = start(cfg).await?;
    let addr = running.addr();
    println!("listening on {addr}");
    tracing::info!(%addr, "luxfarm master listening");
    let mut term = tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate())?;
    tokio::select! {
        _ = tokio::signal::ctrl_c() => {}
        _ = term.recv() => {}
        r = running.task_mut() => { r?; }
    }
    Ok(())
}
