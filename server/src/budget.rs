//! Sample budgets: how a job's haltspp is shared out among its leases so that it ends within
//! one pass per worker of haltspp, whatever the upload interval.
//!
//! A job with haltspp has a target of `haltspp x pixels` samples, the pixels of the sample
//! extent (which a pass samples, `luxfarm::render::extent`). Each lease holds a budget
//! (the samples it may render in all); a worker renders a pass only while it has rendered
//! less than its budget, so it ends at most one pass beyond it, and uploads at once when its
//! budget is spent. Budgets are handed out from the pool the leases have not claimed:
//!
//! ```text
//! claimed = samples merged into the job's film + what active leases may still render
//!           (their budget minus what they delivered)
//! pool    = target - claimed
//! ```
//!
//! A lease asks (at assignment, in heartbeats and with each acknowledgement) and gets more
//! when it has less than two passes left: half the pool shared among the active leases, at
//! least one pass, at most the pool. A lease that ends gives back what it did not deliver.
//! Total merged samples therefore stay below `target + one pass per worker`, and the pool is
//! empty only once the leases hold it all.

use crate::farm::{lock, JobRt, LeaseRt};
use std::collections::HashMap;

/// The job's sample target (None: no haltspp, leases are unbounded).
pub fn target(haltspp: Option<f64>, pixels: u64) -> Option<f64> {
    haltspp.map(|spp| (spp * pixels as f64).ceil())
}

/// What active leases may still render beyond what they delivered.
fn outstanding(leases: &HashMap<String, LeaseRt>) -> f64 {
    leases
        .values()
        .filter(|l| !l.ended)
        .map(|l| (l.budget.unwrap_or(0.0) - l.samples).max(0.0))
        .sum()
}

/// Grows lease `id`'s budget when it has less than two passes left and the pool allows;
/// returns its budget (None: unbounded). `merged` is the job's merged samples.
pub fn grant(
    leases: &mut HashMap<String, LeaseRt>,
    id: &str,
    target: Option<f64>,
    merged: f64,
    pass_estimate: f64,
) -> Option<f64> {
    let target = target?;
    let pool = (target - merged - outstanding(leases)).max(0.0);
    let active = leases.values().filter(|l| !l.ended).count().max(1) as f64;
    let l = leases.get_mut(id)?;
    if l.ended {
        return l.budget;
    }
    let pass = if l.pass_samples > 0.0 {
        l.pass_samples
    } else {
        pass_estimate
    }
    .max(1.0);
    let current = l.budget.unwrap_or(0.0);
    let left = current - l.rendered.max(l.samples);
    if left >= 2.0 * pass || pool <= 0.0 {
        l.budget = Some(current);
        return l.budget;
    }
    let share = (pool / (2.0 * active)).ceil();
    let more = share.max(pass).min(pool);
    l.budget = Some(current + more);
    l.budget
}

/// Grants on the job's runtime state (locks its film, then its leases).
pub fn grant_for(rt: &JobRt, id: &str, target: Option<f64>) -> Option<f64> {
    let merged = lock(&rt.film).total_samples();
    let pass_estimate = rt.info.pass_pixels as f64;
    let mut leases = lock(&rt.leases);
    grant(&mut leases, id, target, merged, pass_estimate)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lease(budget: Option<f64>) -> LeaseRt {
        LeaseRt::new(budget)
    }

    #[test]
    fn no_haltspp_no_bound() {
        let mut m = HashMap::from([("a".to_string(), lease(None))]);
        assert_eq!(grant(&mut m, "a", None, 0.0, 10.0), None);
    }

    #[test]
    fn budgets_never_claim_more_than_the_target() {
        // target 1000 samples, passes of 10: two leases asking in turn, rendering what they
        // are given, until the pool is empty.
        let target = Some(1000.0);
        let mut m = HashMap::from([
            ("a".to_string(), lease(None)),
            ("b".to_string(), lease(None)),
        ]);
        let mut merged = 0.0;
        for _ in 0..200 {
            for id in ["a", "b"] {
                let b = grant(&mut m, id, target, merged, 10.0).unwrap();
                let l = m.get_mut(id).unwrap();
                l.pass_samples = 10.0;
                // Render passes while below the budget, deliver them.
                while l.rendered < b {
                    l.rendered += 10.0;
                }
                merged += l.rendered - l.samples;
                l.samples = l.rendered;
            }
        }
        assert!(merged >= 1000.0, "{merged}");
        assert!(merged <= 1000.0 + 2.0 * 10.0, "{merged}");
        // Both leases got a share.
        assert!(m["a"].samples > 0.0 && m["b"].samples > 0.0, "{m:?}");
    }

    #[test]
    fn an_ended_lease_gives_back_what_it_did_not_deliver() {
        let target = Some(100.0);
        let mut m = HashMap::from([
            ("a".to_string(), lease(None)),
            ("b".to_string(), lease(None)),
        ]);
        let a = grant(&mut m, "a", target, 0.0, 10.0).unwrap();
        assert!(a > 0.0 && a <= 100.0);
        // b takes the rest.
        for _ in 0..20 {
            grant(&mut m, "b", target, 0.0, 10.0);
        }
        let claimed = m["a"].budget.unwrap() + m["b"].budget.unwrap();
        assert!(claimed <= 100.0, "{claimed}");
        // a is lost after delivering 10 samples: its unrendered budget returns to the pool.
        let l = m.get_mut("a").unwrap();
        l.samples = 10.0;
        l.ended = true;
        let rendered_b = m["b"].budget.unwrap();
        m.get_mut("b").unwrap().rendered = rendered_b;
        let b = grant(&mut m, "b", target, 10.0, 10.0).unwrap();
        assert!(b > rendered_b, "{b} {rendered_b}");
        assert!(b + 10.0 <= 100.0 + 1e-9, "{b}");
    }
}
