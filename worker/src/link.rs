//! The worker's connection to the master: registration (protocol versions compared, its own
//! credential received), assignments, bundle downloads, heartbeats and delta uploads, with
//! backoff on failures.
//!
//! ```text
//! user token (role worker) --Register--> worker id + credential + master instance
//! credential --every later call--> NextAssignment, FetchBundle, UploadDelta, Heartbeat, ...
//! ```
//!
//! A master speaking another protocol version is a fatal error (the worker exits with both
//! versions named); a master that no longer knows the credential is registered with again.

use crate::Config;
use luxfarm_proto as pb;
use luxfarm_proto::connect::{self, Auth, AuthChannel};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;
use tokio_stream::StreamExt;
use tonic::Code;

/// The master link shared by the worker's tasks.
#[derive(Clone)]
pub struct Link {
    /// Registration, with the user token.
    register_channel: AuthChannel,
    /// Worker calls, with the worker's credential.
    channel: AuthChannel,
    /// Uploads travel on their own connection: an upload the master holds back (HTTP/2 flow
    /// control while it is busy) must not hold back heartbeats sharing its connection window.
    upload_channel: AuthChannel,
    credential: Auth,
    name: String,
    threads: u32,
    /// What the worker offers: its tags and memory (MiB).
    tags: Vec<String>,
    memory_mb: u64,
    state: Arc<Mutex<Registration>>,
    pub shutdown: Arc<AtomicBool>,
}

/// What registration gave.
#[derive(Clone, Debug, Default)]
struct Registration {
    worker_id: String,
    token: String,
    heartbeat: Duration,
    instance: String,
}

/// The master refused this worker for good (another protocol version, a refused token): the
/// worker exits instead of retrying.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct Refused(pub String);

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
        let ca = cfg.ca_cert.as_deref();
        let register_channel = connect::channel(&cfg.master, cfg.token.as_deref(), ca)?;
        let credential = Auth::new(None)?;
        let channel = connect::channel_with(&cfg.master, credential.clone(), ca)?;
        let upload_channel = connect::channel_with(&cfg.master, credential.clone(), ca)?;
        Ok(Link {
            register_channel,
            channel,
            upload_channel,
            credential,
            name: cfg.name(),
            threads: threads as u32,
            tags: cfg.tags.clone(),
            memory_mb: cfg.memory_mb(),
            state: Arc::new(Mutex::new(Registration {
                heartbeat: Duration::from_secs(1),
                ..Registration::default()
            })),
            shutdown,
        })
    }

    fn client(&self) -> pb::worker_client::WorkerClient<AuthChannel> {
        connect::worker_client(self.channel.clone())
    }

    /// The id the master gave this worker.
    pub fn worker_id(&self) -> String {
        lock(&self.state).worker_id.clone()
    }

    /// Seconds between heartbeats, as the master asked.
    pub fn heartbeat_interval(&self) -> Duration {
        lock(&self.state).heartbeat
    }

    /// The master instance last heard from.
    pub fn instance(&self) -> String {
        lock(&self.state).instance.clone()
    }

    /// Records the master instance of a reply; true when it changed (the master restarted).
    pub fn observe_instance(&self, instance: &str) -> bool {
        if instance.is_empty() {
            return false;
        }
        let mut st = lock(&self.state);
        let changed = !st.instance.is_empty() && st.instance != instance;
        st.instance = instance.to_string();
        changed
    }

    /// Registers, retrying with backoff until the master answers (or shutdown). A master of
    /// another protocol version, or one refusing the token, is a fatal error.
    pub async fn register(&self) -> anyhow::Result<()> {
        let mut attempt = 0;
        loop {
            let (worker_id, worker_token) = {
                let st = lock(&self.state);
                (st.worker_id.clone(), st.token.clone())
            };
            let req = pb::RegisterRequest {
                name: self.name.clone(),
                threads: self.threads,
                worker_id,
                protocol: pb::PROTOCOL_VERSION,
                // The version and the instruction-set level its render core runs at.
                build: format!("luxfarm {} {}", pb::BUILD, luxfarm::isa::build_name()),
                worker_token,
                tags: self.tags.clone(),
                memory_mb: self.memory_mb,
            };
            let client = connect::worker_client(self.register_channel.clone());
            match client.clone().register(req).await {
                Ok(r) => return self.registered(r.into_inner()),
                Err(s) if s.code() == Code::FailedPrecondition => {
                    return Err(
                        Refused(format!("the master refused this worker: {}", s.message())).into(),
                    )
                }
                Err(s) if matches!(s.code(), Code::Unauthenticated | Code::PermissionDenied) => {
                    return Err(
                        Refused(format!("the master refused the token: {}", s.message())).into(),
                    )
                }
                Err(s) => {
                    if self.shutdown.load(Ordering::Relaxed) {
                        anyhow::bail!("shutting down before registering");
                    }
                    tracing::warn!(error = %connect::explain(&s), "master unreachable; retrying");
                    tokio::time::sleep(backoff(attempt)).await;
                    attempt += 1;
                }
            }
        }
    }

    fn registered(&self, r: pb::RegisterReply) -> anyhow::Result<()> {
        if r.protocol != pb::PROTOCOL_VERSION {
            let build = if r.build.is_empty() {
                "an older luxfarm".to_string()
            } else {
                format!("luxfarm {}", r.build)
            };
            return Err(Refused(format!(
                "protocol mismatch: the master ({build}) speaks worker protocol {}, this worker \
                 (luxfarm {}) speaks protocol {}: run the same luxfarm release on the workers \
                 and the master",
                r.protocol,
                pb::BUILD,
                pb::PROTOCOL_VERSION
            ))
            .into());
        }
        self.credential.set(Some(&r.worker_token))?;
        tracing::info!(worker = %r.worker_id, "registered with the master");
        self.observe_instance(&r.master_instance);
        let mut st = lock(&self.state);
        st.worker_id = r.worker_id;
        st.token = r.worker_token;
        st.heartbeat = Duration::from_secs_f64(r.heartbeat_interval.clamp(0.1, 30.0));
        Ok(())
    }

    /// Asks for an assignment (long poll); registers again when the master forgot this
    /// worker.
    pub async fn next_assignment(&self) -> anyhow::Result<Option<pb::Assignment>> {
        let req = pb::NextRequest {
            worker_id: self.worker_id(),
        };
        match self.client().next_assignment(req).await {
            Ok(r) => Ok(r.into_inner().assignment),
            Err(s) if matches!(s.code(), Code::NotFound | Code::Unauthenticated) => {
                self.register().await?;
                Ok(None)
            }
            Err(s) => Err(anyhow::anyhow!("next assignment: {}", connect::explain(&s))),
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
        map_version: u64,
    ) -> Result<pb::UploadAck, tonic::Status> {
        let header = pb::UploadHeader {
            worker_id: self.worker_id(),
            lease_id: lease.to_string(),
            seq,
            encoding: luxfarm_wire::codec::DELTA_ENCODING.into(),
            last,
            size: data.len() as u64,
            master_instance: self.instance(),
            // This worker takes noise-aware sampling maps (crate::map).
            sampling_map_version: Some(map_version),
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
        let ack = r.into_inner();
        Ok(ack)
    }

    /// One heartbeat; None when the master could not be reached. A master that forgot this
    /// worker is registered with again.
    pub async fn heartbeat(
        &self,
        lease: &str,
        samples: f64,
        pass_samples: f64,
    ) -> Option<pb::HeartbeatReply> {
        let req = pb::HeartbeatRequest {
            worker_id: self.worker_id(),
            lease_id: lease.to_string(),
            samples,
            pass_samples,
        };
        match self.client().heartbeat(req).await {
            Ok(r) => {
                let r = r.into_inner();
                if r.unknown_worker {
                    let _ = self.register().await;
                }
                Some(r)
            }
            Err(s) => {
                if s.code() == Code::Unauthenticated {
                    let _ = self.register().await;
                }
                tracing::debug!(error = %s.message(), "heartbeat failed");
                None
            }
        }
    }

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
