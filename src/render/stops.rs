//! How a pass may end before its planned work, in two ways:
//!
//! - **cancel** ([`super::Session::cancel_flag`]): the pass stops between tiles (pixel
//!   samplers) or batches (chain samplers) and its work is discarded: for a render whose
//!   result nobody wants any more.
//! - **wrap-up** ([`super::Session::wrap_up_flag`], [`super::Session::set_deadline`]): a pass
//!   of the chain samplers (metropolis, erpt), which can last minutes on a big film, ends at
//!   its next batch boundary — after at least one batch — and keeps its work: every chain's
//!   pending weight is deposited as at a pass's planned end, and the pass counts the samples
//!   it actually took, so the shortened pass is a complete estimate of the image on its own.
//!   Pixel-sampler passes ignore it: a tile pass counts only whole (each pixel's sample
//!   indices are planned per pass), and the callers bound their sweeps by time already
//!   ([`super::Session::passes_within`]).
//!
//! Without a wrap-up the chains' films depend only on (seed, stream, pass); a pass ended by a
//! deadline or a wrap-up flag ends where the clock or another thread says, so its film
//! depends on timing (it is still a correct estimate, as any number of steps is).

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// What may end a pass early: the cancel flag, the wrap-up flag and the deadline.
#[derive(Clone, Copy, Debug)]
pub struct Stops<'a> {
    pub cancel: &'a AtomicBool,
    pub wrap_up: &'a AtomicBool,
    pub deadline: Option<Instant>,
}

impl Stops<'_> {
    /// Whether the pass is cancelled (its work to be discarded).
    pub fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }

    /// Whether a chain pass should end at this batch boundary, keeping its work: the wrap-up
    /// flag is set or the deadline has come.
    pub fn wrap_up_due(&self) -> bool {
        self.wrap_up.load(Ordering::Relaxed) || self.deadline.is_some_and(|d| Instant::now() >= d)
    }
}

/// What a chain pass (metropolis or erpt) did, when it was not cancelled.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ChainPass {
    /// Contributions discarded as NaN/Inf/negative.
    pub invalid: u64,
    /// The samples the pass took, which its film's deposits are an estimate over: the planned
    /// ones, or fewer when it was wrapped up.
    pub samples: u64,
    /// Whether the pass was wrapped up before its planned end.
    pub wrapped_up: bool,
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn a_wrap_up_is_due_on_the_flag_or_at_the_deadline() {
        let (cancel, wrap) = (AtomicBool::new(false), AtomicBool::new(false));
        let mut s = Stops {
            cancel: &cancel,
            wrap_up: &wrap,
            deadline: None,
        };
        assert!(!s.wrap_up_due() && !s.cancelled());
        s.deadline = Some(Instant::now() + Duration::from_secs(3600));
        assert!(!s.wrap_up_due());
        s.deadline = Some(Instant::now());
        assert!(s.wrap_up_due());
        s.deadline = None;
        wrap.store(true, Ordering::Relaxed);
        assert!(s.wrap_up_due() && !s.cancelled());
        cancel.store(true, Ordering::Relaxed);
        assert!(s.cancelled());
    }
}
