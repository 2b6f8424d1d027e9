//! `luxfarm bench master`: master capacity under many workers (not a test).
//!
//! Starts a real master in this process (loopback, temporary data dir, its own tokio runtime
//! with threads named `master`), queues one job of the chosen resolution, and simulates N
//! workers over the real gRPC worker protocol ([`load`], runtime threads named
//! `loadgen`): each registers, takes a lease, heartbeats, and uploads a full-frame delta every
//! interval, the first uploads staggered over one interval. Reports offered and sustained
//! merges/s, server-side latency (decode, merge, total) and client-side upload round trips,
//! the backlog (uploads due but not yet acknowledged) sampled every second, RSS, bytes/s and
//! the CPU of master and generator, checks that the job's merged samples equal the sum of the
//! acknowledged deltas, and prints a verdict.

pub mod load;

use crate::support::{loadavg, parse_res};
use load::{lock, Cpu, Payload, Schedule, SimWorker, Stats};
use luxfarm_server::{MergeReport, Running, SubmitOptions};
use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::Duration;
use tokio::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// Simulated workers.
    #[arg(long, default_value_t = 200)]
    pub workers: usize,
    /// Seconds between a worker's uploads.
    #[arg(long, default_value_t = 30.0)]
    pub interval: f64,
    /// Seconds of load (at least 3 intervals).
    #[arg(long, default_value_t = 180.0)]
    pub duration: f64,
    /// Film resolution WIDTHxHEIGHT.
    #[arg(long, default_value = "1920x1080")]
    pub res: String,
    /// Upload encoding: lxd2 (what workers send) or lxd1 (raw f64).
    #[arg(long, default_value = "lxd2")]
    pub encoding: String,
    /// Distinct pre-built deltas, cycled through.
    #[arg(long, default_value_t = 3)]
    pub payloads: usize,
    /// Samples per pixel in each delta.
    #[arg(long, default_value_t = 4)]
    pub spp: u32,
    /// Threads of the master's runtime (default: the machine's cores).
    #[arg(long)]
    pub master_threads: Option<usize>,
}

fn scene_text(w: u32, h: u32) -> String {
    format!(
        "LookAt 0 -3 1 0 0 1 0 0 1\nCamera \"perspective\" \"float fov\" [45]\n\
         Film \"fleximage\" \"integer xresolution\" [{w}] \"integer yresolution\" [{h}]\n\
         PixelFilter \"mitchell\"\nSampler \"random\" \"integer pixelsamples\" [1]\n\
         WorldBegin\nAttributeBegin\n  AreaLightSource \"area\" \"color L\" [4 4 4]\n  \
         Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" \
         [-0.5 -0.5 1.99 0.5 -0.5 1.99 0.5 0.5 1.99 -0.5 0.5 1.99]\nAttributeEnd\n\
         Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" \
         [-1 -1 0 1 -1 0 1 1 0 -1 1 0]\nWorldEnd\n"
    )
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let i = ((sorted.len() - 1) as f64 * p).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

fn latency_line(name: &str, mut v: Vec<f64>) -> String {
    v.sort_by(f64::total_cmp);
    format!(
        "  {name:<28} p50 {:7.1} ms  p95 {:7.1} ms  p99 {:7.1} ms  max {:7.1} ms  (n={})",
        percentile(&v, 0.5) * 1e3,
        percentile(&v, 0.95) * 1e3,
        percentile(&v, 0.99) * 1e3,
        v.last().copied().unwrap_or(f64::NAN) * 1e3,
        v.len()
    )
}

/// One backlog sample.
struct Sample {
    backlog: i64,
    in_flight: u64,
    rss: f64,
}

fn build_payloads(a: &Args, w: u32, h: u32) -> anyhow::Result<Vec<Payload>> {
    (0..a.payloads.max(1))
        .map(|k| load::payload(&load::noise_film(w, h, a.spp, k as u32), &a.encoding))
        .collect()
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let (w, h) = parse_res(&a.res)?;
    if a.workers == 0 || a.interval <= 0.0 || a.duration < 3.0 * a.interval {
        anyhow::bail!("need at least one worker and --duration >= 3 x --interval");
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let t = std::time::Instant::now();
    let payloads = Arc::new(build_payloads(&a, w, h)?);
    let payload_mb: f64 = payloads.iter().map(|p| p.bytes as f64).sum::<f64>() / 1e6;
    println!(
        "bench master: {} workers, {w}x{h} deltas in {} ({:.1} MB each, {} pre-built in {:.1} s), \
         one every {} s per worker for {} s; {cores} cores; load {}",
        a.workers,
        a.encoding,
        payload_mb / payloads.len() as f64,
        payloads.len(),
        t.elapsed().as_secs_f64(),
        a.interval,
        a.duration,
        loadavg()
    );
    let master_rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(a.master_threads.unwrap_or(cores).max(1))
        .thread_name("master")
        .enable_all()
        .build()?;
    let dir = tempfile::tempdir()?;
    let mut cfg = luxfarm_server::Config::local(dir.path().to_path_buf());
    cfg.upload_interval = a.interval;
    let running = master_rt.block_on(luxfarm_server::start(cfg))?;
    // No haltspp: the simulated workers' deltas are not held to a sample budget.
    let opts = SubmitOptions {
        name: Some("bench-master".into()),
        halttime: Some(86_400.0),
        ..SubmitOptions::default()
    };
    let job = running.submit(scene_text(w, h).as_bytes(), "bench.lxs", &opts)?;
    let url = format!("http://{}", running.addr());
    let gen_rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(cores)
        .thread_name("loadgen")
        .enable_all()
        .build()?;
    let stats = Arc::new(Stats::default());
    let result = gen_rt.block_on(generate(&a, &url, payloads.clone(), stats.clone()))?;
    if result.drain.is_none() {
        gen_rt.block_on(settle(&running, &job));
    }
    report(&a, (w, h), &running, &job, &stats, &result, &payloads)?;
    running.stop();
    master_rt.shutdown_timeout(Duration::from_secs(2));
    Ok(ExitCode::SUCCESS)
}

/// Joins the workers, runs the schedule, samples the backlog every second, then waits for the
/// last uploads (at most 3 intervals).
async fn generate(
    a: &Args,
    url: &str,
    payloads: Arc<Vec<Payload>>,
    stats: Arc<Stats>,
) -> anyhow::Result<Run> {
    let mut joins = Vec::new();
    for i in 0..a.workers {
        let url = url.to_string();
        joins.push(tokio::spawn(async move { SimWorker::join(&url, i).await }));
    }
    let mut workers = Vec::new();
    for j in joins {
        workers.push(j.await??);
    }
    let sched = Schedule {
        t0: Instant::now() + Duration::from_millis(500),
        interval: Duration::from_secs_f64(a.interval),
        workers: a.workers,
        duration: Duration::from_secs_f64(a.duration),
    };
    let mut tasks = Vec::new();
    let mut beats = Vec::new();
    for (i, wk) in workers.into_iter().enumerate() {
        beats.push(tokio::spawn(
            wk.control(url)?
                .heartbeats(Duration::from_secs(5), stats.clone()),
        ));
        tasks.push(tokio::spawn(wk.uploads(
            i,
            sched,
            payloads.clone(),
            stats.clone(),
        )));
    }
    tokio::time::sleep_until(sched.t0).await;
    let cpu0 = Cpu::now();
    let mut samples = Vec::new();
    let mut tick =
        tokio::time::interval_at(sched.t0 + Duration::from_secs(1), Duration::from_secs(1));
    let end = sched.t0 + sched.duration;
    while Instant::now() < end {
        tick.tick().await;
        let t = Instant::now().duration_since(sched.t0);
        let done = stats.acked.load(Ordering::Relaxed)
            + stats.duplicates.load(Ordering::Relaxed)
            + stats.abandoned.load(Ordering::Relaxed);
        samples.push(Sample {
            backlog: sched.offered_by(t) as i64 - done as i64,
            in_flight: stats.in_flight.load(Ordering::Relaxed),
            rss: load::rss_mb().0,
        });
    }
    let cpu1 = Cpu::now();
    let drain_start = Instant::now();
    let stoppers: Vec<_> = tasks.iter().map(|t| t.abort_handle()).collect();
    let drained = tokio::time::timeout(
        Duration::from_secs_f64(a.interval * 3.0),
        futures_join(tasks),
    )
    .await
    .is_ok();
    for b in beats {
        b.abort();
    }
    if !drained {
        // Stop the simulated workers; uploads the master already received still merge (their
        // acks go nowhere), so the check waits for the master's merge count to settle.
        for s in stoppers {
            s.abort();
        }
    }
    Ok(Run {
        samples,
        cpu: (cpu0, cpu1),
        window: sched.duration.as_secs_f64(),
        offered: sched.offered_by(sched.duration),
        drain: drained.then(|| drain_start.elapsed().as_secs_f64()),
    })
}

/// Waits until the master's merge count has not changed for two seconds (at most a minute).
async fn settle(master: &Running, job: &str) {
    let count = || master.merge_report(job).map(|m| m.merges);
    let mut last = count();
    let mut still = 0;
    for _ in 0..120 {
        tokio::time::sleep(Duration::from_millis(500)).await;
        let now = count();
        still = if now == last { still + 1 } else { 0 };
        last = now;
        if still >= 4 {
            return;
        }
    }
}

async fn futures_join(tasks: Vec<tokio::task::JoinHandle<()>>) {
    for t in tasks {
        let _ = t.await;
    }
}

/// What the load window produced.
struct Run {
    samples: Vec<Sample>,
    cpu: (Cpu, Cpu),
    window: f64,
    offered: u64,
    /// Seconds to acknowledge the uploads still pending at the end (None: not within 3
    /// intervals).
    drain: Option<f64>,
}

fn mean(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    if n == 0 {
        0.0
    } else {
        s / n as f64
    }
}

fn report(
    a: &Args,
    (w, h): (u32, u32),
    master: &Running,
    job: &str,
    stats: &Stats,
    run: &Run,
    payloads: &[Payload],
) -> anyhow::Result<()> {
    let merged = master
        .merge_report(job)
        .ok_or_else(|| anyhow::anyhow!("the bench job is not loaded"))?;
    let win = run.window;
    let in_window = lock(&stats.rtts).iter().filter(|(_, t)| *t <= win).count();
    let acked = stats.acked.load(Ordering::Relaxed);
    println!("\nload window {win:.0} s (load average now {}):", loadavg());
    println!(
        "  uploads offered {:>6}  ({:.2}/s)   acknowledged in window {:>6} ({:.2}/s)   \
         total merged {acked}, duplicates {}, failed attempts {}, abandoned {}",
        run.offered,
        run.offered as f64 / win,
        in_window,
        in_window as f64 / win,
        stats.duplicates.load(Ordering::Relaxed),
        stats.failures.load(Ordering::Relaxed),
        stats.abandoned.load(Ordering::Relaxed),
    );
    let timings = &merged.recent;
    println!("latency:");
    println!(
        "{}",
        latency_line(
            "server decode",
            timings.iter().map(|t| t.decode.as_secs_f64()).collect()
        )
    );
    println!(
        "{}",
        latency_line(
            "server lock wait + merge",
            timings.iter().map(|t| t.merge.as_secs_f64()).collect()
        )
    );
    println!(
        "{}",
        latency_line(
            "server total (received->ack)",
            timings.iter().map(|t| t.total.as_secs_f64()).collect()
        )
    );
    println!(
        "{}",
        latency_line(
            "client upload round trip",
            lock(&stats.rtts).iter().map(|(r, _)| *r).collect()
        )
    );
    let third = run.samples.len() / 3;
    let first = mean(run.samples[..third].iter().map(|s| s.backlog as f64));
    let last = mean(
        run.samples[run.samples.len() - third..]
            .iter()
            .map(|s| s.backlog as f64),
    );
    let max_backlog = run.samples.iter().map(|s| s.backlog).max().unwrap_or(0);
    println!(
        "backlog (due, not acknowledged; 1 s samples): first third mean {first:.1}, last third \
         mean {last:.1}, max {max_backlog}; in flight max {}",
        run.samples.iter().map(|s| s.in_flight).max().unwrap_or(0)
    );
    let per10: Vec<String> = run
        .samples
        .chunks(10)
        .map(|c| format!("{:.0}", mean(c.iter().map(|s| s.backlog as f64))))
        .collect();
    println!("  backlog per 10 s: {}", per10.join(" "));
    let (rss_now, hwm) = load::rss_mb();
    let rss_mean = mean(run.samples.iter().map(|s| s.rss));
    let held: f64 = payloads.iter().map(|p| p.bytes as f64).sum::<f64>() / 1e6;
    println!(
        "memory: process RSS mean {rss_mean:.0} MB, peak {hwm:.0} MB, now {rss_now:.0} MB \
         (the generator holds {held:.0} MB of payloads; the rest is the master)"
    );
    let bytes = stats.acked_bytes.load(Ordering::Relaxed) as f64;
    println!(
        "bytes: {:.1} MB/s of deltas acknowledged ({:.0} MB total)",
        bytes / 1e6 / (win + run.drain.unwrap_or(0.0)),
        bytes / 1e6
    );
    let (c0, c1) = run.cpu;
    let gen = (c1.generator - c0.generator) / win;
    let master = ((c1.total - c0.total) - (c1.generator - c0.generator)) / win;
    let lost = merged.lost_workers;
    let per_merge = master * win / (in_window.max(1) as f64);
    println!(
        "master CPU per merged delta {:.0} ms (receive, decode, merge, checkpoints, heartbeats): \
         {:.1} merges/s per core that the master gets",
        per_merge * 1e3,
        1.0 / per_merge.max(1e-9)
    );
    println!(
        "CPU (cores busy over the window): master {master:.2}, generator {gen:.2}; heartbeats {}, \
         workers timed out {lost}",
        stats.heartbeats.load(Ordering::Relaxed)
    );
    match run.drain {
        Some(d) => println!("drain: the last uploads were acknowledged {d:.1} s after the window"),
        None => println!("drain: uploads still pending 3 intervals after the window"),
    }
    let per_delta = f64::from(w) * f64::from(h) * f64::from(a.spp);
    let ok = verify(&merged, stats, run.drain.is_some(), per_delta);
    let keeps_up = last <= first + (a.workers as f64 * 0.02).max(2.0)
        && run.drain.is_some()
        && lost == 0
        && stats.abandoned.load(Ordering::Relaxed) == 0;
    println!(
        "VERDICT: {} — {} workers x {}x{} every {} s: offered {:.2}/s, acknowledged {:.2}/s, \
         backlog {first:.1} -> {last:.1}, server p95 {:.0} ms; merge count {}",
        if keeps_up { "KEEPS UP" } else { "FALLS BEHIND" },
        a.workers,
        w,
        h,
        a.interval,
        run.offered as f64 / win,
        in_window as f64 / win,
        {
            let mut v: Vec<f64> = timings.iter().map(|t| t.total.as_secs_f64()).collect();
            v.sort_by(f64::total_cmp);
            percentile(&v, 0.95) * 1e3
        },
        if ok { "exact" } else { "WRONG" }
    );
    Ok(())
}

/// The job's merged samples against the deltas (exact: counts are integers). When every
/// upload was acknowledged (`drained`), the film holds exactly the acknowledged deltas.
/// Otherwise the simulated workers were stopped with uploads in flight: the master may have
/// merged some whose acknowledgement never arrived, so the film must hold exactly the master's
/// merges of the equal-sized deltas, and at least every acknowledged one.
fn verify(merged: &MergeReport, stats: &Stats, drained: bool, per_delta: f64) -> bool {
    let acked_samples = stats.acked_samples();
    let acked = stats.acked.load(Ordering::Relaxed);
    let ok = if drained {
        merged.job_samples == acked_samples && merged.merges == acked
    } else {
        merged.job_samples == merged.merges as f64 * per_delta
            && merged.merges >= acked
            && merged.job_samples >= acked_samples
    };
    let unacked = merged.merges.saturating_sub(acked);
    println!(
        "check: job film holds {} samples, acknowledged deltas sum to {acked_samples}; master \
         merges {} (acknowledged {acked}{}) -> {}",
        merged.job_samples,
        merged.merges,
        if drained {
            String::new()
        } else {
            format!(", {unacked} merged with the ack still in flight when the workers stopped")
        },
        if ok {
            "exact, no double count"
        } else {
            "MISMATCH"
        }
    );
    ok
}
