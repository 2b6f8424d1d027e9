//! The start-up dispatch to a sibling binary built for a higher x86-64 level (client `isa`):
//! a copy of `luxfarm` (a hard link in cargo's scratch folder) with a fake sibling beside it,
//! a script that prints the arguments and `LUXFARM_ISA` it was started with.

#![cfg(all(unix, target_arch = "x86_64"))]

use luxfarm::isa::{self, Level};
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::Command;

/// A folder holding `luxfarm` (this build's binary) and, when given, a sibling named for
/// `level` that reports how it was started.
fn install(tag: &str, level: Option<Level>) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir_in(env!("CARGO_TARGET_TMPDIR")).unwrap();
    let exe = dir.path().join("luxfarm");
    std::fs::hard_link(env!("CARGO_BIN_EXE_luxfarm"), &exe)
        .or_else(|_| std::fs::copy(env!("CARGO_BIN_EXE_luxfarm"), &exe).map(|_| ()))
        .unwrap();
    if let Some(l) = level {
        reporter(&dir.path().join(format!("luxfarm-{}", l.name())), tag);
    }
    (dir, exe)
}

/// A script at `path` that prints `tag` and the `LUXFARM_ISA` and arguments it was started
/// with.
fn reporter(path: &Path, tag: &str) {
    std::fs::write(
        path,
        format!("#!/bin/sh\necho \"{tag} isa=$LUXFARM_ISA args=$*\"\n"),
    )
    .unwrap();
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755)).unwrap();
}

fn run(exe: &Path, env: Option<&str>) -> String {
    let mut cmd = Command::new(exe);
    cmd.args(["parse", "--help"]).env_remove("LUXFARM_ISA");
    if let Some(v) = env {
        cmd.env("LUXFARM_ISA", v);
    }
    let out = cmd.output().unwrap();
    assert!(out.status.success(), "{out:?}");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The highest level above this build's that the CPU runs, if any.
fn runnable_level() -> Option<Level> {
    Level::ALL
        .into_iter()
        .rev()
        .find(|&l| Some(l) > isa::BUILD && Some(l) <= isa::cpu_level())
}

#[test]
fn a_runnable_sibling_takes_over_with_the_same_arguments() {
    let Some(level) = runnable_level() else {
        eprintln!("this CPU runs no level above the build's: nothing to dispatch to");
        return;
    };
    let (_dir, exe) = install("sibling", Some(level));
    let out = run(&exe, None);
    // The level and this build's id, which the sibling checks.
    let id = option_env!("LUXFARM_BUILD_ID").unwrap_or("dev");
    assert!(
        out.starts_with(&format!("sibling isa={}:{id} ", level.name())),
        "{out}"
    );
    assert!(out.trim_end().ends_with("args=parse --help"), "{out}");
    // Set but empty (as environment lists in deployments often leave it): as unset.
    assert!(
        run(&exe, Some("")).starts_with("sibling "),
        "empty LUXFARM_ISA"
    );
}

#[test]
fn luxfarm_isa_set_keeps_this_binary() {
    let Some(level) = runnable_level() else {
        return;
    };
    let (_dir, exe) = install("sibling", Some(level));
    let out = run(&exe, Some("x86-64"));
    assert!(!out.contains("sibling"), "{out}");
    assert!(out.contains("Usage"), "{out}");
}

#[test]
fn a_sibling_the_cpu_cannot_run_is_left_alone() {
    if isa::cpu_level() == Some(Level::V4) {
        // Every level runs here; the unit tests cover the choice.
        return;
    }
    let (_dir, exe) = install("sibling", Some(Level::V4));
    let out = run(&exe, None);
    assert!(!out.contains("sibling"), "{out}");
}

#[test]
fn without_siblings_the_binary_runs_itself() {
    let (_dir, exe) = install("none", None);
    let out = run(&exe, None);
    assert!(out.contains("Usage"), "{out}");
}

/// A sibling started with another build's id hands over to its baseline (here a script named
/// `luxfarm`), which must not dispatch again; with its own id it runs itself.
#[test]
fn a_sibling_of_another_build_hands_back_to_its_baseline() {
    let dir = tempfile::tempdir_in(env!("CARGO_TARGET_TMPDIR")).unwrap();
    let level = isa::build_name();
    let sibling = dir.path().join(format!("luxfarm-{level}"));
    std::fs::hard_link(env!("CARGO_BIN_EXE_luxfarm"), &sibling)
        .or_else(|_| std::fs::copy(env!("CARGO_BIN_EXE_luxfarm"), &sibling).map(|_| ()))
        .unwrap();
    reporter(&dir.path().join("luxfarm"), "baseline");
    let out = run(&sibling, Some(&format!("{level}:another-build")));
    assert!(
        out.starts_with(&format!(
            "baseline isa={} args=parse --help",
            Level::V1.name()
        )),
        "{out}"
    );
    let id = option_env!("LUXFARM_BUILD_ID").unwrap_or("dev");
    let out = run(&sibling, Some(&format!("{level}:{id}")));
    assert!(!out.contains("baseline") && out.contains("Usage"), "{out}");
}
