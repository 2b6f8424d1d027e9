//! The Markov-chain samplers on the farm (issue 14): two workers render the Cornell box at
//! 64×64 with metropolis + bidirectional, or erpt + path, each worker on its own stream (its
//! own chains; erpt its own seeds, with the job's quantum). The master's film is the exact sum of the
//! deltas it acknowledged, and its image is the image of a local render within noise:
//! compared with a local render, it differs no more than a second local render of another
//! seed does (RMSE and mean ratio, through `luxfarm compare-image` on the EXR outputs, which
//! apply the per-screen normalisation of these films).

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
