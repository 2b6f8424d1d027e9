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
    /// Share of the time a job's film analyses (convergence tests, noise-aware maps, the
    /// error history) may run, in (0, 1]: after a round that took d seconds (on all cores)
    /// the next waits d (1 - share) / share. They stay at least `convergencestep` spp apart
    /// either way.
    #[arg(long, default_value_t = 0.25)]
    pub analysis_share: f64,
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
    /// URL every job's end is posted to (events done, failed, cancelled and halted; see
    /// `crate::webhooks`). Jobs may name their own hook as well. Also read from
    /// LUXFARM_WEBHOOK.
    #[arg(long, env = "LUXFARM_WEBHOOK")]
    pub webhook: Option<String>,
    /// File holding the secret webhook deliveries are signed with (HMAC-SHA256 of the body in
    /// `X-Luxfarm-Signature`); without it deliveries are unsigned. Also read from
    /// LUXFARM_WEBHOOK_SECRET_FILE.
    #[arg(long, env = "LUXFARM_WEBHOOK_SECRET_FILE")]
    pub webhook_secret_file: Option<PathBuf>,
    /// Refuse submissions naming a webhook of their own (a farm whose submitters should not
    /// make the master post to URLs of their choosing, e.g. inside its network).
    #[arg(long)]
    pub no_job_webhooks: bool,
    /// Attempts at delivering one webhook before it is given up.
    #[arg(long, default_value_t = 10)]
    pub webhook_attempts: u32,
    /// Seconds before the first retry of a webhook; each retry waits twice as long as the one
    /// before, up to --webhook-backoff-max.
    #[arg(long, default_value_t = 1.0)]
    pub webhook_backoff: f64,
    /// Longest wait between two attempts at a webhook (seconds).
    #[arg(long, default_value_t = 600.0)]
    pub webhook_backoff_max: f64,
    /// Seconds one webhook attempt may take (connecting, sending, the answer's headers).
    #[arg(long, default_value_t = 10.0)]
    pub webhook_timeout: f64,
    /// The master's address as receivers reach it (`https://farm.example:7878`): webhook
    /// payloads name output URLs under it. Without it they are paths (`/api/v1/jobs/...`).
    #[arg(long)]
    pub public_url: Option<String>,
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
            analysis_share: 0.25,
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
            webhook: None,
            webhook_secret_file: None,
            no_job_webhooks: false,
            webhook_attempts: 10,
            webhook_backoff: 1.0,
            webhook_backoff_max: 600.0,
            webhook_timeout: 10.0,
            public_url: None,
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
            ("--webhook-backoff", self.webhook_backoff),
            ("--webhook-backoff-max", self.webhook_backoff_max),
            ("--webhook-timeout", self.webhook_timeout),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{name} must be a positive number"));
            }
        }
        if !(self.analysis_share > 0.0 && self.analysis_share <= 1.0) {
            return Err("--analysis-share must be in (0, 1]".into());
        }
        if self.block_after == 0 || self.quarantine_after == 0 {
            return Err("--block-after and --quarantine-after must be at least 1".into());
        }
        if self.max_connections == 0 || self.max_unpacking == 0 {
            return Err("--max-connections and --max-unpacking must be at least 1".into());
        }
        if self.webhook_attempts == 0 {
            return Err("--webhook-attempts must be at least 1".into());
        }
        if let Some(url) = &self.webhook {
            check_hook_url(url).map_err(|e| format!("--webhook: {e}"))?;
        }
        if let Some(url) = &self.public_url {
            check_hook_url(url).map_err(|e| format!("--public-url: {e}"))?;
        }
        if self.default_haltspp > self.max_haltspp {
            return Err("--default-haltspp must not exceed --max-haltspp".into());
        }
        Ok(())
    }
}

/// Longest webhook URL accepted (the master's or a job's).
pub const MAX_HOOK_URL: usize = 2048;

/// Checks a webhook URL (the master's, or a job's from its submitter): an absolute `http` or
/// `https` URL with a host, at most [`MAX_HOOK_URL`] bytes, without spaces or control
/// characters. The error says what is wrong, without repeating a long URL.
pub fn check_hook_url(url: &str) -> Result<(), String> {
    if url.len() > MAX_HOOK_URL {
        return Err(format!(
            "the URL is {} bytes long; at most {MAX_HOOK_URL} are accepted",
            url.len()
        ));
    }
    if url.chars().any(|c| c.is_whitespace() || c.is_control()) {
        return Err("the URL holds a space or a control character".into());
    }
    let parsed = reqwest::Url::parse(url).map_err(|e| format!("{url:?} is not a URL: {e}"))?;
    if !matches!(parsed.scheme(), "http" | "https") {
        return Err(format!(
            "scheme {:?}: only http and https URLs are accepted",
            parsed.scheme()
        ));
    }
    if parsed.host_str().is_none_or(str::is_empty) {
        return Err(format!("{url:?} names no host"));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hook_urls_must_be_http_or_https_with_a_host_and_short() {
        assert!(check_hook_url("http://127.0.0.1:9/hook").is_ok());
        assert!(check_hook_url("https://hooks.example/a?b=c").is_ok());
        for bad in [
            "ftp://x/y",
            "file:///etc/passwd",
            "javascript:alert(1)",
            "hooks",
            "",
        ] {
            assert!(check_hook_url(bad).is_err(), "{bad}");
        }
        assert!(check_hook_url("http://a b/").is_err());
        let long = format!("https://h/{}", "a".repeat(MAX_HOOK_URL));
        let e = check_hook_url(&long).unwrap_err();
        assert!(e.contains("at most 2048"), "{e}");
    }

    #[test]
    fn webhook_options_are_checked() {
        let mut c = Config::local("d".into());
        c.webhook = Some("gopher://x".into());
        assert!(c.validate().unwrap_err().contains("--webhook"));
        c.webhook = Some("http://127.0.0.1:1/h".into());
        c.webhook_attempts = 0;
        assert!(c.validate().unwrap_err().contains("--webhook-attempts"));
        c.webhook_attempts = 3;
        c.webhook_backoff = f64::NAN;
        assert!(c.validate().is_err());
        c.webhook_backoff = 0.05;
        assert!(c.validate().is_ok());
    }

    #[test]
    fn the_analysis_share_is_a_fraction() {
        let mut c = Config::local("d".into());
        for bad in [0.0, -0.5, 1.5, f64::NAN] {
            c.analysis_share = bad;
            assert!(
                c.validate().unwrap_err().contains("--analysis-share"),
                "{bad}"
            );
        }
        for good in [0.05, 1.0] {
            c.analysis_share = good;
            assert!(c.validate().is_ok(), "{good}");
        }
    }
}
