//! `luxfarm parse`: exit status 0 with a summary or JSON when the scene parses, 2 with the
//! located error on stderr when it does not.

use std::path::{Path, PathBuf};
use std::process::Command;

fn shared() -> PathBuf {
    let beside = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../shared"));
    if beside.join("scenes").is_dir() {
        beside.to_path_buf()
    } else {
        PathBuf::from("/work/shared")
    }
}

fn luxfarm(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_luxfarm"))
        .args(args)
        .output()
        .expect("run luxfarm")
}

#[test]
fn summary_of_a_good_scene() {
    let scene = shared().join("scenes/cornell/cornell.lxs");
    let out = luxfarm(&["parse", scene.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("camera: perspective fov 39.3"), "{text}");
    assert!(
        text.contains("film: fleximage 256x256 haltspp 64"),
        "{text}"
    );
    assert!(text.contains("shapes: 6 (1 area-lit)"), "{text}");
    assert!(text.contains("materials: 4 (4 named)"), "{text}");
}

#[test]
fn json_of_a_scene_with_textures() {
    let scene = shared().join(
        "scenes/testsuite/core_regression_tests/tests/integrators/directlighting/simple/default.lxs",
    );
    let out = luxfarm(&["parse", "--json", scene.to_str().unwrap()]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["film"]["kind"], "fleximage");
    assert!(v["named_textures"].as_array().is_some());
    assert!(v["files"].as_array().unwrap().len() >= 3);
}

#[test]
fn broken_scene_exits_2_with_location() {
    let scene = shared().join("scenes/testsuite/sunsky_params/SunSky_Params.lxs");
    let out = luxfarm(&["parse", scene.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("SunSky_Params.lxs:47:1:"), "{err}");
    assert!(err.contains("SunSky_Params-geom.lxo"), "{err}");
    assert!(out.stdout.is_empty());

    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.lxs");
    std::fs::write(&bad, "WorldBegin\n  AtributeBegin\nWorldEnd\n").unwrap();
    let out = luxfarm(&["parse", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad.lxs:2:3: unknown statement 'AtributeBegin'"),
        "{err}"
    );

    let out = luxfarm(&["parse", "/nonexistent/x.lxs"]);
    assert_eq!(out.status.code(), Some(2));
}
