//! Counters of the master and their Prometheus text exposition (`GET /metrics`), with the
//! merge latency as a histogram (`luxfarm_merge_seconds_bucket{le=...}`, `_sum`, `_count`).

use std::collections::VecDeque;
use std::fmt::Write;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::Duration;

/// Upper bounds (seconds) of the merge latency histogram buckets (+Inf is implied).
pub const MERGE_BUCKETS: [f64; 14] = [
    0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1.0, 2.5, 5.0, 10.0, 30.0,
];
/// How many recent merge timings are kept for benchmarks.
const RECENT: usize = 1 << 16;

/// Timing of one merged upload, from the moment its bytes were all received.
#[derive(Clone, Copy, Debug, Default)]
pub struct MergeTiming {
    /// Decoding the delta.
    pub decode: Duration,
    /// Waiting for the job's film and adding the delta to it (with the ledger row).
    pub merge: Duration,
    /// Everything until the acknowledgement (lookups, decode, merge, halt checks).
    pub total: Duration,
}

/// What the master has merged, read by the capacity benchmark (`luxfarm bench master`) after
/// its load window.
#[derive(Clone, Debug, Default)]
pub struct MergeReport {
    /// Samples in the job's merged film.
    pub job_samples: f64,
    /// Deltas merged since the master started (all jobs).
    pub merges: u64,
    /// Timings of the most recent merges (up to 65536), oldest first.
    pub recent: Vec<MergeTiming>,
    /// Workers that are marked lost (timed out).
    pub lost_workers: usize,
}

/// Monotonic counters (atomics; samples and seconds kept as f64 bits).
#[derive(Default)]
pub struct Metrics {
    pub jobs_submitted: AtomicU64,
    pub jobs_finished: AtomicU64,
    pub merges: AtomicU64,
    pub duplicates: AtomicU64,
    pub upload_bytes: AtomicU64,
    merged_samples_bits: AtomicU64,
    merge_seconds_bits: AtomicU64,
    /// Non-cumulative bucket counts of merge latency; the last one is +Inf.
    merge_buckets: [AtomicU64; MERGE_BUCKETS.len() + 1],
    recent: Mutex<VecDeque<MergeTiming>>,
}

fn add_f64(a: &AtomicU64, v: f64) {
    let _ = a.fetch_update(Ordering::Relaxed, Ordering::Relaxed, |bits| {
        Some((f64::from_bits(bits) + v).to_bits())
    });
}

impl Metrics {
    /// Records one merged delta.
    pub fn record_merge(&self, bytes: u64, samples: f64, t: MergeTiming) {
        let secs = t.total.as_secs_f64();
        self.merges.fetch_add(1, Ordering::Relaxed);
        self.upload_bytes.fetch_add(bytes, Ordering::Relaxed);
        add_f64(&self.merged_samples_bits, samples);
        add_f64(&self.merge_seconds_bits, secs);
        let i = MERGE_BUCKETS
            .iter()
            .position(|&le| secs <= le)
            .unwrap_or(MERGE_BUCKETS.len());
        if let Some(b) = self.merge_buckets.get(i) {
            b.fetch_add(1, Ordering::Relaxed);
        }
        let mut recent = self.recent.lock().unwrap_or_else(|p| p.into_inner());
        if recent.len() == RECENT {
            recent.pop_front();
        }
        recent.push_back(t);
    }

    /// The timings of the most recent merges (up to 65536), oldest first.
    pub fn recent_merges(&self) -> Vec<MergeTiming> {
        let recent = self.recent.lock().unwrap_or_else(|p| p.into_inner());
        recent.iter().copied().collect()
    }

    /// The merge latency histogram in Prometheus text format.
    fn merge_histogram(&self) -> Vec<String> {
        let name = "luxfarm_merge_seconds";
        let mut lines = Vec::with_capacity(MERGE_BUCKETS.len() + 3);
        let mut cumulative = 0u64;
        for (le, b) in MERGE_BUCKETS.iter().zip(&self.merge_buckets) {
            cumulative += b.load(Ordering::Relaxed);
            lines.push(format!("{name}_bucket{{le=\"{le}\"}} {cumulative}"));
        }
        if let Some(inf) = self.merge_buckets.last() {
            cumulative += inf.load(Ordering::Relaxed);
        }
        lines.push(format!("{name}_bucket{{le=\"+Inf\"}} {cumulative}"));
        let sum = f64::from_bits(self.merge_seconds_bits.load(Ordering::Relaxed));
        lines.push(format!("{name}_sum {sum}"));
        lines.push(format!("{name}_count {cumulative}"));
        lines
    }

    /// Total merged samples.
    pub fn merged_samples(&self) -> f64 {
        f64::from_bits(self.merged_samples_bits.load(Ordering::Relaxed))
    }

    /// Prometheus text format, with the gauges the caller computed (jobs by state, workers).
    pub fn render(&self, jobs_by_state: &[(&str, usize)], workers: usize, lost: usize) -> String {
        let mut s = String::new();
        let mut metric = |name: &str, kind: &str, help: &str, lines: Vec<String>| {
            let _ = writeln!(s, "# HELP {name} {help}\n# TYPE {name} {kind}");
            for l in lines {
                let _ = writeln!(s, "{l}");
            }
        };
        metric(
            "luxfarm_jobs",
            "gauge",
            "Jobs by state.",
            jobs_by_state
                .iter()
                .map(|(st, n)| format!("luxfarm_jobs{{state=\"{st}\"}} {n}"))
                .collect(),
        );
        metric(
            "luxfarm_workers",
            "gauge",
            "Known workers by state.",
            vec![
                format!("luxfarm_workers{{state=\"alive\"}} {}", workers - lost),
                format!("luxfarm_workers{{state=\"lost\"}} {lost}"),
            ],
        );
        let counters = [
            (
                "luxfarm_jobs_submitted_total",
                "Jobs submitted.",
                self.jobs_submitted.load(Ordering::Relaxed) as f64,
            ),
            (
                "luxfarm_jobs_finished_total",
                "Jobs that reached a final state.",
                self.jobs_finished.load(Ordering::Relaxed) as f64,
            ),
            (
                "luxfarm_merges_total",
                "Film deltas merged.",
                self.merges.load(Ordering::Relaxed) as f64,
            ),
            (
                "luxfarm_duplicate_uploads_total",
                "Replayed uploads ignored.",
                self.duplicates.load(Ordering::Relaxed) as f64,
            ),
            (
                "luxfarm_upload_bytes_total",
                "Bytes of merged film deltas.",
                self.upload_bytes.load(Ordering::Relaxed) as f64,
            ),
            (
                "luxfarm_merged_samples_total",
                "Samples merged (rate() gives merged samples/s).",
                self.merged_samples(),
            ),
        ];
        for (name, help, v) in counters {
            metric(name, "counter", help, vec![format!("{name} {v}")]);
        }
        metric(
            "luxfarm_merge_seconds",
            "histogram",
            "Latency of a delta upload once received: decode, merge into the job film, ledger.",
            self.merge_histogram(),
        );
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exposition_lists_counters() {
        let m = Metrics::default();
        let t = |ms| MergeTiming {
            total: Duration::from_millis(ms),
            ..MergeTiming::default()
        };
        m.record_merge(100, 64.0, t(5));
        m.record_merge(100, 64.0, t(40_000));
        let text = m.render(&[("queued", 1)], 2, 1);
        assert!(text.contains("# TYPE luxfarm_merge_seconds histogram"));
        assert!(text.contains("luxfarm_merge_seconds_bucket{le=\"0.001\"} 0"));
        assert!(text.contains("luxfarm_merge_seconds_bucket{le=\"0.005\"} 1"));
        assert!(text.contains("luxfarm_merge_seconds_bucket{le=\"30\"} 1"));
        assert!(text.contains("luxfarm_merge_seconds_bucket{le=\"+Inf\"} 2"));
        assert!(text.contains("luxfarm_merge_seconds_count 2"));
        assert!(text.contains("luxfarm_merge_seconds_sum 40.005"));
        assert_eq!(m.recent_merges().len(), 2);
        assert!(text.contains("luxfarm_merges_total 2"));
        assert!(text.contains("luxfarm_merged_samples_total 128"));
        assert!(text.contains("luxfarm_jobs{state=\"queued\"} 1"));
        assert!(text.contains("luxfarm_workers{state=\"alive\"} 1"));
    }
}
