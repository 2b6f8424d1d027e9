//! luxfarm master: accepts jobs (REST and gRPC on one port), leases sample streams to workers,
//! merges their film deltas into each job's f64 film, evaluates the halt rules, checkpoints,
//! and serves outputs, metrics and an OpenAPI document.
//!
//! - [`config`]: command-line options; [`serve`]: the listener (gRPC + REST, token, TLS).
//! - [`farm`]: shared state, submission, cancel; [`lease`]: workers, leases, uploads;
//!   [`halt`]: halt rules, checkpoints, job end; [`db`]: the SQLite store.
//! - [`bundle`]: safe unpacking and content-addressed storage of scene bundles.
//! - [`scene`]: what the master asks of the render core; [`output`]: outputs on demand.
//! - [`rest`], [`grpc`], [`views`], [`metrics`], [`error`]; [`dashboard`]: the web page.

pub mod bundle;
pub mod codec;
pub mod config;
pub mod dashboard;
pub mod db;
pub mod error;
pub mod farm;
pub mod grpc;
pub mod halt;
pub mod lease;
pub mod metrics;
pub mod output;
pub mod rest;
pub mod scene;
pub mod serve;
pub mod views;

pub use config::Config;
pub use serve::{start, Running};

/// Runs the master until Ctrl-C / SIGTERM, printing `listening on ADDR` once bound.
pub async fn run(cfg: Config) -> anyhow::Result<()> {
    let running = start(cfg).await?;
    println!("listening on {}", running.addr);
    tracing::info!(addr = %running.addr, "luxfarm master listening");
    let mut term = tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate())?;
    tokio::select! {
        _ = tokio::signal::ctrl_c() => {}
        _ = term.recv() => {}
        r = running.task => { r?; }
    }
    Ok(())
}
