//! `luxfarm study`: a tiny study (a 32×32 scene, seconds of budget) over two local
//! configurations and local farms of 1 and 2 workers, against a reference the study renders
//! itself. The CSV, the HTML report and the figures (SVG and PNG) are produced and agree:
//! every configuration is in the CSV, the error of each local configuration falls from its
//! first checkpoint to its last, the recommendation names a configuration of the CSV, and the
//! HTML inlines the figures. A second study in the same folder reuses the cached reference.

mod cli_common;

use cli_common::{luxfarm, tiny_scene};
use std::collections::BTreeMap;
use std::path::Path;

/// CSV rows per configuration: (seconds, samples, rmse) of each checkpoint.
fn read_csv(path: &Path) -> BTreeMap<String, Vec<(f64, f64, Option<f64>)>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("config,workers,seconds,samples,spp,samples_per_second,rmse,rel_mse,failing_share")
    );
    let mut out: BTreeMap<String, Vec<_>> = BTreeMap::new();
    for l in lines {
        let f: Vec<&str> = l.split(',').collect();
        assert_eq!(f.len(), 9, "{l}");
        let num = |s: &str| s.parse::<f64>().ok();
        let rmse = num(f[6]);
        if let Some(e) = rmse {
            assert!(e.is_finite() && e >= 0.0, "{l}");
            let failing = num(f[8]).unwrap();
            assert!((0.0..=1.0).contains(&failing), "{l}");
        }
        out.entry(f[0].to_string()).or_default().push((
            num(f[2]).unwrap(),
            num(f[3]).unwrap(),
            rmse,
        ));
    }
    out
}

#[test]
fn a_tiny_study_writes_consistent_csv_html_and_figures() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("tiny.lxs");
    std::fs::write(&scene, tiny_scene("tiny", 4)).unwrap();
    let out = tmp.path().join("study");
    let (scene_s, out_s) = (scene.to_str().unwrap(), out.to_str().unwrap());
    let o = luxfarm(&[
        "study",
        scene_s,
        "--configs",
        "scene,path/sobol,farm:1,farm:2",
        "--budget",
        "8",
        "--reference-time",
        "4",
        "--threads",
        "1",
        "-o",
        out_s,
    ]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stdout}\n{stderr}");
    assert!(out.join("reference.flm").is_file());

    let runs = read_csv(&out.join("study.csv"));
    let labels: Vec<&str> = runs.keys().map(String::as_str).collect();
    assert_eq!(labels, ["farm:1", "farm:2", "path/random", "path/sobol"]);
    for local in ["path/random", "path/sobol"] {
        let cps = &runs[local];
        assert!(cps.len() >= 3, "{local}: {cps:?}");
        // Time and samples grow; the error falls from the first checkpoint to the last.
        assert!(cps.windows(2).all(|w| w[1].0 > w[0].0 && w[1].1 > w[0].1));
        let (first, last) = (cps[0].2.unwrap(), cps[cps.len() - 1].2.unwrap());
        assert!(last < first, "{local}: RMSE {first} -> {last}");
    }
    for farm in ["farm:1", "farm:2"] {
        let cps = &runs[farm];
        assert_eq!(cps.len(), 1, "{farm}");
        assert!(cps[0].1 > 0.0 && cps[0].2.is_some(), "{farm}: {cps:?}");
    }

    let rec = stdout.lines().last().unwrap_or_default();
    assert!(rec.starts_with("Recommendation: "), "{stdout}");
    let named = rec
        .trim_start_matches("Recommendation: ")
        .split_whitespace()
        .next()
        .unwrap();
    assert!(runs.contains_key(named), "{rec}");

    let html = std::fs::read_to_string(out.join("study.html")).unwrap();
    assert!(
        html.contains(rec.trim()),
        "the HTML repeats the recommendation"
    );
    for name in [
        "error_vs_time",
        "time_to_target",
        "samples_per_second",
        "farm_speedup",
    ] {
        let svg = std::fs::read_to_string(out.join(format!("{name}.svg"))).unwrap();
        assert!(svg.contains("<svg") && svg.contains("</svg>"), "{name}");
        let png = std::fs::read(out.join(format!("{name}.png"))).unwrap();
        assert!(
            png.starts_with(b"\x89PNG\r\n\x1a\n") && png.len() > 1000,
            "{name}"
        );
        assert!(
            html.contains(&format!("<figure id=\"{name}\"><svg")),
            "{name}"
        );
    }
    for label in labels {
        assert!(html.contains(&format!("<td>{label}</td>")), "{label}");
        assert!(
            std::fs::read_to_string(out.join("error_vs_time.svg"))
                .unwrap()
                .contains(label)
                || label.starts_with("farm:"),
            "the error figure's legend names {label}"
        );
    }

    // Same scene, same folder: the reference is reused, not rendered again.
    let o = luxfarm(&[
        "study",
        scene_s,
        "--configs",
        "scene",
        "--budget",
        "1",
        "--reference-time",
        "4",
        "--threads",
        "1",
        "-o",
        out_s,
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    assert!(stderr.contains("reusing the cached reference"), "{stderr}");
    assert!(!stderr.contains("rendering the reference"), "{stderr}");
}

#[test]
fn bad_study_arguments_are_refused_with_status_2() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("tiny.lxs");
    std::fs::write(&scene, tiny_scene("tiny", 4)).unwrap();
    let s = scene.to_str().unwrap();
    for args in [
        vec!["study", s, "--configs", "photon/random"],
        vec!["study", s, "--budget", "0"],
        vec!["study", s, "--target", "-1"],
    ] {
        let o = luxfarm(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {o:?}");
    }
}
