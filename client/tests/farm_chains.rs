//! The Markov-chain samplers on the farm (issue 14): two workers render the Cornell box at
//! 64×64 with metropolis + bidirectional, or erpt + path, each worker on its own stream (its
//! own chains; erpt its own seeds, with the job's quantum). The master's film is the exact sum of the
//! deltas it acknowledged, and its image is the image of a local render within noise:
//! compared with a local render, it differs no more than a second local render of another
//! seed does (RMSE and mean ratio, through `luxfarm compare-image` on the EXR outputs, which
//! apply the per-screen normalisation of these films).
//!
//! A metropolis pass far longer than the job (a pass here is ~270 M steps) is wrapped up
//! rather than dropped (`luxfarm::render::stops`): a stop from the master (the job's
//! halttime) ends it at its next batch and the lease's last delta carries it; and each ask
//! of the uploader ends it too, so deltas with samples arrive every upload interval.

mod farm_common;

use farm_common::*;
use std::path::Path;
use std::process::Command;

const SPP: u32 = 16;

const METROPOLIS: &str = "Sampler \"metropolis\" \"integer pixelsamples\" [2]";
const BIDIRECTIONAL: &str =
    "SurfaceIntegrator \"bidirectional\" \"integer eyedepth\" [8] \"integer lightdepth\" [8]";
/// Short chains and warm-up for the debug build: a pass of ⌈64·64·2 / 65⌉ = 127 seeds.
const ERPT: &str = "Sampler \"erpt\" \"integer pixelsamples\" [2] \"integer chainlength\" [64] \
                    \"integer initsamples\" [4000]";
const PATH: &str = "SurfaceIntegrator \"path\" \"integer maxdepth\" [8]";

/// The Cornell box at 64×64 with the given Sampler and SurfaceIntegrator statements.
fn scene_text(sampler: &str, integrator: &str) -> String {
    let text = std::fs::read_to_string(shared().join("scenes/cornell/cornell.lxs")).unwrap();
    text.replace("[256]", "[64]")
        .replace("Sampler \"random\" \"integer pixelsamples\" [1]", sampler)
        .replace(
            "SurfaceIntegrator \"path\" \"integer maxdepth\" [8] \"string rrstrategy\" [\"none\"]",
            integrator,
        )
}

/// Renders the scene locally with `seed`; returns the EXR's path.
fn local(dir: &Path, scene: &Path, seed: u32) -> std::path::PathBuf {
    let base = dir.join(format!("local{seed}"));
    run_ok(
        Command::new(exe())
            .arg("render")
            .arg(scene)
            .args(["--threads", "2", "--haltspp", &SPP.to_string()])
            .args(["--seed", &seed.to_string(), "-o"])
            .arg(&base),
    );
    base.with_extension("exr")
}

/// (RMSE, mean ratio) of `a` against `b` from `luxfarm compare-image`.
fn compare(a: &Path, b: &Path) -> (f64, f64) {
    let out = run_ok(Command::new(exe()).arg("compare-image").args([a, b]));
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    let value = |key: &str| -> f64 {
        let line = text
            .lines()
            .find(|l| l.starts_with(key))
            .unwrap_or_else(|| panic!("{text}"));
        line[key.len()..].trim().parse().unwrap()
    };
    (value("RMSE"), value("mean ratio"))
}

#[test]
fn two_workers_render_metropolis_as_a_local_render_does() {
    farm_matches_local("mlt", METROPOLIS, BIDIRECTIONAL);
}

#[test]
fn two_workers_render_erpt_as_a_local_render_does() {
    farm_matches_local("erpt", ERPT, PATH);
}

/// Renders the scene (`stem`.lxs) on two workers to haltspp and checks the merged film
/// against the acknowledged deltas and its image against local renders.
fn farm_matches_local(stem: &str, sampler: &str, integrator: &str) {
    let dir = tempfile::tempdir().unwrap();
    let text = scene_text(sampler, integrator);
    assert!(text.contains(sampler) && text.contains(integrator));
    let scene = dir.path().join(format!("{stem}.lxs"));
    std::fs::write(&scene, &text).unwrap();
    let s = server(&dir.path().join("data"), &["--upload-interval", "1"]);
    let query = format!("?filename={stem}.lxs&haltspp={SPP}&seed=5");
    let (st, job) = post_job(&s, text.into_bytes(), &query);
    assert_eq!(st, 201, "{job}");
    let id = job["id"].as_str().unwrap().to_string();
    let (k1, k2) = (dir.path().join("k1"), dir.path().join("k2"));
    let mut workers = [
        worker(&s.url(), 1, &["--keep-deltas", k1.to_str().unwrap()]),
        worker(&s.url(), 1, &["--keep-deltas", k2.to_str().unwrap()]),
    ];
    let v = wait_job(&s, &id, 900, |v| {
        v["state"] != "queued" && v["state"] != "rendering"
    });
    assert_eq!(v["state"], "done", "{v}");
    assert!(v["workers"].as_array().unwrap().len() >= 2, "{v}");
    // The merged film is the exact sum of the acknowledged deltas.
    stop_workers(&mut workers);
    let merged = final_checkpoint(&s, &id);
    let (sum, n) = sum_kept(&[&k1, &k2]);
    assert_eq!(n as u64, v["merged_deltas"].as_u64().unwrap());
    assert_same_sums(&merged, &sum);
    // The same image as local renders, within the noise two local renders show.
    let farm_exr = s
        .data
        .join("jobs")
        .join(&id)
        .join("out")
        .join("cornell.exr");
    assert!(farm_exr.exists(), "{}", farm_exr.display());
    let (l1, l2) = (local(dir.path(), &scene, 1), local(dir.path(), &scene, 2));
    let (rmse_local, ratio_local) = compare(&l2, &l1);
    let (rmse_farm, ratio_farm) = compare(&farm_exr, &l1);
    eprintln!(
        "farm ({} spp) vs local: RMSE {rmse_farm:.5}, mean ratio {ratio_farm:.4}; \
         local vs local: RMSE {rmse_local:.5}, mean ratio {ratio_local:.4}",
        v["spp"]
    );
    assert!(
        rmse_farm <= 1.6 * rmse_local,
        "farm RMSE {rmse_farm} vs noise {rmse_local}"
    );
    let tol = (3.0 * (ratio_local - 1.0).abs()).max(0.03);
    assert!(
        (ratio_farm - 1.0).abs() <= tol,
        "farm mean ratio {ratio_farm} (tolerance {tol})"
    );
}

/// An erpt job's second lease on a worker takes the quantum its first lease estimated and
/// skips the warm-up: the worker renders a lease, stalls (SIGSTOP) past the master's worker
/// timeout, which ends its lease, and resumes (SIGCONT); its new lease of the job logs the
/// quantum its first lease's warm-up logged, with no second warm-up. (A master restart keeps
/// the lease, so it is not the way to a second one.)
#[test]
fn a_second_erpt_lease_on_a_worker_reuses_the_jobs_quantum() {
    let dir = tempfile::tempdir().unwrap();
    let text = scene_text(ERPT, PATH);
    let data = dir.path().join("data");
    let s = server(
        &data,
        &["--upload-interval", "0.5", "--worker-timeout", "2"],
    );
    let (st, job) = post_job(
        &s,
        text.into_bytes(),
        "?filename=erpt.lxs&haltspp=100000&seed=7",
    );
    assert_eq!(st, 201, "{job}");
    let id = job["id"].as_str().unwrap().to_string();
    let log_path = dir.path().join("worker.log");
    let log = std::fs::File::create(&log_path).unwrap();
    let mut w = Proc(
        Command::new(exe())
            .args(["worker", "--master", &s.url(), "--threads", "1"])
            .env_remove("LUXFARM_TOKEN")
            .env("RUST_LOG", "info")
            .env("NO_COLOR", "1")
            .stdout(std::process::Stdio::null())
            .stderr(log)
            .spawn()
            .expect("spawn worker"),
    );
    let read_log = || std::fs::read_to_string(&log_path).unwrap_or_default();
    let estimated = "erpt: the warm-up estimated the job's quantum";
    let reused = "erpt: the job's quantum from an earlier lease, no warm-up";
    wait_job(&s, &id, 300, |v| {
        v["merged_deltas"].as_u64().unwrap_or(0) >= 2
    });
    assert!(read_log().contains(estimated), "{}", read_log());
    // The worker stalls past the timeout: its lease is over; resumed, it asks again.
    let pid = w.0.id() as libc::pid_t;
    let signal = |sig: libc::c_int| assert_eq!(unsafe { libc::kill(pid, sig) }, 0);
    signal(libc::SIGSTOP);
    let v = wait_job(&s, &id, 120, |v| v["active_leases"] == 0);
    assert_eq!(v["active_leases"], 0, "{v}");
    signal(libc::SIGCONT);
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(300);
    while !read_log().contains(reused) && std::time::Instant::now() < deadline {
        std::thread::sleep(std::time::Duration::from_millis(200));
    }
    let v = get_json(&s.api(&format!("/jobs/{id}")));
    let _ = http().delete(s.api(&format!("/jobs/{id}"))).send();
    stop_workers(std::slice::from_mut(&mut w));
    let text = read_log();
    let quantum = |line: &str| -> String {
        let l = text
            .lines()
            .find(|l| l.contains(line))
            .unwrap_or_else(|| panic!("no \"{line}\" in the worker's log (job {v}):\n{text}"));
        let at = l.find("quantum=").expect("the quantum is logged") + "quantum=".len();
        l[at..].split_whitespace().next().unwrap().to_string()
    };
    assert!(
        text.matches("lease started").count() >= 2,
        "one lease only:\n{text}"
    );
    assert_eq!(text.matches(estimated).count(), 1, "{text}");
    assert_eq!(quantum(estimated), quantum(reused), "{text}");
}

/// A 64×64 scene whose metropolis pass (65 × 65 extent pixels × 65536 pixelsamples) no lease
/// of these tests could finish.
fn endless_metropolis(dir: &Path) -> Vec<u8> {
    let path = small_scene(dir, "endless", (64, 64), "");
    let text = std::fs::read_to_string(path).unwrap().replace(
        "Sampler \"random\" \"integer pixelsamples\" [1]",
        "Sampler \"metropolis\" \"integer pixelsamples\" [65536]",
    );
    assert!(text.contains("metropolis"));
    text.into_bytes()
}

/// The sample counts of the deltas a worker kept as merged (`LEASE-SEQ.merged.lxd`), in
/// sequence order (one lease).
fn kept_samples(dir: &Path) -> Vec<f64> {
    let mut kept: Vec<(u64, f64)> = files_under(dir)
        .iter()
        .filter_map(|p| {
            let name = p.file_name()?.to_str()?.strip_suffix(".merged.lxd")?;
            let seq = name.rsplit('-').next()?.parse().ok()?;
            let film = luxfarm_wire::codec::decode(&std::fs::read(p).ok()?).ok()?;
            Some((seq, film.total_samples()))
        })
        .collect();
    kept.sort_by_key(|k| k.0);
    kept.into_iter().map(|k| k.1).collect()
}

/// Runs the endless metropolis job with `halttime` on one worker under a master with
/// `upload_interval`; returns the job's final view, its merged film and the samples of the
/// worker's merged deltas.
fn endless_job(
    upload_interval: &str,
    halttime: u32,
) -> (serde_json::Value, luxfarm::film::Film, Vec<f64>) {
    let dir = tempfile::tempdir().unwrap();
    let s = server(
        &dir.path().join("data"),
        &["--upload-interval", upload_interval],
    );
    let scene = endless_metropolis(dir.path());
    let (st, job) = post_job(
        &s,
        scene,
        &format!("?filename=endless.lxs&halttime={halttime}"),
    );
    assert_eq!(st, 201, "{job}");
    let id = job["id"].as_str().unwrap().to_string();
    let kept = dir.path().join("kept");
    let mut w = [worker(
        &s.url(),
        2,
        &["--keep-deltas", kept.to_str().unwrap()],
    )];
    // A hang guard only.
    let v = wait_job(&s, &id, 300, |v| {
        v["state"] != "queued" && v["state"] != "rendering"
    });
    assert_eq!(v["state"], "done", "{v}");
    stop_workers(&mut w);
    let merged = final_checkpoint(&s, &id);
    (v, merged, kept_samples(&kept))
}

/// The job's halttime stops the lease inside its first metropolis pass: the worker wraps
/// the pass up and its last (here its only) delta carries the samples taken, which the job
/// keeps; a cancelled pass would leave the job's film empty. The upload interval is far
/// beyond the job, so no ask for a delta ends the pass before the stop.
#[test]
fn a_stopped_metropolis_lease_keeps_its_partial_pass() {
    let (v, merged, kept) = endless_job("3600", 3);
    eprintln!("job {v}; deltas {kept:?}");
    let samples = merged.total_samples();
    assert!(samples > 0.0, "the stopped pass was dropped: {v}");
    assert!(samples < 65.0 * 65.0 * 65536.0, "{samples}");
    assert_eq!(kept.len(), 1, "{kept:?}");
    assert_eq!(kept[0], samples);
}

/// Each ask of the uploader (every second here) wraps up the current metropolis pass: the
/// deltas carry samples while the first pass is far from its end, so the preview moves.
#[test]
fn a_long_metropolis_pass_uploads_every_interval() {
    let (v, merged, kept) = endless_job("1", 8);
    eprintln!("job {v}; deltas {kept:?}");
    let with_samples = kept.iter().filter(|&&n| n > 0.0).count();
    assert!(with_samples >= 3, "deltas with samples: {kept:?}");
    assert!(kept.last().is_some_and(|&n| n > 0.0), "{kept:?}");
    assert_eq!(kept.iter().sum::<f64>(), merged.total_samples());
}
