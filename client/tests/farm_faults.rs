//! Master faults during a two-worker render: the master is killed with SIGKILL at random
//! moments (at least five, loopback), restarted on the same address and data directory, then
//! stopped once with SIGTERM and restarted again. When the job ends, the film's samples must
//! be exactly those of every delta a worker was told was acknowledged (each (lease, sequence)
//! once, whether the answer was "merged" or "duplicate"), none lost and none twice.
//!
//! The random moments come from a seed printed with the test, so a failure can be replayed
//! with `LUXFARM_FAULT_SEED`. Deadlines below only guard against hangs.

mod farm_common;

use farm_common::*;
use luxfarm::film::Film;
use luxfarm_wire::codec;
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::time::Duration;

/// A small xorshift generator: the test needs a few random delays, not a crate.
struct Rng(u64);

impl Rng {
    fn from_env_or_clock() -> Rng {
        let seed = std::env::var("LUXFARM_FAULT_SEED")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| {
                std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map(|d| d.as_nanos() as u64)
                    .unwrap_or(1)
            })
            | 1;
        eprintln!("fault test seed: LUXFARM_FAULT_SEED={seed}");
        Rng(seed)
    }

    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// Milliseconds in `lo..hi`.
    fn millis(&mut self, lo: u64, hi: u64) -> Duration {
        Duration::from_millis(lo + self.next() % (hi - lo))
    }
}

/// Every acknowledged delta the workers kept, once per (lease, sequence): the file name is
/// `LEASE-SEQ.STATUS.lxd` (status `sent` until acknowledged: not counted), and a delta
/// acknowledged twice (the master lost it, or the worker lost the answer) was merged once.
fn acknowledged(dirs: &[&Path]) -> BTreeMap<String, Film> {
    let mut out = BTreeMap::new();
    for d in dirs {
        for p in files_under(d) {
            let name = p.file_name().unwrap().to_string_lossy().to_string();
            let Some(key) = name.split('.').next() else {
                continue;
            };
            if !name.ends_with(".lxd") || name.ends_with(".sent.lxd") {
                continue;
            }
            let f = codec::decode(&std::fs::read(&p).unwrap()).unwrap();
            out.entry(key.to_string()).or_insert(f);
        }
    }
    out
}

/// The (lease, sequence) keys of the deltas a worker kept.
fn keys(dir: &Path) -> BTreeSet<String> {
    files_under(dir)
        .iter()
        .filter(|p| {
            let name = p.to_string_lossy();
            name.ends_with(".lxd") && !name.ends_with(".sent.lxd")
        })
        .filter_map(|p| {
            Some(
                p.file_name()?
                    .to_string_lossy()
                    .split('.')
                    .next()?
                    .to_string(),
            )
        })
        .collect()
}

const ARGS: [&str; 6] = [
    "--upload-interval",
    "0.3",
    "--worker-timeout",
    "20",
    "--checkpoint-interval",
    "2",
];

#[test]
fn kill_9_and_sigterm_lose_no_acknowledged_sample() {
    let mut rng = Rng::from_env_or_clock();
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let mut s = server(&data, &ARGS);
    let addr = s.addr.clone();
    let scene = std::fs::read(small_scene(dir.path(), "f", (16, 12), "")).unwrap();
    let (st, job) = post_job(&s, scene, "?filename=f.lxs&haltspp=1000000");
    assert_eq!(st, 201, "{job}");
    let id = job["id"].as_str().unwrap().to_string();
    let k1 = dir.path().join("k1");
    let k2 = dir.path().join("k2");
    let mut workers = [
        worker(&s.url(), 1, &["--keep-deltas", k1.to_str().unwrap()]),
        worker(&s.url(), 1, &["--keep-deltas", k2.to_str().unwrap()]),
    ];
    let v = wait_job(&s, &id, 120, |v| {
        v["merged_deltas"].as_u64().unwrap_or(0) >= 2
    });
    assert_eq!(v["state"], "rendering", "{v}");
    // five kills at random moments, each after the farm rendered again
    for kill in 0..5 {
        let before = get_json(&s.api(&format!("/jobs/{id}")))["merged_deltas"]
            .as_u64()
            .unwrap_or(0);
        wait_job(&s, &id, 120, |v| {
            v["merged_deltas"].as_u64().unwrap_or(0) > before
        });
        std::thread::sleep(rng.millis(0, 2500));
        eprintln!("kill -9 #{kill}");
        drop(std::mem::replace(
            &mut s.proc,
            Proc(std::process::Command::new("true").spawn().unwrap()),
        ));
        s = server_on(&data, &addr, &ARGS);
    }
    // then a SIGTERM: the master drains and exits cleanly
    wait_job(&s, &id, 120, |v| {
        v["merged_deltas"].as_u64().unwrap_or(0) > 0
    });
    std::thread::sleep(rng.millis(200, 1500));
    s.proc.term();
    let status = s
        .proc
        .wait_exit(120)
        .expect("the master exits after SIGTERM");
    assert!(status.success(), "{status:?}");
    let s = server_on(&data, &addr, &ARGS);
    // each worker uploads again what it had not seen made durable before anything new, so
    // once both delivered a new delta, the last master holds every acknowledged one
    let seen = [keys(&k1), keys(&k2)];
    let end = std::time::Instant::now() + Duration::from_secs(120);
    while [&k1, &k2]
        .iter()
        .zip(&seen)
        .any(|(d, old)| keys(d).is_subset(old))
        && std::time::Instant::now() < end
    {
        std::thread::sleep(Duration::from_millis(200));
    }
    // then end the job and let the workers finish their leases
    let r = http()
        .delete(s.api(&format!("/jobs/{id}")))
        .send()
        .expect("DELETE");
    assert!(r.status().is_success(), "{}", r.status());
    let v = wait_job(&s, &id, 120, |v| {
        v["state"] != "rendering" && v["active_leases"].as_u64() == Some(0)
    });
    assert_eq!(v["active_leases"], 0, "{v}");
    // An acknowledgement sent just before the cancel may still be on its way to a worker.
    stop_workers(&mut workers);
    let merged = final_checkpoint(&s, &id);
    let acked = acknowledged(&[&k1, &k2]);
    assert!(acked.len() >= 5, "{} deltas", acked.len());
    let sum: f64 = acked.values().map(Film::total_samples).sum();
    assert_eq!(
        merged.total_samples(),
        sum,
        "the film holds exactly the acknowledged samples ({} deltas)",
        acked.len()
    );
    assert_eq!(v["samples"].as_f64().unwrap(), sum, "{v}");
}
