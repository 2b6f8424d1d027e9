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
            worker_timeout: 30.0,
            upload_interval: 10.0,
            checkpoint_interval: 30.0,
            max_upload: 1 << 30,
            max_unpacked: 4 << 30,
        }
    }

    /// Refuses unsafe combinations (no token on a non-loopback address).
    pub fn validate(&self) -> Result<(), String> {
        if !self.listen.ip().is_loopback() && self.token.as_deref().unwrap_or("").is_empty() {
            return Err(format!(
                "listening on {} (not loopback) needs --token",
                self.listen
            ));
        }
        if self.upload_interval <= 0.0 || self.worker_timeout <= 0.0 {
            return Err("--upload-interval and --worker-timeout must be positive".into());
        }
        Ok(())
    }
}
