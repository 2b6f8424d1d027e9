//! Start-up dispatch to the binary built for the CPU's instruction-set level.
//!
//! `scripts/build-production` writes the baseline binary (`luxfarm`, plain x86-64) and, beside
//! it, the same program built for higher x86-64 levels (`luxfarm-x86-64-v3`, ...; see
//! `luxfarm::isa`). Before anything else `luxfarm` looks for the highest such sibling the CPU
//! supports and replaces itself with it (`exec`: same process id, arguments, standard streams
//! and environment), so one install serves every farm node and each renders at its CPU's speed.
//! Only binaries of one production build run as each other: the script gives all of them the
//! same build id (`LUXFARM_BUILD_ID` at compile time; a plain `cargo build` has the id `dev`),
//! the parent passes `LUXFARM_ISA=<level>:<id>` to the sibling, and the sibling checks the id:
//! when it belongs to another build (a stale sibling left beside a newer binary) it starts its
//! parent with `LUXFARM_ISA=x86-64` instead of running. The variable
//! is inherited by the master's and workers' child processes. A `LUXFARM_ISA` set without an
//! id (e.g. `x86-64`, to keep the baseline binary for an A/B measurement) stops the dispatch;
//! set but empty, it counts as unset. Without siblings, on a CPU below every sibling's level,
//! or off x86-64 Unix, the binary runs itself. Siblings are looked up beside the file the
//! running binary resolves to (through symlinks) and named after it, so they are installed
//! beside the real `luxfarm`; a sibling without execute permission is passed over.
//!
//! A binary built above the CPU's level would die of an illegal instruction somewhere in a
//! render; [`check_start`] tries to stop it at start-up with a message instead. That is best
//! effort: the check itself is compiled for the binary's level, and start-up code before it
//! may already use the level's instructions.

use luxfarm::isa::{self, Level};
use std::path::{Path, PathBuf};

/// The environment variable naming the level chosen and the build (or, set by the user
/// without a build id, stopping the dispatch).
pub const ENV: &str = "LUXFARM_ISA";

/// The production build this binary belongs to (`scripts/build-production` sets it).
const BUILD_ID: &str = match option_env!("LUXFARM_BUILD_ID") {
    Some(id) => id,
    None => "dev",
};

/// Replaces the process with the best sibling binary for this CPU, if there is one; returns
/// when this binary is the one to run.
pub fn dispatch() {
    if std::env::var_os(ENV).is_some_and(|v| !v.is_empty()) {
        return;
    }
    let Some(path) = std::env::current_exe().ok() else {
        return;
    };
    let Some(level) = best_sibling(&path, isa::cpu_level()) else {
        return;
    };
    exec(
        &sibling(&path, level),
        &format!("{}:{BUILD_ID}", level.name()),
    );
}

/// The highest level above this binary's whose sibling of `exe` exists and that `cpu` runs.
fn best_sibling(exe: &Path, cpu: Option<Level>) -> Option<Level> {
    exe.file_name()?;
    Level::ALL
        .into_iter()
        .rev()
        .filter(|&l| Some(l) > isa::BUILD && Some(l) <= cpu)
        .find(|&l| runnable(&sibling(exe, l)))
}

/// Whether `path` is a file this process may start (on Unix: with an execute bit).
fn runnable(path: &Path) -> bool {
    let Ok(meta) = std::fs::metadata(path) else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        meta.is_file() && meta.permissions().mode() & 0o111 != 0
    }
    #[cfg(not(unix))]
    {
        meta.is_file()
    }
}

/// The binary beside `exe` built for `level` (`luxfarm` -> `luxfarm-x86-64-v3`).
fn sibling(exe: &Path, level: Level) -> PathBuf {
    let name = exe
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or("luxfarm");
    exe.with_file_name(format!("{name}-{}", level.name()))
}

/// The baseline binary beside `exe`, a sibling built for `level` (the inverse of [`sibling`]).
fn parent(exe: &Path, level: &str) -> Option<PathBuf> {
    let name = exe.file_name()?.to_str()?;
    let base = name.strip_suffix(level)?.strip_suffix('-')?;
    Some(exe.with_file_name(base))
}

/// Replaces the process with `binary`, the same arguments and `LUXFARM_ISA=isa`; returns
/// (after a message) only when that fails.
#[cfg(unix)]
fn exec(binary: &Path, isa: &str) {
    use std::os::unix::process::CommandExt;
    let mut args = std::env::args_os();
    let arg0 = args.next().unwrap_or_else(|| binary.as_os_str().to_owned());
    let err = std::process::Command::new(binary)
        .arg0(arg0)
        .args(args)
        .env(ENV, isa)
        .exec();
    // Before exec'ing, the standard library set SIGPIPE back to its default for the new
    // program; this one goes on, and ignores it as Rust programs do (a closed pipe is an
    // error to report, not a signal to die of).
    // SAFETY: setting a signal's disposition to SIG_IGN has no preconditions.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_IGN);
    }
    eprintln!(
        "luxfarm: could not start {} ({err}); running the {} build",
        binary.display(),
        isa::build_name()
    );
}

#[cfg(not(unix))]
fn exec(_binary: &Path, _isa: &str) {}

/// Checks, before anything else runs, that this binary may run here: a binary built for a
/// level the CPU lacks exits with a message (best effort, see the module doc); a sibling
/// started by another build's binary (its id differs) starts that build's baseline binary
/// instead.
#[inline(never)]
pub fn check_start() {
    if isa::cpu_level() < isa::BUILD {
        eprintln!(
            "luxfarm: this binary is built for {}, which this CPU does not support ({}); run \
             the baseline `luxfarm` binary instead",
            isa::build_name(),
            isa::cpu_level().map_or("unknown level", Level::name)
        );
        std::process::exit(1);
    }
    let Some(value) = std::env::var(ENV).ok() else {
        return;
    };
    let Some((level, id)) = value.split_once(':') else {
        return;
    };
    if id == BUILD_ID || level != isa::build_name() {
        return;
    }
    let Some(base) = std::env::current_exe()
        .ok()
        .and_then(|exe| parent(&exe, level))
    else {
        return;
    };
    eprintln!(
        "luxfarm: {} is from another build than {}; running the latter",
        level,
        base.display()
    );
    exec(&base, Level::V1.name());
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An empty file with an execute bit (or without: `runnable` passes it over).
    fn touch_mode(dir: &Path, name: &str, mode: u32) {
        let path = dir.join(name);
        std::fs::write(&path, b"").unwrap();
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(&path, std::fs::Permissions::from_mode(mode)).unwrap();
        }
        #[cfg(not(unix))]
        let _ = mode;
    }

    fn touch(dir: &Path, name: &str) {
        touch_mode(dir, name, 0o755);
    }

    #[test]
    fn picks_the_highest_sibling_the_cpu_runs() {
        if isa::BUILD >= Some(Level::V3) {
            // Built for v3 or above (-Ctarget-cpu): nothing above it but v4.
            return;
        }
        let dir = tempfile::tempdir().unwrap();
        let exe = dir.path().join("luxfarm");
        touch(dir.path(), "luxfarm");
        // No siblings: this binary runs.
        assert_eq!(best_sibling(&exe, Some(Level::V4)), None);
        touch(dir.path(), "luxfarm-x86-64-v3");
        touch(dir.path(), "luxfarm-x86-64-v4");
        assert_eq!(best_sibling(&exe, Some(Level::V4)), Some(Level::V4));
        assert_eq!(best_sibling(&exe, Some(Level::V3)), Some(Level::V3));
        // Below every sibling, or an unknown CPU: this binary.
        assert_eq!(best_sibling(&exe, Some(Level::V2)), None);
        assert_eq!(best_sibling(&exe, None), None);
        // A sibling this process may not start is passed over.
        #[cfg(unix)]
        {
            touch_mode(dir.path(), "luxfarm-x86-64-v4", 0o644);
            assert_eq!(best_sibling(&exe, Some(Level::V4)), Some(Level::V3));
        }
        // A sibling of another name does not count.
        let other = dir.path().join("lf");
        assert_eq!(best_sibling(&other, Some(Level::V4)), None);
    }

    #[test]
    fn sibling_and_parent_are_inverse() {
        let exe = Path::new("/opt/lf/luxfarm");
        let s = sibling(exe, Level::V3);
        assert_eq!(s, Path::new("/opt/lf/luxfarm-x86-64-v3"));
        assert_eq!(parent(&s, "x86-64-v3").as_deref(), Some(exe));
        assert_eq!(parent(&s, "x86-64-v4"), None);
        assert_eq!(parent(exe, "x86-64-v3"), None);
    }

    #[test]
    fn never_picks_a_level_at_or_below_its_own() {
        let dir = tempfile::tempdir().unwrap();
        let exe = dir.path().join("luxfarm");
        for l in Level::ALL {
            touch(dir.path(), &format!("luxfarm-{}", l.name()));
        }
        let picked = best_sibling(&exe, Some(Level::V4));
        assert!(picked > isa::BUILD || picked.is_none());
        assert!(best_sibling(&exe, isa::BUILD).is_none());
    }
}
