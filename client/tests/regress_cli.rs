//! `luxfarm regress DIR`: a TestSuite-style folder with three .cfg tests — one whose
//! reference (a longer render of the same scene) is within its MSE threshold, one with a
//! threshold of zero that noise must exceed, and one without its reference film — gives a
//! PASS, a FAIL and a SKIP row, exits 1 because of the FAIL, and writes nothing into DIR.

mod cli_common;

use cli_common::{luxfarm, tiny_scene};
use std::collections::BTreeSet;
use std::path::Path;

fn test_dir(dir: &Path, threshold: &str, reference: &str) {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(dir.join("default.lxs"), tiny_scene("default", 64)).unwrap();
    std::fs::write(
        dir.join("simple.cfg"),
        format!(
            "sceneFile = \"default.lxs\"\nreferenceFilm = \"{reference}\"\n\
             testFilm = \"default.flm\"\nerrorTreshold = {threshold}\n\
             cleanFiles = \"default.flm\"\n"
        ),
    )
    .unwrap();
}

fn files(dir: &Path) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for e in walk(dir) {
        out.insert(e);
    }
    out
}

fn walk(dir: &Path) -> Vec<String> {
    let mut v = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            v.extend(walk(&p));
        } else {
            v.push(p.display().to_string());
        }
    }
    v
}

#[test]
fn regress_prints_pass_fail_and_skip_rows() {
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("suite");
    test_dir(&suite.join("a_pass"), "0.5", "reference.flm");
    test_dir(&suite.join("b_fail"), "0", "reference.flm");
    test_dir(&suite.join("c_skip"), "0.5", "missing.flm");
    // References: a longer render of the same scene with another seed.
    for d in ["a_pass", "b_fail"] {
        let scene = suite.join(d).join("default.lxs");
        let base = suite.join(d).join("reference");
        let o = luxfarm(&[
            "render",
            scene.to_str().unwrap(),
            "--haltspp",
            "64",
            "--seed",
            "9",
            "-o",
            base.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let before = files(&suite);
    let o = luxfarm(&["regress", suite.to_str().unwrap(), "--haltspp", "8"]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stdout}\n{stderr}");
    let row = |name: &str| {
        stdout
            .lines()
            .find(|l| l.contains(name))
            .unwrap_or_else(|| panic!("no row for {name}: {stdout}"))
            .to_string()
    };
    let pass = row("a_pass");
    assert!(pass.starts_with("PASS"), "{pass}");
    assert!(row("b_fail").starts_with("FAIL"), "{stdout}");
    assert!(row("c_skip").starts_with("SKIP"), "{stdout}");
    // The scale column: same scene, same light, so about 1.
    let scale: f64 = pass.split_whitespace().nth(3).unwrap().parse().unwrap();
    assert!((0.8..1.25).contains(&scale), "{pass}");
    assert_eq!(files(&suite), before, "regress wrote into the suite folder");
}

#[test]
fn a_malformed_cfg_is_refused_with_its_location() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("t.cfg"), "sceneFile = \"a.lxs\"\ngarbage\n").unwrap();
    let o = luxfarm(&["regress", tmp.path().to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("t.cfg:2:1:"), "{err}");
}
