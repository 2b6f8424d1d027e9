//! luxfarm worker: a slave node. It registers with the master (protocol versions compared; it
//! gets its own credential), takes assignments (a scene bundle by content hash, a seed, its
//! own stream id and a sample budget), renders the whole frame progressively with the full
//! render core (every file the scene names opened inside the bundle) and uploads film deltas
//! tagged (lease, sequence) every upload interval, when its budget is spent, and at stop. A
//! failed upload is retried with the same sequence number and the same bytes, while new
//! samples keep accumulating in the session film; acknowledged deltas are kept until the
//! master reports them durable and uploaded again if it restarted before, so a delta is never
//! lost and never counted twice. SIGTERM uploads the last delta, then exits. A master of
//! another protocol version makes the worker exit with both versions named.
//!
//! - [`link`]: the connection to the master (register, heartbeats, uploads with retry).
//! - [`cache`]: scene bundles cached by content hash, checked again before each use.
//! - [`job`]: rendering one lease; `flags.rs` holds the state its render thread, uploader
//!   and heartbeats share, `upload.rs` the uploads and their queues until durable.
//! - [`map`]: noise-aware sampling maps the master sends with its acknowledgements.

pub mod cache;
mod flags;
pub mod job;
pub mod link;
pub mod map;
pub mod quanta;
mod upload;

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// Options of a worker.
#[derive(Clone, Debug, clap::Args)]
pub struct Config {
    /// URL of the master, e.g. http://127.0.0.1:7878 (https:// for TLS).
    #[arg(long)]
    pub master: String,
    /// Render threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Name shown on the master (default: the host name and process id).
    #[arg(long)]
    pub name: Option<String>,
    /// Bearer token of the master. Also read from LUXFARM_TOKEN.
    #[arg(long, env = "LUXFARM_TOKEN")]
    pub token: Option<String>,
    /// Extra CA certificate (PEM) to trust for an https:// master.
    #[arg(long)]
    pub ca_cert: Option<PathBuf>,
    /// Where scene bundles are cached (default: a directory under the system temp dir).
    #[arg(long)]
    pub cache_dir: Option<PathBuf>,
    /// Keep a copy of every delta (lxd1 encoding) in this directory (for audits):
    /// LEASE-SEQ.sent.lxd when queued for upload, replaced by LEASE-SEQ.STATUS.lxd with the
    /// master's acknowledgement status.
    #[arg(long)]
    pub keep_deltas: Option<PathBuf>,
    /// Exit after this many leases (0: run forever).
    #[arg(long, default_value_t = 0)]
    pub max_leases: u64,
    /// A tag this worker offers (repeat, or comma-separated): jobs asking for tags go only to
    /// workers having them all.
    #[arg(long = "tag")]
    pub tags: Vec<String>,
    /// Memory this worker offers in MiB (default: the machine's, from /proc/meminfo).
    #[arg(long)]
    pub memory_mb: Option<u64>,
}

impl Config {
    /// The memory declared to the master: `--memory-mb`, else the machine's total (0 when it
    /// cannot be read).
    fn memory_mb(&self) -> u64 {
        self.memory_mb.unwrap_or_else(|| {
            std::fs::read_to_string("/proc/meminfo")
                .ok()
                .and_then(|t| mem_total_mb(&t))
                .unwrap_or(0)
        })
    }

    fn threads(&self) -> usize {
        self.threads
            .filter(|&n| n > 0)
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
    }

    fn name(&self) -> String {
        self.name.clone().unwrap_or_else(|| {
            let host = std::fs::read_to_string("/etc/hostname")
                .map(|s| s.trim().to_string())
                .unwrap_or_else(|_| "worker".into());
            format!("{host}-{}", std::process::id())
        })
    }
}

/// Runs a worker until SIGTERM / Ctrl-C (after uploading the last delta) or `max_leases`.
pub async fn run(cfg: Config) -> anyhow::Result<()> {
    let shutdown = Arc::new(AtomicBool::new(false));
    spawn_signal_watch(shutdown.clone())?;
    let threads = cfg.threads();
    let link = link::Link::new(&cfg, threads, shutdown.clone())?;
    let cache = cache::Cache::new(cfg.cache_dir.clone())?;
    let quanta = Arc::new(quanta::Quanta::default());
    link.register().await?;
    let mut leases = 0u64;
    while !shutdown.load(Ordering::Relaxed) {
        let assignment = match link.next_assignment().await {
            Ok(Some(a)) => a,
            Ok(None) => continue,
            Err(e) if e.is::<link::Refused>() => return Err(e),
            Err(e) => {
                tracing::warn!(error = %e, "no assignment; retrying");
                tokio::time::sleep(Duration::from_millis(500)).await;
                continue;
            }
        };
        let span =
            tracing::info_span!("lease", lease = %assignment.lease_id, job = %assignment.job_id);
        let _e = span.enter();
        match job::run_lease(&link, &cache, &quanta, &cfg, threads, assignment).await {
            Ok(()) => {}
            Err(e) => tracing::error!(error = %format!("{e:#}"), "lease failed"),
        }
        leases += 1;
        if cfg.max_leases > 0 && leases >= cfg.max_leases {
            break;
        }
    }
    tracing::info!("worker exiting");
    Ok(())
}

/// MemTotal of a /proc/meminfo text, in MiB.
fn mem_total_mb(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024)
}

fn spawn_signal_watch(flag: Arc<AtomicBool>) -> anyhow::Result<()> {
    use tokio::signal::unix::{signal, SignalKind};
    let mut term = signal(SignalKind::terminate())?;
    let mut int = signal(SignalKind::interrupt())?;
    tokio::spawn(async move {
        tokio::select! {
            _ = term.recv() => {}
            _ = int.recv() => {}
        }
        tracing::info!("signal received: uploading the last delta, then exiting");
        flag.store(true, Ordering::Relaxed);
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn memory_comes_from_meminfo() {
        let text = "MemTotal:       16303580 kB\nMemFree:  1 kB\n";
        assert_eq!(super::mem_total_mb(text), Some(15921));
        assert_eq!(super::mem_total_mb("MemFree: 1 kB"), None);
    }
}
