//! Scene bundles: a scene with every file it references, as it travels from the client to the
//! master and from the master to the workers.
//!
//! Data flow:
//! 1. the client packs a `.lxs` into a tar of the files it references, paths relative to the
//!    scene's directory, or passes a `.zip`/`.tar` through ([`prepare`]);
//! 2. the master detects the upload's kind ([`detect`]: raw `.lxs`, zip, tar), unpacks it into
//!    a staging directory under [`Limits`] ([`unpack`], every name through
//!    [`safe_relative`]), picks the scene ([`pick_scene`]) and stores a canonical tar named by
//!    its sha256 ([`write_canonical_tar`]);
//! 3. a worker fetches that tar, checks it against its name ([`sha256_hex`], [`is_hash`]) and
//!    unpacks it with the same rules.
//!
//! Before queueing a job the master also checks that every file the scene names lies inside
//! the bundle ([`check_scene_files`]), as the workers' render core enforces when it opens them.
//!
//! Safety rules, for every entry: no absolute path, no `..`, no empty or odd component, no
//! symlink, hard link or device; sizes checked while reading (headers are not trusted), the
//! total unpacked size and the entry count bounded (decompression bombs).

mod check;
mod pack;
mod path;
mod store;
mod unpack;

pub use check::{check_scene_files, FILE_PARAMS};
pub use pack::{prepare, referenced_files, Upload};
pub use path::safe_relative;
pub use store::{hash_dir, hash_file, hex, is_hash, sha256_hex, write_canonical_tar};
pub use unpack::unpack;

use crate::{Result, WireError};
use std::path::PathBuf;

/// Size bounds for unpacking a bundle.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Most bytes all entries may unpack to.
    pub max_unpacked: u64,
    /// Most entries (files and directories).
    pub max_entries: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_unpacked: 4 << 30,
            max_entries: 20_000,
        }
    }
}

/// The kind of an upload, from its first bytes (and its name for a raw scene).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Lxs,
    Zip,
    Tar,
}

/// Detects the kind of an upload. Zip and tar are recognised by their magic numbers; anything
/// else must be a text scene (UTF-8, no NUL bytes).
pub fn detect(bytes: &[u8], file_name: &str) -> Result<Kind> {
    if bytes.starts_with(b"PK\x03\x04") || bytes.starts_with(b"PK\x05\x06") {
        return Ok(Kind::Zip);
    }
    if bytes.get(257..262) == Some(b"ustar") {
        return Ok(Kind::Tar);
    }
    if bytes.starts_with(&[0x1f, 0x8b]) {
        return Err(WireError::Unsupported(format!(
            "{file_name}: compressed tar is not accepted; send a .tar, .zip or .lxs"
        )));
    }
    if bytes.is_empty() {
        return Err(WireError::Bundle(format!("{file_name}: empty upload")));
    }
    let head = bytes.get(..64 * 1024).unwrap_or(bytes);
    if head.contains(&0) || std::str::from_utf8(head).is_err() && head.len() == bytes.len() {
        return Err(WireError::Unsupported(format!(
            "{file_name}: not a scene: expected a .lxs text file, a .zip or a .tar"
        )));
    }
    Ok(Kind::Lxs)
}

/// Whether `f` has the extension of a scene format luxfarm reads (`.lxs`, `.igs`, ...).
fn is_scene_file(f: &std::path::Path) -> bool {
    f.extension().and_then(|e| e.to_str()).is_some_and(|e| {
        luxfarm::formats::SCENE_EXTENSIONS.contains(&e.to_ascii_lowercase().as_str())
    })
}

/// Picks the scene among the unpacked files: `wanted` when given, else the only scene file
/// (an extension of [`luxfarm::formats::SCENE_EXTENSIONS`]) at the shallowest depth.
pub fn pick_scene(files: &[PathBuf], wanted: &str) -> Result<PathBuf> {
    if !wanted.is_empty() {
        let rel = safe_relative(wanted)?;
        return files
            .iter()
            .find(|f| **f == rel)
            .cloned()
            .ok_or_else(|| WireError::Bundle(format!("scene {wanted:?} not in bundle")));
    }
    let lxs: Vec<&PathBuf> = files.iter().filter(|f| is_scene_file(f)).collect();
    let depth = lxs.iter().map(|f| f.components().count()).min();
    let top: Vec<&&PathBuf> = lxs
        .iter()
        .filter(|f| Some(f.components().count()) == depth)
        .collect();
    match top.as_slice() {
        [one] => Ok((**one).clone()),
        [] => Err(WireError::Bundle(format!(
            "not a scene: the bundle holds no {} scene file",
            luxfarm::formats::SCENE_EXTENSIONS
                .iter()
                .map(|e| format!(".{e}"))
                .collect::<Vec<_>>()
                .join(" or ")
        ))),
        _ => Err(WireError::Bundle(format!(
            "the bundle holds several scene files ({}); name one with `scene`",
            top.iter()
                .map(|f| f.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_detected() {
        assert_eq!(detect(b"WorldBegin\n", "s.lxs").unwrap(), Kind::Lxs);
        assert_eq!(detect(b"PK\x03\x04rest", "a").unwrap(), Kind::Zip);
        let mut tar = vec![0u8; 512];
        tar[257..262].copy_from_slice(b"ustar");
        assert_eq!(detect(&tar, "a").unwrap(), Kind::Tar);
        assert!(matches!(
            detect(&[0x1f, 0x8b, 8, 0], "a.tar.gz"),
            Err(WireError::Unsupported(_))
        ));
        assert!(matches!(detect(b"", "a"), Err(WireError::Bundle(_))));
        assert!(matches!(
            detect(b"a\0b", "a"),
            Err(WireError::Unsupported(_))
        ));
        assert!(matches!(
            detect(&[0xff, 0xfe, 0x41], "a"),
            Err(WireError::Unsupported(_))
        ));
    }

    #[test]
    fn pick_scene_rules() {
        let files = vec![PathBuf::from("s.lxs"), PathBuf::from("inc/geo.lxs")];
        assert_eq!(pick_scene(&files, "").unwrap(), PathBuf::from("s.lxs"));
        assert_eq!(
            pick_scene(&files, "inc/geo.lxs").unwrap(),
            PathBuf::from("inc/geo.lxs")
        );
        assert!(pick_scene(&files, "../s.lxs").is_err());
        assert!(pick_scene(&files, "t.lxs").is_err());
        assert!(pick_scene(&[PathBuf::from("a.ply")], "").is_err());
        let igs = vec![PathBuf::from("m/mats.igm"), PathBuf::from("s.IGS")];
        assert_eq!(pick_scene(&igs, "").unwrap(), PathBuf::from("s.IGS"));
        let lws = vec![PathBuf::from("shot.lws"), PathBuf::from("Objects/box.lwo")];
        assert_eq!(pick_scene(&lws, "").unwrap(), PathBuf::from("shot.lws"));
        let two = vec![PathBuf::from("a.lxs"), PathBuf::from("b.igs")];
        let e = pick_scene(&two, "").unwrap_err();
        assert!(e.to_string().contains("several"), "{e}");
    }
}
