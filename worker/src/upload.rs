//! The uploads of one lease: the deltas the render thread hands over, sent in sequence order
//! with retries and backoff, then kept once acknowledged until the master holds them
//! durably (and sent again if it restarted before). `--keep-deltas` saves a copy of each.
//! [`crate::job`] runs this loop beside the render thread.

use crate::flags::{load_f64, Flags};
use crate::link::{backoff, Link};
use crate::Config;
use luxfarm::atomic_write::write_bytes_atomic;
use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};
use tonic::Code;

/// Acknowledged deltas kept at most while waiting for the master to make them durable (it
/// checkpoints every few uploads; more means its checkpoints fail).
const MAX_RETAINED: usize = 64;

/// How long a lease waits, after its last delta, for the master to make it durable.
const DURABLE_WAIT: Duration = Duration::from_secs(600);

/// A delta ready to upload.
pub(crate) struct Delta {
    pub(crate) bytes: Vec<u8>,
    pub(crate) last: bool,
}

/// The deltas of one lease on their way to durability.
struct Queues {
    /// Not yet acknowledged, in sequence order.
    pending: VecDeque<(u64, Delta)>,
    /// Acknowledged, not yet durable, in sequence order.
    retained: VecDeque<(u64, Delta)>,
    /// The master instance the retained deltas were acknowledged by.
    instance: String,
}

impl Queues {
    /// Drops what the master holds durably; after a master restart, puts what it had not
    /// made durable back in front of the pending deltas.
    fn update(&mut self, durable: u64, instance: &str) {
        while self.retained.front().is_some_and(|(s, _)| *s <= durable) {
            self.retained.pop_front();
        }
        if !instance.is_empty() && instance != self.instance {
            if !self.instance.is_empty() && !self.retained.is_empty() {
                tracing::info!(
                    deltas = self.retained.len(),
                    "the master restarted: uploading again what it had not made durable"
                );
            }
            while let Some(d) = self.retained.pop_back() {
                self.pending.push_front(d);
            }
            self.instance = instance.to_string();
        }
    }

    /// Moves the front pending delta to the retained ones (it was acknowledged).
    fn acknowledged(&mut self) {
        if let Some(d) = self.pending.pop_front() {
            self.retained.push_back(d);
        }
        if self.retained.len() > MAX_RETAINED {
            if let Some((seq, _)) = self.retained.pop_front() {
                tracing::error!(
                    seq,
                    "the master makes no delta durable: forgetting the oldest"
                );
            }
        }
    }
}

/// Asks for deltas every interval, uploads them in order, retries with backoff, keeps the
/// acknowledged ones until they are durable.
pub(crate) async fn upload_loop(
    link: &Link,
    cfg: &Config,
    lease: &str,
    interval: Duration,
    flags: &Flags,
    mut rx: tokio::sync::mpsc::Receiver<Delta>,
) -> anyhow::Result<()> {
    let mut q = Queues {
        pending: VecDeque::new(),
        retained: VecDeque::new(),
        instance: link.instance(),
    };
    let mut next_seq = 1u64;
    let mut last_take = Instant::now();
    let mut requested = false;
    let mut render_done = false;
    let mut attempt = 0u32;
    let mut retry_at = Instant::now();
    let mut done_since: Option<Instant> = None;
    let mut shutdown_since: Option<Instant> = None;
    loop {
        q.update(flags.durable.load(Ordering::SeqCst), &link.instance());
        if !requested && q.pending.is_empty() && last_take.elapsed() >= interval {
            flags.ask_for_delta();
            requested = true;
        }
        if !render_done {
            match tokio::time::timeout(Duration::from_millis(50), rx.recv()).await {
                Ok(Some(d)) => {
                    if let Some(dir) = &cfg.keep_deltas {
                        keep(dir, lease, next_seq, &d.bytes, SENT);
                    }
                    q.pending.push_back((next_seq, d));
                    next_seq += 1;
                    requested = false;
                    last_take = Instant::now();
                }
                Ok(None) => render_done = true,
                Err(_) => {}
            }
        } else if q.pending.is_empty() {
            if q.retained.is_empty() {
                return Ok(());
            }
            // The last delta is acknowledged: wait for the master to make it durable.
            let since = *done_since.get_or_insert_with(Instant::now);
            if since.elapsed() > DURABLE_WAIT {
                anyhow::bail!(
                    "the master did not make {} acknowledged delta(s) durable",
                    q.retained.len()
                );
            }
            flags.ask.notify_one();
            tokio::time::sleep(Duration::from_millis(100)).await;
        } else {
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
        if link.shutdown.load(Ordering::Relaxed) {
            let since = *shutdown_since.get_or_insert_with(Instant::now);
            if render_done && since.elapsed() > Duration::from_secs(30) {
                anyhow::bail!(
                    "shutting down: {} delta(s) not acknowledged, {} not yet durable",
                    q.pending.len(),
                    q.retained.len()
                );
            }
        }
        let Some((seq, delta)) = q.pending.front() else {
            continue;
        };
        if Instant::now() < retry_at {
            continue;
        }
        let seq = *seq;
        match link
            .upload(lease, seq, delta.last, &delta.bytes, flags.map.version())
            .await
        {
            Ok(mut ack) => {
                if let Some(m) = ack.sampling_map.take() {
                    flags.map.offer(m);
                }
                tracing::debug!(seq, status = %ack.status, bytes = delta.bytes.len(), "delta acknowledged");
                if let Some(dir) = &cfg.keep_deltas {
                    keep(dir, lease, seq, &delta.bytes, &ack.status);
                }
                q.acknowledged();
                attempt = 0;
                link.observe_instance(&ack.master_instance);
                flags.apply(ack.stop, ack.budget, ack.durable_seq);
            }
            Err(s) if s.code() == Code::Aborted => {
                // The master restarted: learn its instance, then upload again what it lost.
                tracing::info!(reason = %s.message(), "the master restarted");
                let (samples, pass) = (load_f64(&flags.samples), load_f64(&flags.pass_samples));
                if let Some(r) = link.heartbeat(lease, samples, pass).await {
                    link.observe_instance(&r.master_instance);
                    flags.apply(r.stop, r.budget, r.durable_seq);
                } else {
                    retry_at = Instant::now() + backoff(attempt);
                    attempt += 1;
                }
            }
            Err(s)
                if matches!(
                    s.code(),
                    Code::FailedPrecondition | Code::NotFound | Code::PermissionDenied
                ) =>
            {
                tracing::info!(reason = %s.message(), "lease over; dropping unsent deltas");
                flags.request_stop();
                q.pending.clear();
                while rx.recv().await.is_some() {}
                return Ok(());
            }
            Err(s) if matches!(s.code(), Code::InvalidArgument | Code::ResourceExhausted) => {
                tracing::error!(seq, reason = %s.message(), "delta refused by the master");
                q.pending.pop_front();
            }
            Err(s) => {
                tracing::warn!(seq, attempt, reason = %luxfarm_proto::connect::explain(&s),
                    "upload failed; will retry");
                retry_at = Instant::now() + backoff(attempt);
                attempt += 1;
            }
        }
    }
}

/// The status a kept delta has until the master acknowledges it.
const SENT: &str = "sent";

/// Saves a delta for audits (`--keep-deltas`) as `LEASE-SEQ.STATUS.lxd`, atomically (an
/// auditor reading the folder while the worker runs sees whole deltas only): with status
/// [`SENT`] when it is queued for upload, then with the master's acknowledgement status, which
/// replaces the sent copy. A worker killed between an acknowledgement and its record leaves
/// the sent copy: the folder always holds every delta the master may have merged.
fn keep(dir: &Path, lease: &str, seq: u64, bytes: &[u8], status: &str) {
    let name = |status: &str| -> PathBuf { dir.join(format!("{lease}-{seq:06}.{status}.lxd")) };
    let written = std::fs::create_dir_all(dir)
        .map_err(|e| e.to_string())
        .and_then(|_| write_bytes_atomic(&name(status), bytes).map_err(|e| e.to_string()));
    match written {
        Err(e) => tracing::warn!(error = %e, "could not keep delta"),
        Ok(()) if status != SENT => {
            let _ = std::fs::remove_file(name(SENT));
        }
        Ok(()) => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn delta(last: bool) -> Delta {
        Delta {
            bytes: vec![1, 2, 3],
            last,
        }
    }

    fn seqs(v: &VecDeque<(u64, Delta)>) -> Vec<u64> {
        v.iter().map(|(s, _)| *s).collect()
    }

    #[test]
    fn acknowledged_deltas_wait_for_durability_and_return_after_a_restart() {
        let mut q = Queues {
            pending: (1..=4).map(|s| (s, delta(false))).collect(),
            retained: VecDeque::new(),
            instance: "m1".into(),
        };
        q.acknowledged();
        q.acknowledged();
        q.acknowledged();
        assert_eq!(seqs(&q.retained), [1, 2, 3]);
        // The master made 1 durable.
        q.update(1, "m1");
        assert_eq!(seqs(&q.retained), [2, 3]);
        assert_eq!(seqs(&q.pending), [4]);
        // It restarted: 2 and 3 are uploaded again, before 4.
        q.update(1, "m2");
        assert_eq!(seqs(&q.pending), [2, 3, 4]);
        assert!(q.retained.is_empty());
        // The same instance again changes nothing.
        q.update(1, "m2");
        assert_eq!(seqs(&q.pending), [2, 3, 4]);
    }
}
