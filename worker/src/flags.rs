//! The state a lease's render thread, uploader and heartbeat task share: stop, the samples
//! rendered and the budget, the durable sequence number, the session's cancel flag and the
//! newest sampling map. What the master says (in acknowledgements and heartbeats) lands
//! here; [`crate::job`] and [`crate::upload`] read and update it.

use crate::map::MapSlot;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;

/// State shared by the render thread, the uploader and the heartbeat task.
pub(crate) struct Flags {
    /// The master asked the lease to stop (or shutdown): render no more, send the last delta.
    pub(crate) stop: AtomicBool,
    /// The uploader wants the next delta.
    pub(crate) want: AtomicBool,
    /// Samples rendered so far, and per pass (f64 bits).
    pub(crate) samples: AtomicU64,
    pub(crate) pass_samples: AtomicU64,
    /// Samples the lease may render (f64 bits; +inf: unbounded).
    pub(crate) budget: AtomicU64,
    /// Highest sequence number the master holds durably.
    pub(crate) durable: AtomicU64,
    /// The render thread needs more budget: heartbeat now.
    pub(crate) ask: tokio::sync::Notify,
    /// The session's cancel flag: set on stop so a long pass ends between tiles.
    pub(crate) cancel: std::sync::Mutex<Option<Arc<AtomicBool>>>,
    /// The newest sampling map from the master, until the render thread takes it.
    pub(crate) map: MapSlot,
    /// The lease's upload interval in seconds: a sweep of passes is kept within it, so the
    /// render thread hands over a delta when the uploader asks (a stop needs no such bound:
    /// it sets the session's cancel flag, which ends a sweep between tiles).
    pub(crate) upload_secs: f64,
}

pub(crate) fn load_f64(a: &AtomicU64) -> f64 {
    f64::from_bits(a.load(Ordering::Relaxed))
}

pub(crate) fn store_f64(a: &AtomicU64, v: f64) {
    a.store(v.to_bits(), Ordering::Relaxed);
}

impl Flags {
    pub(crate) fn new(budget: Option<f64>, upload_secs: f64) -> Flags {
        Flags {
            stop: AtomicBool::new(false),
            want: AtomicBool::new(false),
            samples: AtomicU64::new(0f64.to_bits()),
            pass_samples: AtomicU64::new(0f64.to_bits()),
            budget: AtomicU64::new(budget.unwrap_or(f64::INFINITY).to_bits()),
            durable: AtomicU64::new(0),
            ask: tokio::sync::Notify::new(),
            cancel: std::sync::Mutex::new(None),
            map: MapSlot::default(),
            upload_secs,
        }
    }

    /// Stops the lease: no more passes, the current one interrupted. True the first time.
    pub(crate) fn request_stop(&self) -> bool {
        let first = !self.stop.swap(true, Ordering::SeqCst);
        if let Some(c) = self
            .cancel
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .as_ref()
        {
            c.store(true, Ordering::SeqCst);
        }
        first
    }

    /// Applies what the master said about the lease.
    pub(crate) fn apply(&self, stop: bool, budget: Option<f64>, durable: u64) {
        store_f64(&self.budget, budget.unwrap_or(f64::INFINITY));
        self.durable.fetch_max(durable, Ordering::SeqCst);
        if stop && self.request_stop() {
            tracing::info!("master asked to stop");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budget_defaults_to_unbounded() {
        let f = Flags::new(None, 1.0);
        assert!(load_f64(&f.budget).is_infinite());
        f.apply(false, Some(100.0), 3);
        assert_eq!(load_f64(&f.budget), 100.0);
        assert_eq!(f.durable.load(Ordering::SeqCst), 3);
        f.apply(false, Some(200.0), 1);
        assert_eq!(f.durable.load(Ordering::SeqCst), 3);
        assert!(!f.stop.load(Ordering::SeqCst));
        f.apply(true, None, 0);
        assert!(f.stop.load(Ordering::SeqCst));
    }
}
