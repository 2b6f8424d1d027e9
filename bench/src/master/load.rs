//! The load generator of `luxfarm bench master`: simulated workers speaking the real gRPC
//! worker protocol (register, lease, heartbeats, film delta uploads on a staggered schedule),
//! pre-built delta payloads, the per-second backlog sampler, and CPU/RSS readings from /proc.

use luxfarm::film::Film;
use luxfarm_proto as pb;
use luxfarm_proto::connect;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;
use tokio::time::Instant;

/// One pre-built delta: its encoded bytes in upload chunks and its sample count.
pub struct Payload {
    pub chunks: Vec<Vec<u8>>,
    pub bytes: usize,
    pub samples: f64,
}

/// A film that looks like a render delta: a smooth image times per-sample noise, `spp`
/// splats per pixel with fractional filter weights (as a Mitchell filter gives).
pub fn noise_film(w: u32, h: u32, spp: u32, seed: u32) -> Film {
    let mut f = Film::new(w, h, vec![]);
    let mut s: u32 = (0x9E37_79B9 ^ seed.wrapping_mul(0x85EB_CA6B)) | 1;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        (s >> 8) as f32 / (1u32 << 24) as f32
    };
    for y in 0..h {
        for x in 0..w {
            let base = 0.05 + 0.9 * (x as f32 / w as f32) * (1.0 - 0.5 * y as f32 / h as f32);
            for _ in 0..spp {
                let n = next();
                // Path tracing noise: mostly near the mean, sometimes a bright firefly.
                let v = if n > 0.98 {
                    base * 20.0 * n
                } else {
                    base * 2.0 * n
                };
                let weight = 0.2 + 0.8 * next();
                f.add_splat(0, x, y, [v * 0.95, v, v * 1.08], 1.0, weight);
            }
        }
    }
    f.add_sample_count(f64::from(w) * f64::from(h) * f64::from(spp));
    f
}

/// Encodes a film into an upload payload.
pub fn payload(film: &Film, encoding: &str) -> anyhow::Result<Payload> {
    let bytes = match encoding {
        "lxd1" => luxfarm_wire::codec::encode(film),
        "lxd2" => luxfarm_wire::codec::encode_delta(film),
        other => anyhow::bail!("unknown encoding {other:?} (lxd1 or lxd2)"),
    };
    Ok(Payload {
        bytes: bytes.len(),
        chunks: bytes.chunks(pb::CHUNK_BYTES).map(<[u8]>::to_vec).collect(),
        samples: film.total_samples(),
    })
}

/// Counters shared by the simulated workers.
#[derive(Default)]
pub struct Stats {
    pub acked: AtomicU64,
    pub duplicates: AtomicU64,
    pub failures: AtomicU64,
    pub abandoned: AtomicU64,
    pub in_flight: AtomicU64,
    pub acked_bytes: AtomicU64,
    acked_samples_bits: AtomicU64,
    /// Upload round trips (seconds) and when they ended (seconds after t0).
    pub rtts: Mutex<Vec<(f64, f64)>>,
    pub heartbeats: AtomicU64,
}

impl Stats {
    pub fn acked_samples(&self) -> f64 {
        f64::from_bits(self.acked_samples_bits.load(Ordering::Relaxed))
    }
    fn add_samples(&self, v: f64) {
        let _ = self
            .acked_samples_bits
            .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |b| {
                Some((f64::from_bits(b) + v).to_bits())
            });
    }
}

/// The schedule: worker `i` uploads at `t0 + interval * (i / n + k)` while before `end`.
#[derive(Clone, Copy)]
pub struct Schedule {
    pub t0: Instant,
    pub interval: Duration,
    pub workers: usize,
    pub duration: Duration,
}

impl Schedule {
    fn first(&self, i: usize) -> Duration {
        self.interval.mul_f64(i as f64 / self.workers as f64)
    }
    /// Upload times of worker `i`, as offsets from t0.
    pub fn times(&self, i: usize) -> impl Iterator<Item = Duration> + '_ {
        let first = self.first(i);
        (0u32..)
            .map(move |k| first + self.interval * k)
            .take_while(move |t| *t < self.duration)
    }
    /// Uploads due by offset `t` (all workers).
    pub fn offered_by(&self, t: Duration) -> u64 {
        (0..self.workers)
            .map(|i| self.times(i).take_while(|d| *d <= t).count() as u64)
            .sum()
    }
}

/// A simulated worker, registered (with its own credential) and holding a lease.
pub struct SimWorker {
    client: pb::worker_client::WorkerClient<connect::AuthChannel>,
    id: String,
    token: String,
    instance: String,
    lease: String,
}

impl SimWorker {
    /// Connects (own HTTP/2 connection), registers and takes a lease.
    pub async fn join(url: &str, i: usize) -> anyhow::Result<SimWorker> {
        let reg = connect::worker_client(connect::channel(url, None, None)?)
            .register(pb::RegisterRequest {
                name: format!("sim-{i:03}"),
                threads: 2,
                worker_id: String::new(),
                protocol: pb::PROTOCOL_VERSION,
                build: pb::BUILD.into(),
                worker_token: String::new(),
                ..Default::default()
            })
            .await?
            .into_inner();
        let mut client =
            connect::worker_client(connect::channel(url, Some(&reg.worker_token), None)?);
        for _ in 0..10 {
            let next = client
                .next_assignment(pb::NextRequest {
                    worker_id: reg.worker_id.clone(),
                })
                .await?
                .into_inner();
            if let Some(a) = next.assignment {
                return Ok(SimWorker {
                    client,
                    id: reg.worker_id,
                    token: reg.worker_token,
                    instance: reg.master_instance,
                    lease: a.lease_id,
                });
            }
        }
        anyhow::bail!("simulated worker {i} got no assignment")
    }

    /// Heartbeats every `every` until the task is aborted.
    pub async fn heartbeats(mut self, every: Duration, stats: Arc<Stats>) {
        loop {
            tokio::time::sleep(every).await;
            let req = pb::HeartbeatRequest {
                worker_id: self.id.clone(),
                lease_id: self.lease.clone(),
                samples: 0.0,
                pass_samples: 0.0,
            };
            if self.client.heartbeat(req).await.is_ok() {
                stats.heartbeats.fetch_add(1, Ordering::Relaxed);
            }
        }
    }

    /// A handle on a second connection for the heartbeats, as the worker keeps uploads and
    /// control calls apart (a held-back upload would block heartbeats on its connection).
    pub fn control(&self, url: &str) -> anyhow::Result<SimWorker> {
        Ok(SimWorker {
            client: connect::worker_client(connect::channel(url, Some(&self.token), None)?),
            id: self.id.clone(),
            token: self.token.clone(),
            instance: self.instance.clone(),
            lease: self.lease.clone(),
        })
    }

    /// Uploads on the schedule; a late upload goes out as soon as the previous one is
    /// acknowledged. A failed upload is retried (same sequence number) up to 5 times.
    pub async fn uploads(
        mut self,
        i: usize,
        sched: Schedule,
        payloads: Arc<Vec<Payload>>,
        stats: Arc<Stats>,
    ) {
        let times: Vec<Duration> = sched.times(i).collect();
        for (k, at) in times.into_iter().enumerate() {
            tokio::time::sleep_until(sched.t0 + at).await;
            let p = &payloads[(i + k) % payloads.len()];
            let seq = k as u64 + 1;
            let mut tries = 0;
            loop {
                let start = Instant::now();
                stats.in_flight.fetch_add(1, Ordering::Relaxed);
                let r = self
                    .upload_once(seq, &payloads, (i + k) % payloads.len())
                    .await;
                stats.in_flight.fetch_sub(1, Ordering::Relaxed);
                let end = Instant::now();
                match r {
                    Ok(ack) => {
                        let rtt = end.duration_since(start).as_secs_f64();
                        let when = end.duration_since(sched.t0).as_secs_f64();
                        lock(&stats.rtts).push((rtt, when));
                        if ack.status == "merged" {
                            stats.acked.fetch_add(1, Ordering::Relaxed);
                            stats
                                .acked_bytes
                                .fetch_add(p.bytes as u64, Ordering::Relaxed);
                            stats.add_samples(p.samples);
                        } else {
                            stats.duplicates.fetch_add(1, Ordering::Relaxed);
                        }
                        break;
                    }
                    Err(e) => {
                        stats.failures.fetch_add(1, Ordering::Relaxed);
                        tries += 1;
                        if tries >= 5 {
                            eprintln!("worker {i} upload {seq} abandoned: {}", e.message());
                            stats.abandoned.fetch_add(1, Ordering::Relaxed);
                            break;
                        }
                        tokio::time::sleep(Duration::from_secs(1)).await;
                    }
                }
            }
        }
    }

    async fn upload_once(
        &mut self,
        seq: u64,
        payloads: &Arc<Vec<Payload>>,
        which: usize,
    ) -> Result<pb::UploadAck, tonic::Status> {
        let first = pb::UploadChunk {
            part: Some(pb::upload_chunk::Part::Header(pb::UploadHeader {
                worker_id: self.id.clone(),
                lease_id: self.lease.clone(),
                seq,
                encoding: payload_encoding(&payloads[which]).into(),
                last: false,
                size: payloads[which].bytes as u64,
                master_instance: self.instance.clone(),
                sampling_map_version: None,
            })),
        };
        let p = payloads.clone();
        let n = p[which].chunks.len();
        // Chunks are copied one at a time as the stream is polled (the payload is shared).
        let data = (0..n).map(move |j| pb::UploadChunk {
            part: Some(pb::upload_chunk::Part::Data(p[which].chunks[j].clone())),
        });
        let stream = tokio_stream::iter(std::iter::once(first).chain(data));
        Ok(self.client.upload_delta(stream).await?.into_inner())
    }
}

/// The encoding name of a payload, from its magic.
fn payload_encoding(p: &Payload) -> &'static str {
    match p.chunks.first().and_then(|c| c.get(..4)) {
        Some(b"LXD2") => "lxd2",
        _ => "lxd1",
    }
}

/// Locks a mutex, recovering from poisoning (the counters stay meaningful).
pub fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

/// CPU seconds of this process, split into the generator's threads (names starting with
/// `loadgen`, and the main thread) and the rest (the master: its runtime, blocking pool and
/// rayon threads). Read from /proc; zeros where unavailable.
#[derive(Clone, Copy, Debug, Default)]
pub struct Cpu {
    pub total: f64,
    pub generator: f64,
}

impl Cpu {
    pub fn now() -> Cpu {
        let tick = clock_tick();
        let total = std::fs::read_to_string("/proc/self/stat")
            .ok()
            .and_then(|s| stat_times(&s))
            .unwrap_or(0.0)
            / tick;
        let pid = std::process::id().to_string();
        let mut generator = 0.0;
        if let Ok(rd) = std::fs::read_dir("/proc/self/task") {
            for e in rd.flatten() {
                let tid = e.file_name().to_string_lossy().to_string();
                let comm = std::fs::read_to_string(e.path().join("comm")).unwrap_or_default();
                if tid == pid || comm.starts_with("loadgen") {
                    let stat = std::fs::read_to_string(e.path().join("stat")).unwrap_or_default();
                    generator += stat_times(&stat).unwrap_or(0.0) / tick;
                }
            }
        }
        Cpu { total, generator }
    }
}

/// utime + stime (clock ticks) of a /proc stat line.
fn stat_times(stat: &str) -> Option<f64> {
    let after = stat.rsplit_once(')')?.1;
    let f: Vec<&str> = after.split_whitespace().collect();
    let u: f64 = f.get(11)?.parse().ok()?;
    let s: f64 = f.get(12)?.parse().ok()?;
    Some(u + s)
}

fn clock_tick() -> f64 {
    // SAFETY: sysconf has no preconditions.
    let t = unsafe { libc::sysconf(libc::_SC_CLK_TCK) };
    if t > 0 {
        t as f64
    } else {
        100.0
    }
}

/// (VmRSS, VmHWM) of this process in MB.
pub fn rss_mb() -> (f64, f64) {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let field = |name: &str| {
        status
            .lines()
            .find_map(|l| l.strip_prefix(name))
            .and_then(|v| v.split_whitespace().next())
            .and_then(|v| v.parse::<f64>().ok())
            .map_or(0.0, |kb| kb / 1024.0)
    };
    (field("VmRSS:"), field("VmHWM:"))
}
