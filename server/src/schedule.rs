//! The scheduling order: which job a worker asking for work gets. Pure functions over job rows
//! and counts, so the order is tested without a farm; `lease::assign` walks the result and
//! leases the first job that is loaded and not halting.
//!
//! ```text
//! unfinished jobs (priority DESC, submission ASC) + worker (tags, memory) + open leases per
//!   job + sequence policies --order--> candidate jobs, best first
//! ```
//!
//! The order, as documented in the README:
//!
//! 1. A job the worker cannot take is left out: it asks for a tag the worker lacks, or the
//!    worker has tags and the job asks for none (tags are pools: a tagged worker serves only
//!    jobs asking for its tags, an untagged worker only jobs asking for none); it asks for
//!    more memory than the worker declared (a worker declaring none takes no job asking for
//!    memory); it already has `max_workers` open leases; or the worker is blocked from it.
//! 2. Higher priority first (0 to 100; 0 by default).
//! 3. Equal priority: submission order, older first. The frames of a sequence take the place
//!    of its first unfinished frame and are ordered by the sequence's policy: `earliest`
//!    piles workers on the first unfinished frame (frame order); `spread` gives the frame with
//!    the fewest open leases (ties in frame order), so workers spread over the frames.

use crate::db::JobRow;
use std::collections::{HashMap, HashSet};

/// How a sequence hands its frames to workers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Policy {
    /// Workers spread over the unfinished frames (fewest open leases first).
    #[default]
    Spread,
    /// Workers piled on the earliest unfinished frame (each frame finishes as soon as it can).
    Earliest,
}

impl Policy {
    /// Parses `spread` or `earliest`.
    pub fn parse(s: &str) -> Option<Policy> {
        match s.trim() {
            "spread" => Some(Policy::Spread),
            "earliest" => Some(Policy::Earliest),
            _ => None,
        }
    }

    pub fn as_str(self) -> &'static str {
        match self {
            Policy::Spread => "spread",
            Policy::Earliest => "earliest",
        }
    }
}

/// What the worker asking for work offers.
#[derive(Clone, Debug)]
pub struct Offer<'a> {
    pub tags: &'a [String],
    pub memory_mb: u64,
    /// Jobs the worker is blocked from.
    pub blocked: &'a HashSet<String>,
}

/// Whether the worker may take the job at all (rule 1).
pub fn can_take(job: &JobRow, offer: &Offer<'_>, open_leases: u32) -> bool {
    job.tags.iter().all(|t| offer.tags.contains(t))
        && job.tags.is_empty() == offer.tags.is_empty()
        && (job.min_memory_mb == 0 || offer.memory_mb >= job.min_memory_mb)
        && (job.max_workers == 0 || open_leases < job.max_workers)
        && !offer.blocked.contains(&job.id)
}

/// The candidate jobs for a worker, best first (see the module docs). `jobs` are the
/// unfinished jobs in priority then submission order; `open` counts open leases per job;
/// `policies` gives each sequence's policy (a sequence missing there spreads).
pub fn order<'j>(
    jobs: &'j [JobRow],
    offer: &Offer<'_>,
    open: &HashMap<String, u32>,
    policies: &HashMap<String, Policy>,
) -> Vec<&'j JobRow> {
    let leases = |j: &JobRow| open.get(&j.id).copied().unwrap_or(0);
    let mut out: Vec<&JobRow> = Vec::new();
    let mut placed: HashSet<(i32, &str)> = HashSet::new();
    for job in jobs {
        if !can_take(job, offer, leases(job)) {
            continue;
        }
        let Some(seq) = job.sequence_id.as_deref() else {
            out.push(job);
            continue;
        };
        // The first takeable frame of a sequence places all its frames of this priority.
        if !placed.insert((job.priority, seq)) {
            continue;
        }
        let mut frames: Vec<&JobRow> = jobs
            .iter()
            .filter(|f| f.sequence_id.as_deref() == Some(seq) && f.priority == job.priority)
            .filter(|f| can_take(f, offer, leases(f)))
            .collect();
        let policy = policies.get(seq).copied().unwrap_or_default();
        // Stable sorts keep submission order among equals.
        frames.sort_by_key(|f| f.sequence_frame.unwrap_or(i64::MAX));
        if policy == Policy::Spread {
            frames.sort_by_key(|f| leases(f));
        }
        out.extend(frames);
    }
    out
}

/// Queued demand: the worker leases the unfinished, not halting jobs could use now (each
/// job's `max_workers`, else `per_job`), summed. Zero when there is nothing to render, so an
/// autoscaler can scale workers to zero.
pub fn leases_wanted(jobs: &[JobRow], per_job: u32, halting: impl Fn(&str) -> bool) -> u64 {
    jobs.iter()
        .filter(|j| !j.state.is_final() && !halting(&j.id))
        .map(|j| {
            u64::from(if j.max_workers > 0 {
                j.max_workers
            } else {
                per_job
            })
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::db::JobState;

    fn job(id: &str, priority: i32) -> JobRow {
        JobRow {
            id: id.into(),
            name: id.into(),
            state: JobState::Queued,
            reason: String::new(),
            priority,
            bundle_hash: String::new(),
            scene_path: String::new(),
            seed: 0,
            haltspp: None,
            halttime: None,
            haltthreshold: None,
            width: 1,
            height: 1,
            submitted_ms: 0,
            first_lease_ms: None,
            finished_ms: None,
            ckpt_gen: 0,
            frame: None,
            owner: String::new(),
            notes: vec![],
            sequence_id: None,
            sequence_frame: None,
            tags: vec![],
            min_memory_mb: 0,
            max_workers: 0,
            webhook: String::new(),
        }
    }

    fn frame(id: &str, seq: &str, n: i64) -> JobRow {
        JobRow {
            sequence_id: Some(seq.into()),
            sequence_frame: Some(n),
            ..job(id, 0)
        }
    }

    fn ids(v: Vec<&JobRow>) -> Vec<&str> {
        v.into_iter().map(|j| j.id.as_str()).collect()
    }

    #[test]
    fn priority_then_submission() {
        let jobs = [job("hi", 90), job("a", 0), job("b", 0)];
        let none = HashSet::new();
        let offer = Offer {
            tags: &[],
            memory_mb: 0,
            blocked: &none,
        };
        let got = order(&jobs, &offer, &HashMap::new(), &HashMap::new());
        assert_eq!(ids(got), ["hi", "a", "b"]);
    }

    #[test]
    fn tags_memory_max_workers_and_blocks_filter() {
        let mut gpu = job("gpu", 50);
        gpu.tags = vec!["gpu".into()];
        let mut big = job("big", 40);
        big.min_memory_mb = 8000;
        let mut two = job("two", 30);
        two.max_workers = 2;
        let jobs = [gpu, big, two, job("plain", 0), job("blocked", 0)];
        let open = HashMap::from([("two".to_string(), 2)]);
        let blocked = HashSet::from(["blocked".to_string()]);
        let none: Vec<String> = vec![];
        let offer = Offer {
            tags: &none,
            memory_mb: 4000,
            blocked: &blocked,
        };
        assert_eq!(ids(order(&jobs, &offer, &open, &HashMap::new())), ["plain"]);
        let tags = vec!["gpu".to_string(), "x".to_string()];
        let offer = Offer {
            tags: &tags,
            memory_mb: 16000,
            blocked: &blocked,
        };
        // A tagged worker serves only the jobs asking for its tags.
        let got = order(&jobs, &offer, &HashMap::new(), &HashMap::new());
        assert_eq!(ids(got), ["gpu"]);
        let offer = Offer {
            tags: &none,
            memory_mb: 16000,
            blocked: &blocked,
        };
        let got = order(&jobs, &offer, &HashMap::new(), &HashMap::new());
        assert_eq!(ids(got), ["big", "two", "plain"]);
    }

    #[test]
    fn sequence_policies_spread_or_pile_on_the_earliest_frame() {
        let jobs = [
            job("before", 0),
            frame("f1", "s", 1),
            frame("f2", "s", 2),
            frame("f3", "s", 3),
            job("after", 0),
        ];
        let open = HashMap::from([("f1".to_string(), 2), ("f2".to_string(), 1)]);
        let none = HashSet::new();
        let offer = Offer {
            tags: &[],
            memory_mb: 0,
            blocked: &none,
        };
        let spread = HashMap::from([("s".to_string(), Policy::Spread)]);
        assert_eq!(
            ids(order(&jobs, &offer, &open, &spread)),
            ["before", "f3", "f2", "f1", "after"]
        );
        let earliest = HashMap::from([("s".to_string(), Policy::Earliest)]);
        assert_eq!(
            ids(order(&jobs, &offer, &open, &earliest)),
            ["before", "f1", "f2", "f3", "after"]
        );
    }

    #[test]
    fn demand_counts_unfinished_jobs_not_halting() {
        let mut capped = job("capped", 0);
        capped.max_workers = 2;
        let mut done = job("done", 0);
        done.state = JobState::Done;
        let jobs = [capped, done, job("open", 0), job("halting", 0)];
        assert_eq!(leases_wanted(&jobs, 8, |id| id == "halting"), 10);
        assert_eq!(leases_wanted(&[], 8, |_| false), 0);
    }

    #[test]
    fn policies_parse() {
        assert_eq!(Policy::parse("spread"), Some(Policy::Spread));
        assert_eq!(Policy::parse("earliest"), Some(Policy::Earliest));
        assert_eq!(Policy::parse("random"), None);
    }
}
