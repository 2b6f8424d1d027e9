//! The state a lease's render thread, uploader and heartbeat task share: stop, the samples
//! rendered and the budget, the durable sequence number, the session's flags and the newest
//! sampling map. What the master says (in acknowledgements and heartbeats) lands here;
//! [`crate::job`] and [`crate::upload`] read and update it.
//!
//! A pass can be interrupted in two ways (`luxfarm::render::stops`), and the lease uses both:
//!
//! ```text
//! stop (master, shutdown) --pixel sampler--> cancel flag: the tile pass is dropped (it
//!                                            counts only whole); the last delta holds the
//!                                            passes before it
//!                         --chain sampler--> wrap-up flag: the pass ends at its next batch
//!                                            and is kept: the last delta carries it
//! uploader asks for a delta (every upload interval) --> wrap-up flag, then `want`: a
//!   metropolis or erpt pass of minutes ends at its next batch, so the render thread hands
//!   it over in time; the render thread lowers the flag again once it took the delta
//! ```

use crate::map::MapSlot;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;

/// State shared by the render thread, the uploader and the heartbeat task.
pub(crate) struct Flags {
    /// The master asked the lease to stop (or shutdown): render no more, send the last delta.
    pub(crate) stop: AtomicBool,
    /// The uploader wants the next delta ([`Flags::ask_for_delta`], [`Flags::take_want`]).
    want: AtomicBool,
    /// Samples rendered so far, and per pass (f64 bits).
    pub(crate) samples: AtomicU64,
    pub(crate) pass_samples: AtomicU64,
    /// Samples the lease may render (f64 bits; +inf: unbounded).
    pub(crate) budget: AtomicU64,
    /// Highest sequence number the master holds durably.
    pub(crate) durable: AtomicU64,
    /// The render thread needs more budget: heartbeat now.
    pub(crate) ask: tokio::sync::Notify,
    /// The session's flags, once it exists ([`Flags::attach`]).
    session: std::sync::Mutex<Option<SessionFlags>>,
    /// The newest sampling map from the master, until the render thread takes it.
    pub(crate) map: MapSlot,
    /// The lease's upload interval in seconds: a sweep of pixel-sampler passes is kept
    /// within it, so the render thread hands over a delta when the uploader asks (a chain
    /// pass is wrapped up by the ask instead; a stop needs no such bound: it cancels a tile
    /// pass or wraps up a chain pass).
    pub(crate) upload_secs: f64,
}

/// The flags of the lease's render session that the other tasks raise.
pub(crate) struct SessionFlags {
    /// Raised on stop: the cancel flag of a pixel sampler's session, the wrap-up flag of a
    /// chain sampler's.
    on_stop: Arc<AtomicBool>,
    /// The session's wrap-up flag: raised when the uploader asks for a delta.
    wrap_up: Arc<AtomicBool>,
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
            session: std::sync::Mutex::new(None),
            map: MapSlot::default(),
            upload_secs,
        }
    }

    /// Takes the session's flags: `cancel` and `wrap_up` (`Session::cancel_flag`,
    /// `Session::wrap_up_flag`); `chains` says whether its passes run Markov chains, whose
    /// work a stop keeps. A stop already requested applies at once.
    pub(crate) fn attach(&self, cancel: Arc<AtomicBool>, wrap_up: Arc<AtomicBool>, chains: bool) {
        let on_stop = if chains { wrap_up.clone() } else { cancel };
        *self.session_flags() = Some(SessionFlags { on_stop, wrap_up });
        if self.stop.load(Ordering::SeqCst) {
            self.raise_on_stop();
        }
    }

    fn session_flags(&self) -> std::sync::MutexGuard<'_, Option<SessionFlags>> {
        self.session.lock().unwrap_or_else(|p| p.into_inner())
    }

    fn raise_on_stop(&self) {
        if let Some(f) = self.session_flags().as_ref() {
            f.on_stop.store(true, Ordering::SeqCst);
        }
    }

    /// Stops the lease: no more passes, the current one cancelled (tiles) or wrapped up
    /// (chains). True the first time.
    pub(crate) fn request_stop(&self) -> bool {
        let first = !self.stop.swap(true, Ordering::SeqCst);
        self.raise_on_stop();
        first
    }

    /// The uploader asks for the next delta: the current chain pass is wrapped up (its
    /// flag raised before `want`, so the render thread that sees `want` lowers it after).
    pub(crate) fn ask_for_delta(&self) {
        if let Some(f) = self.session_flags().as_ref() {
            f.wrap_up.store(true, Ordering::SeqCst);
        }
        self.want.store(true, Ordering::SeqCst);
    }

    /// Whether the uploader asked for a delta (once per ask). The render thread then lowers
    /// the wrap-up flag, so its next chain passes run whole again, unless the lease stops
    /// (a stop raised meanwhile raises it again).
    pub(crate) fn take_want(&self) -> bool {
        if !self.want.swap(false, Ordering::SeqCst) {
            return false;
        }
        if let Some(f) = self.session_flags().as_ref() {
            f.wrap_up.store(false, Ordering::SeqCst);
        }
        if self.stop.load(Ordering::SeqCst) {
            self.raise_on_stop();
        }
        true
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

    fn session_flags(f: &Flags, chains: bool) -> (Arc<AtomicBool>, Arc<AtomicBool>) {
        let (cancel, wrap) = (Arc::default(), Arc::<AtomicBool>::default());
        f.attach(Arc::clone(&cancel), Arc::clone(&wrap), chains);
        (cancel, wrap)
    }

    fn up(b: &AtomicBool) -> bool {
        b.load(Ordering::SeqCst)
    }

    /// A stop cancels a tile pass (it counts only whole) but wraps up a chain pass (kept for
    /// the last delta); a stop before the session exists applies when it is attached.
    #[test]
    fn a_stop_cancels_tiles_and_wraps_up_chains() {
        let f = Flags::new(None, 1.0);
        let (cancel, wrap) = session_flags(&f, false);
        f.request_stop();
        assert!(up(&cancel) && !up(&wrap));
        let f = Flags::new(None, 1.0);
        let (cancel, wrap) = session_flags(&f, true);
        f.request_stop();
        assert!(!up(&cancel) && up(&wrap));
        let f = Flags::new(None, 1.0);
        f.request_stop();
        let (cancel, wrap) = session_flags(&f, true);
        assert!(!up(&cancel) && up(&wrap));
    }

    /// The uploader's ask wraps up the current chain pass; the render thread taking the ask
    /// lowers the flag again (the next passes run whole), unless the lease is stopping.
    #[test]
    fn an_ask_for_a_delta_wraps_up_the_pass_until_taken() {
        let f = Flags::new(None, 1.0);
        let (cancel, wrap) = session_flags(&f, true);
        assert!(!f.take_want());
        f.ask_for_delta();
        assert!(up(&wrap) && !up(&cancel));
        assert!(f.take_want());
        assert!(!up(&wrap) && !f.take_want());
        f.ask_for_delta();
        f.request_stop();
        assert!(f.take_want());
        assert!(up(&wrap), "a stop keeps the pass wrapped up");
        assert!(!up(&cancel));
    }
}
