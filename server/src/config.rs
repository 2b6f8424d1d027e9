//! Command-line configuration of the master (`luxfarm-server`, `luxfarm server`).

use std::net::SocketAddr;
use std::path::PathBuf;

/// Options of the master.
#[derive(Clone, Debug, clap::Args)]
pub struct Config {
    /// Address to listen on (gRPC, REST and dashboard share it). Port 0 picks a free port; the
    /// chosen address is printed as `listening on ADDR` on stdout.
    #[arg(long, default_value = "127.0.0.1:7878")]
    pub listen: SocketAddr,
    /// Directory of the job store, bundles, checkpoints and outputs.
    #[arg(long, default_value = "luxfarm-data")]
    pub data_dir: PathBuf,
    /// Bearer token required on every API and worker call (required when listening on a
    /// non-loopback address). Also read from LUXFARM_TOKEN.
    #[arg(long, env = "LUXFARM_TOKEN")]
    pub token: Option<String>,
    /// PEM certificate chain for TLS (with --tls-key).
    #[arg(long, requires = "tls_key")]
    pub tls_cert: Option<PathBuf>,
    /// PEM private key for TLS (with --tls-cert).
    #[arg(long, requires = "tls_cert")]
    pub tls_key: Option<PathBuf>,
    /// Serve plain HTTP on a non-loopback address (behind a proxy that terminates TLS);
    /// without it such an address needs --tls-cert and --tls-key.
    #[arg(long)]
    pub allow_plaintext: bool,
    /// Seconds without a heartbeat after which a worker loses its lease.
    #[arg(long, default_value_t = 30.0)]
    pub worker_timeout: f64,
    /// Seconds between a worker's film delta uploads.
    #[arg(long, default_value_t = 10.0)]
    pub upload_interval: f64,
    /// Seconds between checkpoints of a rendering job's merged film.
    #[arg(long, default_value_t = 30.0)]
    pub checkpoint_interval: f64,
    /// Largest upload accepted (bytes) for a scene bundle.
    #[arg(long, default_value_t = 1 << 30)]
    pub max_upload: u64,
    /// Most bytes a bundle may unpack to.
    #[arg(long, default_value_t = 4 << 30)]
    pub max_unpacked: u64,
    /// Memory budget of one job (bytes): its film, a checkpoint copy and one decoded delta
    /// per merge slot. A submission whose film needs more is refused, naming the figure.
    #[arg(long, default_value_t = 4 << 30)]
    pub max_job_memory: u64,
    /// Halt rule given to a job that has none (samples per pixel); the job says so.
    #[arg(long, default_value_t = 256.0)]
    pub default_haltspp: f64,
    /// Largest haltspp a job may ask for.
    #[arg(long, default_value_t = 1_000_000.0)]
    pub max_haltspp: f64,
    /// Largest halttime a job may ask for (seconds).
    #[arg(long, default_value_t = 604_800.0)]
    pub max_halttime: f64,
    /// Connections served at once; more wait in the listen queue.
    #[arg(long, default_value_t = 512)]
    pub max_connections: usize,
    /// Seconds a connection may take to send a request's headers.
    #[arg(long, default_value_t = 10.0)]
    pub header_timeout: f64,
    /// Seconds an idle connection (no request in progress) stays open.
    #[arg(long, default_value_t = 120.0)]
    pub idle_timeout: f64,
    /// Seconds a REST request may take, its body included.
    #[arg(long, default_value_t = 900.0)]
    pub request_timeout: f64,
    /// Submissions unpacked at once (the others wait before their bundle is unpacked).
    #[arg(long, default_value_t = 2)]
    pub max_unpacking: usize,
    /// Failed leases (render failures, timeouts, refused deltas) after which a worker is
    /// blocked from a job.
    #[arg(long, default_value_t = 3)]
    pub block_after: u32,
    /// Jobs a worker may be blocked from before it is quarantined farm-wide.
    #[arg(long, default_value_t = 3)]
    pub quarantine_after: u32,
    /// Seconds after which a quarantine is forgiven (an admin may forgive sooner).
    #[arg(long, default_value_t = 3600.0)]
    pub quarantine_ttl: f64,
    /// Workers an unfinished job without a `max_workers` counts as wanting in the
    /// `luxfarm_leases_wanted` gauge (what an autoscaler scales workers on).
    #[arg(long, default_value_t = 8)]
    pub workers_per_job: u32,
}

impl Config {
    /// A configuration for tests and the embedded master: loopback, a free port.
    pub fn local(data_dir: PathBuf) -> Config {
        Config {
            listen: SocketAddr::from(([127, 0, 0, 1], 0)),
            data_dir,
            token: None,
            tls_cert: None,
            tls_key: None,
            allow_plaintext: false,
            worker_timeout: 30.0,
            upload_interval: 10.0,
            checkpoint_interval: 30.0,
            max_upload: 1 << 30,
            max_unpacked: 4 << 30,
            max_job_memory: 4 << 30,
            default_haltspp: 256.0,
            max_haltspp: 1_000_000.0,
            max_halttime: 604_800.0,
            max_connections: 512,
            header_timeout: 10.0,
            idle_timeout: 120.0,
            request_timeout: 900.0,
            max_unpacking: 2,
            block_after: 3,
            quarantine_after: 3,
            quarantine_ttl: 3600.0,
            workers_per_job: 8,
        }
    }

    /// Refuses unsafe combinations (no token, or no TLS, on a non-loopback address).
    pub fn validate(&self) -> Result<(), String> {
        if !self.listen.ip().is_loopback() && self.token.as_deref().unwrap_or("").is_empty() {
            return Err(format!(
                "listening on {} (not loopback) needs --token (an admin token)",
                self.listen
            ));
        }
        if !self.listen.ip().is_loopback() && self.tls_cert.is_none() && !self.allow_plaintext {
            return Err(format!(
                "listening on {} (not loopback) needs TLS: --tls-cert and --tls-key (a server \
                 certificate, not a CA certificate, and its key), or --allow-plaintext behind a \
                 proxy that terminates TLS",
                self.listen
            ));
        }
        let positive = [
            ("--upload-interval", self.upload_interval),
            ("--worker-timeout", self.worker_timeout),
            ("--checkpoint-interval", self.checkpoint_interval),
            ("--default-haltspp", self.default_haltspp),
            ("--max-haltspp", self.max_haltspp),
            ("--max-halttime", self.max_halttime),
            ("--header-timeout", self.header_timeout),
            ("--idle-timeout", self.idle_timeout),
            ("--request-timeout", self.request_timeout),
            ("--quarantine-ttl", self.quarantine_ttl),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{name} must be a positive number"));
            }
        }
        if self.block_after == 0 || self.quarantine_after == 0 {
            return Err("--block-after and --quarantine-after must be at least 1".into());
        }
        if self.max_connections == 0 || self.max_unpacking == 0 {
            return Err("--max-connections and --max-unpacking must be at least 1".into());
        }
        if self.default_haltspp > self.max_haltspp {
            return Err("--default-haltspp must not exceed --max-haltspp".into());
        }
        Ok(())
    }
}
