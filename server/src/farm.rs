//! The master's shared state: the store, the jobs being rendered (their merged films) and the
//! workers, plus job submission and queries. Leases and uploads are in `lease`, halting,
//! checkpoints and cancel in `halt`, identities in `auth`.
//!
//! Opening a data directory ([`Farm::open`]) checks it first (`datadir`): a database that
//! does not match the directory is refused, a job whose checkpoint or bundle is missing fails
//! alone with the file named. Workers and their open leases are taken back from the store, so
//! workers carry on after a restart and upload again what the master had not made durable.

use crate::admission::{self, SubmitOptions};
use crate::config::Config;
use crate::datadir;
use crate::db::{Db, JobRow, JobState, NewJob};
use crate::error::{Result, ServerError};
use crate::metrics::{MergeReport, Metrics};
use crate::scene::Film;
use crate::scene::{self, SceneInfo};
use crate::scratch::{BytePool, ScratchPool};
use luxfarm_wire::bundle::{self, Limits};
use std::collections::{HashMap, VecDeque};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Instant, SystemTime, UNIX_EPOCH};

/// Milliseconds since the Unix epoch.
pub fn now_ms() -> i64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_millis() as i64)
        .unwrap_or(0)
}

/// A fresh unique id with a prefix (time, counter and process id hashed). Ids are names, not
/// secrets: credentials come from [`secret`].
pub fn new_id(prefix: &str) -> String {
    use sha2::{Digest, Sha256};
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let nanos = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    let mut h = Sha256::new();
    h.update(nanos.to_le_bytes());
    h.update(n.to_le_bytes());
    h.update(std::process::id().to_le_bytes());
    format!("{prefix}{}", &bundle::hex(&h.finalize())[..16])
}

/// 32 random bytes from the operating system, in hex, after `prefix` (credentials).
pub fn secret(prefix: &str) -> Result<String> {
    let mut b = [0u8; 32];
    getrandom::getrandom(&mut b)
        .map_err(|e| ServerError::Internal(format!("no random numbers: {e}")))?;
    Ok(format!("{prefix}{}", bundle::hex(&b)))
}

/// Locks a std mutex, recovering from poisoning (a panicked holder leaves consistent data
/// here: every critical section is a plain update).
pub fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

/// One lease of a rendering job, as the master tracks it in memory.
#[derive(Clone, Debug)]
pub struct LeaseRt {
    /// The worker was told (or will be told) to stop.
    pub stop: bool,
    /// The lease ended: its last delta arrived, it was lost, or the job ended.
    pub ended: bool,
    /// Samples merged from this lease.
    pub samples: f64,
    /// Samples the lease may render in all (None: unbounded); see `budget`.
    pub budget: Option<f64>,
    /// Samples the worker says it rendered, and the samples of one of its passes.
    pub rendered: f64,
    pub pass_samples: f64,
}

impl LeaseRt {
    /// A fresh lease with the budget it was granted.
    pub fn new(budget: Option<f64>) -> LeaseRt {
        LeaseRt {
            stop: false,
            ended: false,
            samples: 0.0,
            budget,
            rendered: 0.0,
            pass_samples: 0.0,
        }
    }
}

/// A job being rendered: its merged film and leases.
pub struct JobRt {
    pub id: String,
    pub info: SceneInfo,
    pub film: Mutex<Film>,
    /// Bumped on every merge (ETag of previews, checkpoint trigger).
    pub version: AtomicU64,
    /// Set when the job ends: no merge is accepted after the final checkpoint.
    pub closed: AtomicBool,
    pub leases: Mutex<HashMap<String, LeaseRt>>,
    pub state: Mutex<RunState>,
    /// Held while a checkpoint is written (the tick's, the shutdown drain's, the job end's):
    /// one at a time per job.
    pub checkpointing: Mutex<()>,
    /// The job's kept copy of its merged film, taken for a checkpoint or the analyses
    /// (`crate::analysis`) so the film lock is held only while copying; its buffers are
    /// reused from one copy to the next (see [`JobRt::copy_film`]).
    pub copy: Mutex<Option<Film>>,
}

impl JobRt {
    /// Copies the merged film into the kept copy `slot` (a guard of [`JobRt::copy`]),
    /// reusing its buffers, and returns it with what `under_lock` read while the film was
    /// locked (the film's version, the ledger's last row).
    pub fn copy_film<'a, T>(
        &self,
        slot: &'a mut Option<Film>,
        under_lock: impl FnOnce(&Film) -> T,
    ) -> (&'a Film, T) {
        let copy = slot.get_or_insert_with(|| Film::new(1, 1, Vec::new()));
        let film = lock(&self.film);
        copy.clone_from(&film);
        let read = under_lock(&film);
        (copy, read)
    }
}

/// The points of a checkpoint a probe (`Farm::checkpoint_probe`) sees, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CheckpointStep {
    /// Another checkpoint (or an analysis) of the job holds what this one needs: it waits.
    Waiting,
    /// The film was copied and the generation chosen; nothing is written yet.
    Copied { generation: i64 },
}

/// A function told each [`CheckpointStep`] of every checkpoint (job id, step), on the
/// checkpointing thread: tests hold a checkpoint at a step to drive an interleaving.
pub type CheckpointProbe = Arc<dyn Fn(&str, CheckpointStep) + Send + Sync>;

/// Mutable bookkeeping of a rendering job.
pub struct RunState {
    /// Set when a halt rule held or the job was cancelled: the final state and reason, and
    /// when the halt began (the last deltas are awaited until a deadline).
    pub halting: Option<(JobState, String, Instant)>,
    pub checkpoint_version: u64,
    pub last_checkpoint: Instant,
    /// The last checkpoint failure (file and reason), retried every checkpoint interval.
    pub checkpoint_error: Option<String>,
    /// (time, merged samples) over the last minute, for samples per second.
    pub history: VecDeque<(Instant, f64)>,
    /// Spp at the last convergence test, the test's state and its last result.
    pub convergence: crate::scene::Convergence,
    /// No analysis before this moment (`crate::analysis`: the job's share of time).
    pub analysis_after: Option<Instant>,
    /// The sampling maps sent to the workers: the noise-aware map built from the merged film
    /// (noise-aware jobs) and the user sampling map (`crate::usermap`), combined.
    pub noise_map: crate::noisemap::NoiseMapState,
    /// The error estimate over time (`crate::trade`); empty again after a master restart.
    pub trade: crate::trade::TradeState,
    /// First lease time (job clock for halttime).
    pub first_lease_ms: Option<i64>,
}

/// A worker as the master knows it.
#[derive(Clone, Debug)]
pub struct WorkerRt {
    pub id: String,
    pub name: String,
    pub threads: u32,
    pub last_seen: Instant,
    pub last_seen_ms: i64,
    pub lease: Option<(String, String)>,
    pub lost: bool,
    pub samples: f64,
    /// What the worker declared: tags, memory (MiB, 0: unknown) and build.
    pub tags: Vec<String>,
    pub memory_mb: u64,
    pub build: String,
}

/// The master.
pub struct Farm {
    pub cfg: Config,
    pub db: Mutex<Db>,
    pub jobs: Mutex<HashMap<String, Arc<JobRt>>>,
    pub workers: Mutex<HashMap<String, WorkerRt>>,
    pub metrics: Metrics,
    /// Bumped whenever a job changes (watchers wake up).
    pub changed: tokio::sync::watch::Sender<u64>,
    /// Wakes workers waiting for an assignment.
    pub work_available: tokio::sync::Notify,
    /// Uploads decoded and merged at once (one per core): more would only hold more decoded
    /// films in memory while competing for the same cores.
    pub merge_slots: tokio::sync::Semaphore,
    /// Uploads received at once (four per core): the others wait before their bytes are read,
    /// held back by HTTP/2 flow control, so the master's memory stays bounded under load
    /// (a waiting worker keeps rendering into its film).
    pub receive_slots: tokio::sync::Semaphore,
    /// Submissions unpacked at once (`--max-unpacking`).
    pub unpack_slots: tokio::sync::Semaphore,
    /// Cores the merge slots were sized by (admission control counts decoded deltas).
    pub cores: usize,
    /// Films deltas are decoded into, one per merge slot at most, reused across uploads.
    pub scratch: ScratchPool,
    /// Buffers uploads are received into, as many, reused across uploads.
    pub received: BytePool,
    /// This run of the master: workers seeing it change upload again what was not durable.
    pub instance: String,
    /// Set on SIGTERM/SIGINT: no new leases or uploads, in-flight work finishes.
    pub draining: AtomicBool,
    /// Told the steps of every checkpoint (tests); None in service.
    pub checkpoint_probe: Mutex<Option<CheckpointProbe>>,
}

impl Farm {
    /// Opens the data directory and store, checks that they match, and prepares unfinished
    /// jobs, their workers and leases for resumption.
    pub fn open(cfg: Config) -> Result<Arc<Farm>> {
        datadir::prepare_layout(&cfg.data_dir)?;
        let mut db = Db::open(&cfg.data_dir.join("farm.sqlite"))?;
        db.set_hook_targets(cfg.webhook.clone(), cfg.public_url.clone());
        datadir::check_identity(&db, &cfg.data_dir)?;
        datadir::check_jobs(&db, &cfg.data_dir, now_ms())?;
        let workers = datadir::resume_workers(&db)?
            .into_iter()
            .map(|(w, lease)| {
                let rt = WorkerRt {
                    id: w.id.clone(),
                    name: w.name,
                    threads: w.threads,
                    // A worker gets a full timeout from the restart to come back.
                    last_seen: Instant::now(),
                    last_seen_ms: w.last_seen_ms,
                    lease,
                    lost: false,
                    samples: 0.0,
                    tags: w.tags,
                    memory_mb: w.memory_mb,
                    build: w.build,
                };
                (w.id, rt)
            })
            .collect();
        let (changed, _) = tokio::sync::watch::channel(0);
        let cores = std::thread::available_parallelism().map_or(2, |n| n.get());
        Ok(Arc::new(Farm {
            unpack_slots: tokio::sync::Semaphore::new(cfg.max_unpacking),
            cfg,
            db: Mutex::new(db),
            jobs: Mutex::new(HashMap::new()),
            workers: Mutex::new(workers),
            metrics: Metrics::default(),
            changed,
            work_available: tokio::sync::Notify::new(),
            merge_slots: tokio::sync::Semaphore::new(cores),
            receive_slots: tokio::sync::Semaphore::new(4 * cores),
            scratch: ScratchPool::new(cores),
            received: BytePool::new(cores),
            cores,
            instance: new_id("m"),
            draining: AtomicBool::new(false),
            checkpoint_probe: Mutex::new(None),
        }))
    }

    /// Tells watchers that something changed.
    pub fn touch(&self) {
        self.changed.send_modify(|v| *v += 1);
    }

    /// Tells the checkpoint probe, if any, that a checkpoint of `job` reached `step`.
    pub fn probe(&self, job: &str, step: CheckpointStep) {
        let probe = lock(&self.checkpoint_probe).clone();
        if let Some(p) = probe {
            p(job, step);
        }
    }

    /// Locks `m` for a checkpoint of `job`, telling the probe when it has to wait for it.
    pub fn wait_lock<'a, T>(&self, job: &str, m: &'a Mutex<T>) -> MutexGuard<'a, T> {
        match m.try_lock() {
            Ok(g) => g,
            Err(std::sync::TryLockError::Poisoned(p)) => p.into_inner(),
            Err(std::sync::TryLockError::WouldBlock) => {
                self.probe(job, CheckpointStep::Waiting);
                lock(m)
            }
        }
    }

    /// True once the master is shutting down.
    pub fn is_draining(&self) -> bool {
        self.draining.load(Ordering::SeqCst)
    }

    /// Directory of a job's checkpoints and outputs.
    pub fn job_dir(&self, id: &str) -> PathBuf {
        self.cfg.data_dir.join("jobs").join(id)
    }

    /// Directory a bundle is unpacked in.
    pub fn scene_dir(&self, hash: &str) -> PathBuf {
        self.cfg.data_dir.join("scenes").join(hash)
    }

    /// The stored bundle (canonical tar) of a hash.
    pub fn bundle_path(&self, hash: &str) -> PathBuf {
        self.cfg
            .data_dir
            .join("bundles")
            .join(format!("{hash}.tar"))
    }

    /// One job row, or NotFound.
    pub fn job_row(&self, id: &str) -> Result<JobRow> {
        lock(&self.db)
            .job(id)?
            .ok_or_else(|| ServerError::NotFound(format!("no job {id:?}")))
    }

    /// Accepts an upload (raw .lxs, .zip or .tar): unpacks it safely, checks the scene parses
    /// within its own directory and passes admission control, stores it content-addressed and
    /// queues a job.
    pub fn submit(&self, bytes: &[u8], file_name: &str, opts: &SubmitOptions) -> Result<JobRow> {
        if bytes.len() as u64 > self.cfg.max_upload {
            return Err(ServerError::TooLarge(format!(
                "upload of {} bytes exceeds the limit of {}",
                bytes.len(),
                self.cfg.max_upload
            )));
        }
        if self.is_draining() {
            return Err(ServerError::Unavailable(
                "the master is shutting down: submit again once it is back".into(),
            ));
        }
        admission::check_overrides(&self.cfg, opts)?;
        let staging = self.cfg.data_dir.join("tmp").join(new_id("s"));
        std::fs::create_dir_all(&staging)?;
        let result = self.submit_staged(bytes, file_name, opts, &staging);
        if staging.exists() {
            let _ = std::fs::remove_dir_all(&staging);
        }
        result
    }

    fn submit_staged(
        &self,
        bytes: &[u8],
        file_name: &str,
        opts: &SubmitOptions,
        staging: &Path,
    ) -> Result<JobRow> {
        let limits = Limits {
            max_unpacked: self.cfg.max_unpacked,
            ..Limits::default()
        };
        let unpacked = staging.join("b");
        std::fs::create_dir_all(&unpacked)?;
        let files = bundle::unpack(bytes, file_name, &unpacked, limits)?;
        let scene_rel = bundle::pick_scene(&files, opts.scene.as_deref().unwrap_or(""))?;
        let info = scene::inspect(&unpacked, &scene_rel, opts.frame)?;
        let admitted = admission::admit(&self.cfg, self.cores, &info, opts)?;
        let tar_tmp = staging.join("bundle.tar");
        let hash = bundle::write_canonical_tar(&unpacked, &files, &tar_tmp)?;
        let bundle_path = self.bundle_path(&hash);
        if !bundle_path.exists() {
            std::fs::rename(&tar_tmp, &bundle_path)?;
        }
        let scene_dir = self.scene_dir(&hash);
        if !scene_dir.exists() {
            std::fs::rename(&unpacked, &scene_dir)?;
        }
        let id = new_id("j");
        let tags = admission::clean_tags(&opts.tags)?;
        let frame_number = opts.sequence_frame.or(opts.frame);
        let sequence = opts.sequence.as_deref().filter(|s| !s.is_empty());
        let frame_name = match sequence {
            Some(seq) => Some(self.check_frame(seq, frame_number, &opts.owner)?),
            None => None,
        };
        let name = frame_name.unwrap_or_else(|| {
            opts.name
                .as_deref()
                .map(admission::clean_name)
                .filter(|n| !n.is_empty())
                .unwrap_or_else(|| admission::clean_name(&info.name))
        });
        let seed = opts.seed.unwrap_or_else(|| now_ms() as u64);
        let scene_path = scene_rel.to_string_lossy().replace('\\', "/");
        lock(&self.db).insert_job(&NewJob {
            id: &id,
            name: &name,
            priority: opts.priority.unwrap_or(0),
            bundle_hash: &hash,
            scene_path: &scene_path,
            seed: seed & (i64::MAX as u64),
            haltspp: admitted.haltspp,
            halttime: admitted.halttime,
            haltthreshold: admitted.haltthreshold,
            width: info.width,
            height: info.height,
            submitted_ms: now_ms(),
            frame: opts.frame,
            owner: &opts.owner,
            notes: &admitted.notes,
            sequence_id: sequence,
            sequence_frame: sequence.and(frame_number),
            tags: &tags,
            min_memory_mb: opts.min_memory_mb.unwrap_or(0),
            max_workers: opts.max_workers.unwrap_or(0),
            webhook: opts.webhook.as_deref().unwrap_or(""),
        })?;
        tracing::info!(job = %id, %name, bundle = %hash, "job queued");
        self.metrics.jobs_submitted.fetch_add(1, Ordering::Relaxed);
        self.touch();
        self.work_available.notify_waiters();
        self.job_row(&id)
    }

    /// The merge statistics of a loaded job, for the capacity benchmark.
    pub fn merge_report(&self, job: &str) -> Option<MergeReport> {
        let rt = lock(&self.jobs).get(job).cloned()?;
        let job_samples = lock(&rt.film).total_samples();
        Some(MergeReport {
            job_samples,
            merges: self.metrics.merges.load(Ordering::Relaxed),
            recent: self.metrics.recent_merges(),
            lost_workers: lock(&self.workers).values().filter(|w| w.lost).count(),
        })
    }
}

impl crate::webhooks::Outbox for Farm {
    fn with_db<T>(&self, f: impl FnOnce(&Db) -> Result<T>) -> Result<T> {
        f(&lock(&self.db))
    }
}
