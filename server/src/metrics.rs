//! Counters of the master and their Prometheus text exposition (`GET /metrics`).

use std::fmt::Write;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

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
}

fn add_f64(a: &AtomicU64, v: f64) {
    let _ = a.fetch_update(Ordering::Relaxed, Ordering::Relaxed, |bits| {
        Some((f64::from_bits(bits) + v).to_bits())
    });
}

impl Metrics {
    /// Records one merged delta.
    pub fn record_merge(&self, bytes: u64, samples: f64, took: Duration) {
        self.merges.fetch_add(1, Ordering::Relaxed);
        self.upload_bytes.fetch_add(bytes, Ordering::Relaxed);
        add_f64(&self.merged_samples_bits, samples);
        add_f64(&self.merge_seconds_bits, took.as_secs_f64());
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
            (
                "luxfarm_merge_seconds_total",
                "Time spent decoding and merging deltas (divide by merges for the mean latency).",
                f64::from_bits(self.merge_seconds_bits.load(Ordering::Relaxed)),
            ),
        ];
        for (name, help, v) in counters {
            metric(name, "counter", help, vec![format!("{name} {v}")]);
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exposition_lists_counters() {
        let m = Metrics::default();
        m.record_merge(100, 64.0, Duration::from_millis(5));
        let text = m.render(&[("queued", 1)], 2, 1);
        assert!(text.contains("luxfarm_merges_total 1"));
        assert!(text.contains("luxfarm_merged_samples_total 64"));
        assert!(text.contains("luxfarm_jobs{state=\"queued\"} 1"));
        assert!(text.contains("luxfarm_workers{state=\"alive\"} 1"));
    }
}
