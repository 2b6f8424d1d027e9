//! Path safety of bundle entries: an entry name from an archive (or a scene name from a
//! request) becomes a relative path of normal components, or is refused. Everything that
//! joins an untrusted name to a directory goes through [`safe_relative`] first.

use crate::{Result, WireError};
use std::path::{Component, Path, PathBuf};

/// Longest path component accepted (the usual file-system limit, NAME_MAX).
pub const MAX_COMPONENT: usize = 255;
/// Longest entry name accepted (leaves room under PATH_MAX for the directory it lands in).
pub const MAX_ENTRY_NAME: usize = 1024;

/// Checks an entry name and turns it into a relative path made of normal components only:
/// no absolute path (`/x`, `\x`, `C:x`), no `..`, no NUL, no component longer than
/// [`MAX_COMPONENT`] bytes and no name longer than [`MAX_ENTRY_NAME`]; `.` and empty
/// components are dropped; `/` and `\` both separate.
pub fn safe_relative(name: &str) -> Result<PathBuf> {
    let shown: String = name.chars().take(80).collect();
    let shown = if shown.len() < name.len() {
        format!("{shown}...")
    } else {
        shown
    };
    let bad = |why: &str| WireError::Bundle(format!("bundle entry {shown:?}: {why}"));
    if name.len() > MAX_ENTRY_NAME {
        return Err(bad(&format!(
            "name of {} bytes, longer than the {MAX_ENTRY_NAME} accepted",
            name.len()
        )));
    }
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
            p if p.len() > MAX_COMPONENT => {
                return Err(bad(&format!(
                    "a path component of {} bytes, longer than the {MAX_COMPONENT} accepted",
                    p.len()
                )))
            }
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
        // Over-long components and names are refused with their size, the name shortened.
        let long = format!("{}/scene.lxs", "d".repeat(290));
        let e = safe_relative(&long).unwrap_err().to_string();
        assert!(e.contains("290 bytes") && e.len() < 300, "{e}");
        assert!(safe_relative(&"a/".repeat(600)).is_err());
        assert!(safe_relative(&format!("{}/x", "d".repeat(255))).is_ok());
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
