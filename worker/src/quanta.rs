//! The erpt sampler's energy quanta of the jobs this worker has rendered, so a job's later
//! leases skip the warm-up (`initsamples` samples, 100,000 by default) its first lease paid.
//!
//! The quantum depends only on the scene and the job's seed, never on the lease's stream
//! (`luxfarm::sampler::erpt::warm_up_key`), so a lease handed a remembered quantum renders
//! the same film as with a warm-up of its own. Keys are the bundle's content hash, the scene
//! path inside it, the animation frame and the seed; the memo keeps the newest [`KEPT`].

use std::collections::VecDeque;
use std::sync::Mutex;

/// Quanta remembered at most (the oldest is forgotten first).
pub const KEPT: usize = 64;

/// What a quantum is remembered under.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Key {
    pub bundle_hash: String,
    pub scene_path: String,
    pub frame: Option<i64>,
    pub seed: u64,
}

/// The remembered quanta, newest last.
#[derive(Default)]
pub struct Quanta {
    known: Mutex<VecDeque<(Key, f64)>>,
}

impl Quanta {
    /// The quantum remembered for `key`.
    pub fn get(&self, key: &Key) -> Option<f64> {
        let known = self.known.lock().unwrap_or_else(|p| p.into_inner());
        known.iter().find(|(k, _)| k == key).map(|(_, q)| *q)
    }

    /// Remembers `q` for `key` (a quantum not positive and finite is not kept).
    pub fn put(&self, key: Key, q: f64) {
        if !(q > 0.0 && q.is_finite()) {
            return;
        }
        let mut known = self.known.lock().unwrap_or_else(|p| p.into_inner());
        known.retain(|(k, _)| *k != key);
        known.push_back((key, q));
        while known.len() > KEPT {
            known.pop_front();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(seed: u64) -> Key {
        Key {
            bundle_hash: "ab".into(),
            scene_path: "s.lxs".into(),
            frame: None,
            seed,
        }
    }

    #[test]
    fn remembers_the_newest_and_forgets_the_oldest() {
        let q = Quanta::default();
        assert_eq!(q.get(&key(1)), None);
        q.put(key(1), 2.0);
        q.put(key(1), 3.0);
        assert_eq!(q.get(&key(1)), Some(3.0));
        q.put(key(2), f64::NAN);
        q.put(key(2), 0.0);
        assert_eq!(q.get(&key(2)), None);
        let other_frame = Key {
            frame: Some(4),
            ..key(1)
        };
        assert_eq!(q.get(&other_frame), None);
        for s in 10..10 + KEPT as u64 {
            q.put(key(s), 1.0);
        }
        assert_eq!(q.get(&key(1)), None, "the oldest is forgotten");
        assert_eq!(q.get(&key(10 + KEPT as u64 - 1)), Some(1.0));
    }
}
