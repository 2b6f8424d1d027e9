//! The worker's connection to the master: registration (again after a master restart),
//! assignments, bundle downloads, heartbeats and delta uploads, with backoff on failures.

use crate::Config;
use luxfarm_proto as pb;
use luxfarm_proto::connect::{self, AuthChannel};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;
use tokio_stream::StreamExt;
use tonic::Code;

/// The master link shared by the worker's tasks.
#[derive(Clone)]
pub struct Link {
    channel: AuthChannel,
    /// Uploads travel on their own connection: an upload the master holds back (HTTP/2 flow
    /// control while it is busy) must not hold back heartbeats sharing its connection window.
    upload_channel: AuthChannel,
    name: String,
    threads: u32,
    worker_id: Arc<Mutex<String>>,
    heartbeat: Arc<Mutex<Duration>>,
    pub shutdown: Arc<AtomicBool>,
}

/// Backoff delays: 0.2 s doubling to 5 s.
pub fn backoff(attempt: u32) -> Duration {
    Duration::from_millis((200u64 << attempt.min(5)).min(5000))
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

impl Link {
    /// A link to the configured master (connects lazily).
    pub fn new(cfg: &Config, threads: usize, shutdown: Arc<AtomicBool>) -> anyhow::Result<Link> {
        let channel = connect::channel(&cfg.master, cfg.token.as_deref(), cfg.ca_cert.as_deref())?;
        let upload_channel =
            connect::channel(&cfg.master, cfg.token.as_deref(), cfg.ca_cert.as_deref())?;
        Ok(Link {
            channel,
            upload_channel,
            name: cfg.name(),
            threads: threads as u32,
            worker_id: Arc::new(Mutex::new(String::new())),
            heartbeat: Arc::new(Mutex::new(Duration::from_secs(1))),
            shutdown,
        })
    }

    fn client(&self) -> pb::worker_client::WorkerClient<AuthChannel> {
        connect::worker_client(self.channel.clone())
    }

    /// The id the master gave this worker.
    pub fn worker_id(&self) -> String {
        lock(&self.worker_id).clone()
    }

    /// Seconds between heartbeats, as the master asked.
    pub fn heartbeat_interval(&self) -> Duration {
        *lock(&self.heartbeat)
    }

    /// Registers, retrying with backoff until the master answers (or shutdown).
    pub async fn register(&self) -> anyhow::Result<()> {
        let mut attempt = 0;
        loop {
            let req = pb::RegisterRequest {
                name: self.name.clone(),
                threads: self.threads,
                worker_id: self.worker_id(),
            };
            match self.client().register(req).await {
                Ok(r) => {
                    let r = r.into_inner();
                    tracing::info!(worker = %r.worker_id, "registered with the master");
                    *lock(&self.worker_id) = r.worker_id;
                    *lock(&self.heartbeat) =
                        Duration::from_secs_f64(r.heartbeat_interval.clamp(0.1, 30.0));
                    return Ok(());
                }
                Err(s) if s.code() == Code::Unauthenticated => {
                    anyhow::bail!("the master refused the token: {}", s.message())
                }
                Err(s) => {
                    if self.shutdown.load(Ordering::Relaxed) {
                        anyhow::bail!("shutting down before registering");
                    }
                    tracing::warn!(error = %s.message(), "master unreachable; retrying");
                    tokio::time::sleep(backoff(attempt)).await;
                    attempt += 1;
                }
            }
        }
    }

    /// Asks for an assignment (long poll); re-registers when the master forgot this worker.
    pub async fn next_assignment(&self) -> anyhow::Result<Option<pb::Assignment>> {
        let req = pb::NextRequest {
            worker_id: self.worker_id(),
        };
        match self.client().next_assignment(req).await {
            Ok(r) => Ok(r.into_inner().assignment),
            Err(s) if s.code() == Code::NotFound => {
                self.register().await?;
                Ok(None)
            }
            Err(s) => Err(anyhow::anyhow!("next assignment: {}", s.message())),
        }
    }

    /// Downloads a bundle (tar bytes).
    pub async fn fetch_bundle(&self, hash: &str) -> anyhow::Result<Vec<u8>> {
        let mut stream = self
            .client()
            .fetch_bundle(pb::BundleRequest { hash: hash.into() })
            .await?
            .into_inner();
        let mut out = Vec::new();
        while let Some(chunk) = stream.next().await {
            out.extend_from_slice(&chunk?.data);
        }
        Ok(out)
    }

    /// One upload attempt of an encoded delta.
    pub async fn upload(
        &self,
        lease: &str,
        seq: u64,
        last: bool,
        data: &[u8],
    ) -> Result<pb::UploadAck, tonic::Status> {
        let header = pb::UploadHeader {
            worker_id: self.worker_id(),
            lease_id: lease.to_string(),
            seq,
            encoding: luxfarm_wire::codec::DELTA_ENCODING.into(),
            last,
            size: data.len() as u64,
        };
        let mut chunks = vec![pb::UploadChunk {
            part: Some(pb::upload_chunk::Part::Header(header)),
        }];
        for c in data.chunks(pb::CHUNK_BYTES) {
            chunks.push(pb::UploadChunk {
                part: Some(pb::upload_chunk::Part::Data(c.to_vec())),
            });
        }
        let r = connect::worker_client(self.upload_channel.clone())
            .upload_delta(tokio_stream::iter(chunks))
            .await?;
        Ok(r.into_inner())
    }

    /// One heartbeat: Some(stop) or None when the master could not be reached.
    pub async fn heartbeat(&self, lease: &str, samples: f64) -> Option<bool> {
        let req = pb::HeartbeatRequest {
            worker_id: self.worker_id(),
            lease_id: lease.to_string(),
            samples,
        };
        match self.client().heartbeat(req).await {
            Ok(r) => {
                let r = r.into_inner();
                if r.unknown_worker {
                    let _ = self.register().await;
                }
                Some(r.stop)
            }
            Err(s) => {
                tracing::debug!(error = %s.message(), "heartbeat failed");
                None
            }
        }
    }
}

impl Link {
    /// Tells the master this lease cannot be rendered.
    pub async fn report_failure(&self, lease: &str, reason: &str) -> anyhow::Result<()> {
        self.client()
            .report_failure(pb::FailureReport {
                worker_id: self.worker_id(),
                lease_id: lease.to_string(),
                reason: reason.to_string(),
            })
            .await?;
        Ok(())
    }
}
