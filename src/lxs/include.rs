//! Resolving `Include "file"` paths: relative to the including file's directory, checked for
//! existence, cycles, depth, and (for untrusted scenes) confinement to the root scene's
//! directory, with symlinks resolved.

use super::error::{LxsError, LxsErrorKind, LxsResult};
use super::params::Loc;
use std::path::{Component, Path, PathBuf};

/// Where an included file is, once resolved.
pub struct Resolved {
    /// The path as shown in locations (the including directory joined with the name).
    pub display: PathBuf,
    /// The canonical path (symlinks resolved), used for cycle detection and confinement.
    pub canonical: PathBuf,
}

/// Removes `.` and `..` components lexically. Returns None when `..` climbs above the start.
fn normalize(p: &Path) -> Option<PathBuf> {
    let mut out = PathBuf::new();
    let mut depth: usize = 0;
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                if depth == 0 {
                    return None;
                }
                out.pop();
                depth -= 1;
            }
            Component::Normal(s) => {
                out.push(s);
                depth += 1;
            }
            Component::RootDir | Component::Prefix(_) => out.push(c.as_os_str()),
        }
    }
    Some(out)
}

/// Resolves `name` written in a file whose directory is `dir` (display form) / `canonical_dir`.
/// `root` is the canonical directory of the root scene when includes are confined to it.
pub fn resolve(
    name: &str,
    dir: &Path,
    canonical_dir: &Path,
    root: Option<&Path>,
    loc: &Loc,
) -> LxsResult<Resolved> {
    let rel = Path::new(name);
    let outside = |why: &str| {
        Err(LxsError::new(
            LxsErrorKind::IncludeOutsideRoot,
            loc.clone(),
            format!("Include \"{name}\" {why}: includes are confined to the scene's directory"),
        ))
    };
    if name.is_empty() {
        return Err(LxsError::new(
            LxsErrorKind::MissingInclude,
            loc.clone(),
            "Include with an empty file name",
        ));
    }
    if let Some(root) = root {
        if rel.has_root() || rel.is_absolute() {
            return outside("is an absolute path");
        }
        let inside = normalize(&canonical_dir.join(rel)).is_some_and(|p| p.starts_with(root));
        if !inside {
            return outside("leaves the root directory");
        }
    }
    let display = dir.join(rel);
    let canonical = match std::fs::canonicalize(canonical_dir.join(rel)) {
        Ok(c) => c,
        Err(e) => {
            return Err(LxsError::new(
                LxsErrorKind::MissingInclude,
                loc.clone(),
                format!("Include \"{name}\": cannot open {}: {e}", display.display()),
            ))
        }
    };
    if let Some(root) = root {
        if !canonical.starts_with(root) {
            return outside("resolves (through a symlink) outside the root directory");
        }
    }
    if canonical.is_dir() {
        return Err(LxsError::new(
            LxsErrorKind::MissingInclude,
            loc.clone(),
            format!("Include \"{name}\": {} is a directory", display.display()),
        ));
    }
    Ok(Resolved { display, canonical })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalize_refuses_to_climb_above_start() {
        assert_eq!(
            normalize(Path::new("a/./b/../c")),
            Some(PathBuf::from("a/c"))
        );
        assert_eq!(normalize(Path::new("a/../../c")), None);
        assert_eq!(
            normalize(Path::new("/r/a/../c")),
            Some(PathBuf::from("/r/c"))
        );
    }
}
