//! What the API shows of jobs and workers: one view type each, serialised as JSON for REST and
//! converted to protobuf for gRPC; and a job's speed/accuracy trade (`crate::trade`): its
//! error history with a projection, and its convergence map as a PNG.

use crate::db::{JobRow, JobState};
use crate::error::{Result, ServerError};
use crate::farm::{lock, now_ms, Farm};
use crate::trade::TradeView;
use luxfarm_proto as pb;
use std::collections::HashMap;
use std::sync::atomic::Ordering;

/// A job as the API shows it.
#[derive(Clone, Debug, serde::Serialize, utoipa::ToSchema)]
pub struct JobView {
    pub id: String,
    pub name: String,
    /// queued, rendering, done, cancelled, failed
    pub state: JobState,
    /// Why the job ended or failed (empty otherwise).
    pub reason: String,
    /// True once a halt rule held or a cancel arrived, while the last deltas are awaited.
    pub halting: bool,
    pub priority: i32,
    pub width: u32,
    pub height: u32,
    /// Merged samples and samples per pixel.
    pub samples: f64,
    pub spp: f64,
    pub haltspp: Option<f64>,
    pub halttime: Option<f64>,
    pub haltthreshold: Option<f64>,
    /// Failing-pixel fraction of the last convergence test.
    pub convergence: Option<f64>,
    /// Seconds since the first lease (to the end for finished jobs).
    pub elapsed: f64,
    /// Merged samples per second over the last minute.
    pub samples_per_sec: f64,
    /// Estimated seconds left (from haltspp or halttime), when known.
    pub eta: Option<f64>,
    /// The error estimate over time and the projected time to haltthreshold (`trade`).
    pub trade: TradeView,
    pub active_leases: u32,
    /// Workers on the job with the samples they contributed.
    pub workers: Vec<JobWorkerView>,
    pub submitted_ms: i64,
    pub finished_ms: Option<i64>,
    pub seed: u64,
    pub merged_deltas: u64,
    /// The animation frame the job renders (animated scene formats), when given.
    pub frame: Option<i64>,
    /// Changes whenever the merged film changes (the preview's ETag).
    pub film_version: String,
    /// Who submitted the job (a token's name; empty on an open farm).
    pub owner: String,
    /// The master's notes about the job (e.g. the default halt rule it was given).
    pub notes: Vec<String>,
    /// The frame sequence the job is a frame of, and its frame number there.
    pub sequence: Option<String>,
    pub sequence_frame: Option<i64>,
    /// The file name of the job's image: `NAME_0001.png` for a frame of a sequence.
    pub output_name: String,
    /// Tags a worker must all have to take the job.
    pub tags: Vec<String>,
    /// Memory (MiB) a worker must have (0: any); most workers at once (0: no limit).
    pub min_memory_mb: u64,
    pub max_workers: u32,
    /// Workers whose leases of this job failed, and whether they are blocked from it.
    pub failures: Vec<crate::blocks::FailureView>,
}

/// A worker's contribution to a job.
#[derive(Clone, Debug, serde::Serialize, utoipa::ToSchema)]
pub struct JobWorkerView {
    pub worker_id: String,
    pub lease_id: String,
    pub samples: f64,
    pub active: bool,
}

/// A worker as the API shows it.
#[derive(Clone, Debug, serde::Serialize, utoipa::ToSchema)]
pub struct WorkerView {
    pub id: String,
    pub name: String,
    pub threads: u32,
    /// idle, rendering, lost
    pub state: String,
    pub job_id: Option<String>,
    pub lease_id: Option<String>,
    pub last_seen_ms: i64,
    /// Seconds since the last heartbeat.
    pub last_seen_secs: f64,
    pub samples: f64,
    /// What the worker declared: tags, memory (MiB, 0: unknown) and build.
    pub tags: Vec<String>,
    pub memory_mb: u64,
    pub build: String,
    /// Why the worker gets no leases at all (quarantined), if it does not.
    pub quarantined: Option<String>,
    /// Jobs the worker is blocked from (too many failed leases).
    pub blocked_jobs: Vec<String>,
    /// Samples per second of the worker's acknowledged uploads over the last minute (three
    /// upload intervals if that is longer); 0 when it is not rendering.
    pub samples_per_sec: f64,
}

/// The view of one job.
pub fn job_view(farm: &Farm, row: &JobRow) -> Result<JobView> {
    let rt = lock(&farm.jobs).get(&row.id).cloned();
    let (ledger_samples, deltas, per_lease) = {
        let db = lock(&farm.db);
        let (s, n) = db.job_totals(&row.id)?;
        (s, n, db.lease_samples(&row.id)?)
    };
    let pixels = (row.width as f64 * row.height as f64).max(1.0);
    let mut view = JobView {
        id: row.id.clone(),
        name: row.name.clone(),
        state: row.state,
        reason: row.reason.clone(),
        halting: false,
        priority: row.priority,
        width: row.width,
        height: row.height,
        samples: ledger_samples,
        spp: ledger_samples / pixels,
        haltspp: row.haltspp,
        halttime: row.halttime,
        haltthreshold: row.haltthreshold,
        convergence: None,
        elapsed: match (row.first_lease_ms, row.finished_ms) {
            (Some(a), Some(b)) => (b - a) as f64 / 1000.0,
            (Some(a), None) => (now_ms() - a) as f64 / 1000.0,
            _ => 0.0,
        },
        samples_per_sec: 0.0,
        eta: None,
        trade: TradeView::new(Vec::new(), row.haltthreshold, None),
        active_leases: 0,
        workers: per_lease
            .into_iter()
            .map(|(lease_id, worker_id, samples)| JobWorkerView {
                worker_id,
                lease_id,
                samples,
                active: false,
            })
            .collect(),
        submitted_ms: row.submitted_ms,
        finished_ms: row.finished_ms,
        seed: row.seed,
        merged_deltas: deltas,
        frame: row.frame,
        film_version: format!("{}-{}", row.ckpt_gen, 0),
        owner: row.owner.clone(),
        notes: row.notes.clone(),
        sequence: row.sequence_id.clone(),
        sequence_frame: row.sequence_frame,
        output_name: row.output_name("png"),
        tags: row.tags.clone(),
        min_memory_mb: row.min_memory_mb,
        max_workers: row.max_workers,
        failures: farm.job_failures(&row.id)?,
    };
    // haltspp counts samples over the sample extent's pixels (`luxfarm::render::extent`).
    let mut pass_pixels = pixels;
    if let Some(rt) = rt {
        pass_pixels = (rt.info.pass_pixels as f64).max(1.0);
        let samples = lock(&rt.film).total_samples();
        view.samples = samples;
        view.spp = samples / pixels;
        let version = rt.version.load(Ordering::Relaxed);
        view.film_version = format!("{}-{}", row.ckpt_gen, version + 1);
        let st = lock(&rt.state);
        view.halting = st.halting.is_some();
        view.convergence = st.convergence.last_failing;
        view.trade = TradeView::new(st.trade.history.points(), row.haltthreshold, None);
        if let (Some((t0, s0)), Some((t1, s1))) = (st.history.front(), st.history.back()) {
            let dt = t1.duration_since(*t0).as_secs_f64();
            if dt > 0.0 {
                view.samples_per_sec = (s1 - s0) / dt;
            }
        }
        drop(st);
        let leases = lock(&rt.leases);
        view.active_leases = leases.values().filter(|l| !l.ended).count() as u32;
        for w in &mut view.workers {
            w.active = leases.get(&w.lease_id).is_some_and(|l| !l.ended);
        }
    }
    view.eta = eta(&view, pass_pixels);
    Ok(view)
}

/// A job's trade with the projections to its haltthreshold and to the relative error
/// `target`. A job that is not loaded (ended, or not started since the master started) has
/// the history saved with its last checkpoint.
pub fn trade_view(farm: &Farm, id: &str, target: Option<f64>) -> Result<TradeView> {
    let row = farm.job_row(id)?;
    let rt = lock(&farm.jobs).get(id).cloned();
    let history = match rt {
        Some(rt) => lock(&rt.state).trade.history.points(),
        None => crate::halt::load_trade(farm, id).points(),
    };
    Ok(TradeView::new(history, row.haltthreshold, target))
}

/// A PNG of the job's last convergence map (the haltthreshold test's, else `trade`'s own),
/// its longer side at most `max_size`. 503 before a test ran, 404 for a job not rendering.
pub fn convergence_png(farm: &Farm, id: &str, max_size: u32) -> Result<Vec<u8>> {
    let row = farm.job_row(id)?;
    let rt = lock(&farm.jobs).get(id).cloned().ok_or_else(|| {
        ServerError::NotFound(format!(
            "job {id} is {}: convergence maps exist only while a job renders",
            row.state.as_str()
        ))
    })?;
    let noise: Vec<f32> = {
        let st = lock(&rt.state);
        if row.haltthreshold.is_some() {
            st.convergence.test().noise_map().to_vec()
        } else {
            st.trade.own_noise().to_vec()
        }
    };
    if noise.is_empty() {
        return Err(ServerError::NotReady(format!(
            "job {id} has no convergence map yet (the first test runs after convergencestep spp)"
        )));
    }
    crate::trade::overlay_png(&noise, rt.info.width, rt.info.height, max_size)
        .map_err(ServerError::Internal)
}

/// Seconds left by the job's halt rules: haltspp's sample count (`pass_pixels`, the sample
/// extent's pixels, per spp) at the current rate, and halttime.
fn eta(v: &JobView, pass_pixels: f64) -> Option<f64> {
    if v.state.is_final() {
        return None;
    }
    let by_spp = v.haltspp.and_then(|h| {
        (v.samples_per_sec > 0.0)
            .then(|| ((h * pass_pixels - v.samples) / v.samples_per_sec).max(0.0))
    });
    let by_time = v.halttime.map(|t| (t - v.elapsed).max(0.0));
    match (by_spp, by_time) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// Views of every job in scheduling order.
pub fn job_views(farm: &Farm) -> Result<Vec<JobView>> {
    let rows = lock(&farm.db).jobs()?;
    rows.iter().map(|r| job_view(farm, r)).collect()
}

/// Views of every known worker.
pub fn worker_views(farm: &Farm) -> Result<Vec<WorkerView>> {
    let rates = worker_rates(farm, now_ms())?;
    let workers: Vec<crate::farm::WorkerRt> = lock(&farm.workers).values().cloned().collect();
    let mut v = Vec::with_capacity(workers.len());
    for w in workers {
        let rendering = !w.lost && w.lease.is_some();
        let mut blocked_jobs: Vec<String> = farm.blocked_jobs(&w.id)?.into_iter().collect();
        blocked_jobs.sort();
        v.push(WorkerView {
            quarantined: farm.quarantine(&w.id)?,
            blocked_jobs,
            name: w.name,
            threads: w.threads,
            state: if w.lost {
                "lost".into()
            } else if rendering {
                "rendering".into()
            } else {
                "idle".into()
            },
            job_id: w.lease.as_ref().map(|(j, _)| j.clone()),
            lease_id: w.lease.as_ref().map(|(_, l)| l.clone()),
            last_seen_ms: w.last_seen_ms,
            last_seen_secs: w.last_seen.elapsed().as_secs_f64(),
            samples: w.samples,
            tags: w.tags,
            memory_mb: w.memory_mb,
            build: w.build,
            samples_per_sec: if rendering {
                rates.get(&w.id).copied().unwrap_or(0.0)
            } else {
                0.0
            },
            id: w.id,
        });
    }
    v.sort_by(|a, b| a.name.cmp(&b.name).then(a.id.cmp(&b.id)));
    Ok(v)
}

/// The shortest window of [`worker_rates`]; it grows to three upload intervals when the
/// farm's interval is longer, so a rendering worker always has uploads in it.
pub const RATE_WINDOW_MS: i64 = 60_000;

/// Ledger rows may be slightly out of time order (merges run concurrently): the backwards scan
/// of [`worker_rates`] goes this far past the window's start before it stops.
const SCAN_SLACK_MS: i64 = 10_000;

/// Each worker's samples per second from its acknowledged uploads (the ledger): the samples of
/// its uploads merged within the window over the time they cover, from the upload before the
/// first of them (or the start of its lease) to the last of them.
///
/// The ledger is read newest first through a read-only connection of its own (the store's
/// methods belong to the farm module; WAL lets this reader run beside the writer), so the cost
/// follows the uploads in the window, not the size of the ledger.
pub fn worker_rates(farm: &Farm, now_ms: i64) -> Result<HashMap<String, f64>> {
    use rusqlite::OpenFlags;
    let interval_ms = (farm.cfg.upload_interval * 3000.0).min(86_400_000.0) as i64;
    let from = now_ms - RATE_WINDOW_MS.max(interval_ms);
    let conn = rusqlite::Connection::open_with_flags(
        farm.cfg.data_dir.join("farm.sqlite"),
        OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_NO_MUTEX,
    )?;
    let mut st = conn.prepare(
        "SELECT l.worker_id, g.samples, g.merged_ms, COALESCE( \
           (SELECT p.merged_ms FROM ledger p WHERE p.lease_id = g.lease_id AND p.seq < g.seq \
            ORDER BY p.seq DESC LIMIT 1), l.started_ms) \
         FROM ledger g JOIN leases l ON l.id = g.lease_id ORDER BY g.rowid DESC",
    )?;
    let mut rows = st.query([])?;
    // worker -> (samples, first covered time, last upload time)
    let mut acc: HashMap<String, (f64, i64, i64)> = HashMap::new();
    while let Some(r) = rows.next()? {
        let merged: i64 = r.get(2)?;
        if merged < from - SCAN_SLACK_MS {
            break;
        }
        if merged < from {
            continue;
        }
        let (worker, samples, prev): (String, f64, i64) = (r.get(0)?, r.get(1)?, r.get(3)?);
        let e = acc.entry(worker).or_insert((0.0, prev, merged));
        e.0 += samples;
        e.1 = e.1.min(prev);
        e.2 = e.2.max(merged);
    }
    Ok(acc
        .into_iter()
        .filter(|(_, (s, a, b))| b > a && s.is_finite())
        .map(|(w, (s, a, b))| (w, s * 1000.0 / (b - a) as f64))
        .collect())
}

impl From<JobView> for pb::JobInfo {
    fn from(v: JobView) -> pb::JobInfo {
        pb::JobInfo {
            id: v.id,
            name: v.name,
            state: v.state.as_str().into(),
            reason: v.reason,
            priority: v.priority,
            width: v.width,
            height: v.height,
            samples: v.samples,
            spp: v.spp,
            haltspp: v.haltspp,
            halttime: v.halttime,
            haltthreshold: v.haltthreshold,
            elapsed: v.elapsed,
            samples_per_sec: v.samples_per_sec,
            active_leases: v.active_leases,
            submitted_ms: v.submitted_ms,
            finished_ms: v.finished_ms,
            seed: v.seed,
            convergence: v.convergence,
            merged_deltas: v.merged_deltas,
            frame: v.frame,
            owner: v.owner,
            notes: v.notes,
            sequence: v.sequence.unwrap_or_default(),
            sequence_frame: v.sequence_frame,
            tags: v.tags,
        }
    }
}

impl From<WorkerView> for pb::WorkerInfo {
    fn from(w: WorkerView) -> pb::WorkerInfo {
        pb::WorkerInfo {
            id: w.id,
            name: w.name,
            threads: w.threads,
            state: w.state,
            job_id: w.job_id.unwrap_or_default(),
            lease_id: w.lease_id.unwrap_or_default(),
            last_seen_ms: w.last_seen_ms,
            samples: w.samples,
            samples_per_sec: w.samples_per_sec,
            tags: w.tags,
            memory_mb: w.memory_mb,
            build: w.build,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Config;
    use crate::db::NewJob;

    const NOW: i64 = 1_000_000_000;

    #[test]
    fn worker_rates_cover_the_uploads_of_the_window() {
        let dir = tempfile::tempdir().unwrap();
        let farm = Farm::open(Config::local(dir.path().to_path_buf())).unwrap();
        {
            let mut db = lock(&farm.db);
            db.insert_job(&NewJob {
                id: "j",
                name: "j",
                priority: 0,
                bundle_hash: "h",
                scene_path: "s.lxs",
                seed: 1,
                haltspp: None,
                halttime: None,
                haltthreshold: None,
                width: 8,
                height: 6,
                submitted_ms: 0,
                ..Default::default()
            })
            .unwrap();
            // Rows come in merge order. w3: uploads long ago only.
            db.create_lease("l3", "j", "w3", NOW - 900_000).unwrap();
            db.ledger_insert("l3", 1, "j", 1e6, 10, NOW - 800_000)
                .unwrap();
            // w1: 1000 samples every 10 s for 200 s.
            db.create_lease("l1", "j", "w1", NOW - 200_000).unwrap();
            for k in 1..=20 {
                db.ledger_insert("l1", k, "j", 1000.0, 10, NOW - 200_000 + k as i64 * 10_000)
                    .unwrap();
            }
            // w2: one upload of 500 samples 4 s after its lease began (merged a little out
            // of time order).
            db.create_lease("l2", "j", "w2", NOW - 5_000).unwrap();
            db.ledger_insert("l2", 1, "j", 500.0, 10, NOW - 1_000)
                .unwrap();
        }
        let r = worker_rates(&farm, NOW).unwrap();
        // The 7 uploads from NOW - 60 s on, covering NOW - 70 s .. NOW.
        assert!((r["w1"] - 100.0).abs() < 1e-9, "{r:?}");
        assert!((r["w2"] - 125.0).abs() < 1e-9, "{r:?}");
        assert!(!r.contains_key("w3"), "{r:?}");
        // A minute later nothing is recent.
        assert!(worker_rates(&farm, NOW + 200_000).unwrap().is_empty());
    }

    #[test]
    fn eta_counts_haltspp_over_the_sample_extent() {
        let dir = tempfile::tempdir().unwrap();
        let farm = Farm::open(Config::local(dir.path().to_path_buf())).unwrap();
        lock(&farm.db)
            .insert_job(&NewJob {
                id: "j",
                name: "j",
                bundle_hash: "h",
                scene_path: "s.lxs",
                seed: 1,
                haltspp: Some(4.0),
                width: 8,
                height: 6,
                ..Default::default()
            })
            .unwrap();
        let mut v = job_view(&farm, &farm.job_row("j").unwrap()).unwrap();
        v.state = crate::db::JobState::Rendering;
        v.samples = 100.0;
        v.samples_per_sec = 10.0;
        // 4 spp over a 9 x 7 extent (an 8 x 6 image under a 0.5 box) is 252 samples.
        assert_eq!(eta(&v, 63.0), Some(15.2));
        assert_eq!(eta(&v, 48.0), Some(9.2));
        v.samples = 1000.0;
        assert_eq!(eta(&v, 63.0), Some(0.0));
        v.state = crate::db::JobState::Done;
        assert_eq!(eta(&v, 63.0), None);
    }
}
