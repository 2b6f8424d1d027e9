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
        let sibling = dir.path().join(format!("luxfarm-{}", l.name()));
        std::fs::write(
            &sibling,
            format!("#!/bin/sh\necho \"{tag} isa=$LUXFARM_ISA args=$*\"\n"),
        )
        .unwrap();
        std::fs::set_permissions(&sibling, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    (dir, exe)
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
    assert!(
        out.starts_with("sibling ") && out.contains(&format!("isa={}", level.name())),
        "{out}"
    );
    assert!(out.trim_end().ends_with("args=parse --help"), "{out}");
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
