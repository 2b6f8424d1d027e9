//! Helpers shared by the integration tests: locating the shared material and its scenes.

#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// The shared material: `../shared` beside the repository, or /work/shared.
pub fn shared() -> PathBuf {
    let beside = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared"));
    if beside.join("scenes").is_dir() {
        beside
    } else {
        PathBuf::from("/work/shared")
    }
}

/// Every `.lxs` file below `dir`, sorted.
pub fn all_scenes(dir: &Path) -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "lxs") {
                out.push(p);
            }
        }
    }
    let mut out = Vec::new();
    walk(dir, &mut out);
    out.sort();
    out
}
