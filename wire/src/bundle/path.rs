//! Path safety of bundle entries: an entry name from an archive (or a scene name from a
//! request) becomes a relative path of normal components, or is refused. Everything that
//! joins an untrusted name to a directory goes through [`safe_relative`] first.

use crate::{Result, WireError};
use std::path::{Component, Path, PathBuf};

/// Checks an entry name and turns it into a relative path made of normal components only:
/// no absolute path (`/x`, `\x`, `C:x`), no `..`, no NUL; `.` and empty components are
/// dropped; `/` and `\` both separate.
pub fn safe_relative(name: &str) -> Result<PathBuf> {
    let bad = |why: &str| WireError::Bundle(format!("bundle entry {name:?}: {why}"));
    if name.is_empty() {
        return Err(bad("empty name"));
    }
    if name.starts_with('/') || name.starts_with('\\') || name.contains(':') {
        return Err(bad("absolute path refused"));
    }
    let mut out = PathBuf::new();
    for part in name.split(['/', '\\']) {
        match part {
            "" | "." => continue,
            ".." => return Err(bad("'..' refused")),
            p => {
                let c = Path::new(p).components().next();
                if !matches!(c, Some(Component::Normal(_))) || p.contains('\0') {
                    return Err(bad("invalid path component"));
                }
                out.push(p);
            }
        }
    }
    if out.as_os_str().is_empty() {
        return Err(bad("empty path"));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unsafe_names_are_refused() {
        for name in [
            "/etc/passwd",
            "../x.lxs",
            "a/../../x",
            "a/..",
            "C:\\x",
            "c:x.lxs",
            "\\abs",
            "",
            ".",
            "./",
            "a\0b.lxs",
        ] {
            assert!(safe_relative(name).is_err(), "{name:?}");
        }
    }

    #[test]
    fn safe_names_are_normalised() {
        assert_eq!(
            safe_relative("./a/b.ply").unwrap(),
            PathBuf::from("a/b.ply")
        );
        assert_eq!(
            safe_relative("a\\b//c.lxs").unwrap(),
            PathBuf::from("a/b/c.lxs")
        );
        assert_eq!(safe_relative("..a.lxs").unwrap(), PathBuf::from("..a.lxs"));
    }
}
