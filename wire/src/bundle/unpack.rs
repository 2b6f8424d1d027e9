//! Unpacking an upload (a raw .lxs, a .zip or a .tar) into an empty staging directory.
//!
//! Every entry name passes [`safe_relative`]; symlinks, hard links and devices are refused;
//! sizes are counted while the bytes are copied (archive headers are not trusted), and the
//! total unpacked size and the entry count are bounded by [`Limits`] (decompression bombs).
//! Files are created with `create_new`, so a repeated entry cannot overwrite an earlier one.

use super::{detect, safe_relative, Kind, Limits};
use crate::{Result, WireError};
use std::fs;
use std::io::{self, Read};
use std::path::{Path, PathBuf};

/// Tracks the unpacked bytes and entry count against the limits.
struct Budget {
    limits: Limits,
    bytes: u64,
    entries: usize,
}

impl Budget {
    fn entry(&mut self) -> Result<()> {
        self.entries += 1;
        if self.entries > self.limits.max_entries {
            return Err(WireError::TooLarge(format!(
                "bundle has more than {} entries",
                self.limits.max_entries
            )));
        }
        Ok(())
    }

    /// Copies `r` into a new file at `dest`, never writing more than the remaining budget.
    fn copy(&mut self, mut r: impl Read, dest: &Path) -> Result<()> {
        if let Some(parent) = dest.parent() {
            fs::create_dir_all(parent)?;
        }
        let mut f = fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(dest)
            .map_err(|e| match e.kind() {
                io::ErrorKind::AlreadyExists => {
                    WireError::Bundle(format!("bundle entry {} repeated", dest.display()))
                }
                _ => WireError::Io(e),
            })?;
        let left = self.limits.max_unpacked.saturating_sub(self.bytes);
        let n = io::copy(&mut (&mut r).take(left + 1), &mut f)
            .map_err(|e| WireError::Bundle(format!("bundle unreadable: {e}")))?;
        self.bytes += n;
        if self.bytes > self.limits.max_unpacked {
            return Err(WireError::TooLarge(format!(
                "bundle unpacks to more than {} bytes",
                self.limits.max_unpacked
            )));
        }
        Ok(())
    }
}

/// Unpacks an upload into `dest` (an empty directory). A raw scene is stored as `file_name`'s
/// base name when it has a scene extension (`.lxs`, `.igs`, ...), else as `scene.` with the
/// extension of the format its content shows (`.lxs` by default). Returns the relative paths
/// of the files written.
pub fn unpack(bytes: &[u8], file_name: &str, dest: &Path, limits: Limits) -> Result<Vec<PathBuf>> {
    let mut budget = Budget {
        limits,
        bytes: 0,
        entries: 0,
    };
    match detect(bytes, file_name)? {
        Kind::Lxs => {
            let format = luxfarm::formats::detect_content(bytes)
                .unwrap_or(luxfarm::formats::SceneFormat::Lxs);
            let by_content = format!("scene.{}", format.extension());
            let base = Path::new(file_name)
                .file_name()
                .and_then(|s| s.to_str())
                .filter(|s| super::is_scene_file(Path::new(s)))
                .unwrap_or(&by_content);
            let rel = safe_relative(base)?;
            budget.entry()?;
            budget.copy(bytes, &dest.join(&rel))?;
            Ok(vec![rel])
        }
        Kind::Zip => unpack_zip(bytes, dest, &mut budget),
        Kind::Tar => unpack_tar(bytes, dest, &mut budget),
    }
}

fn unpack_zip(bytes: &[u8], dest: &Path, budget: &mut Budget) -> Result<Vec<PathBuf>> {
    let bad = |e: zip::result::ZipError| WireError::Bundle(format!("bad zip: {e}"));
    let mut archive = zip::ZipArchive::new(io::Cursor::new(bytes)).map_err(bad)?;
    let mut files = Vec::new();
    for i in 0..archive.len() {
        budget.entry()?;
        let entry = archive.by_index(i).map_err(bad)?;
        let name = entry.name().map_err(bad)?.to_string();
        let rel = safe_relative(&name)?;
        if entry.is_symlink() {
            return Err(WireError::Bundle(format!(
                "bundle entry {name:?}: symlink refused"
            )));
        }
        if entry.is_dir() {
            fs::create_dir_all(dest.join(&rel))?;
            continue;
        }
        if !entry.is_file() {
            return Err(WireError::Bundle(format!(
                "bundle entry {name:?}: not a regular file"
            )));
        }
        budget.copy(entry, &dest.join(&rel))?;
        files.push(rel);
    }
    Ok(files)
}

fn unpack_tar(bytes: &[u8], dest: &Path, budget: &mut Budget) -> Result<Vec<PathBuf>> {
    let bad = |e: io::Error| WireError::Bundle(format!("bad tar: {e}"));
    let mut archive = tar::Archive::new(bytes);
    let mut files = Vec::new();
    for entry in archive.entries().map_err(bad)? {
        budget.entry()?;
        let entry = entry.map_err(bad)?;
        let name = String::from_utf8_lossy(&entry.path_bytes()).into_owned();
        let rel = safe_relative(&name)?;
        match entry.header().entry_type() {
            tar::EntryType::Directory => fs::create_dir_all(dest.join(&rel))?,
            tar::EntryType::Regular | tar::EntryType::Continuous => {
                budget.copy(entry, &dest.join(&rel))?;
                files.push(rel);
            }
            tar::EntryType::XGlobalHeader | tar::EntryType::XHeader => {}
            other => {
                return Err(WireError::Bundle(format!(
                    "bundle entry {name:?}: {other:?} refused (only regular files and directories)"
                )))
            }
        }
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    /// A tar holding one entry of `kind` named `name` (link target `/etc/passwd`).
    fn tar_with(name: &str, kind: tar::EntryType, data: &[u8]) -> Vec<u8> {
        let mut b = tar::Builder::new(Vec::new());
        let mut h = tar::Header::new_ustar();
        h.set_entry_type(kind);
        h.set_size(data.len() as u64);
        h.set_mode(0o644);
        if kind.is_symlink() || kind.is_hard_link() {
            b.append_link(&mut h, name, "/etc/passwd").unwrap();
        } else {
            b.append_data(&mut h, name, data).unwrap();
        }
        b.into_inner().unwrap()
    }

    /// A tar entry whose header names `name` as it is, bypassing the tar crate's own checks
    /// (as a hostile client would write it).
    fn raw_tar(name: &str, data: &[u8]) -> Vec<u8> {
        let mut h = tar::Header::new_ustar();
        h.as_old_mut().name[..name.len()].copy_from_slice(name.as_bytes());
        h.set_size(data.len() as u64);
        h.set_mode(0o644);
        h.set_entry_type(tar::EntryType::Regular);
        h.set_cksum();
        let mut out = h.as_bytes().to_vec();
        out.extend_from_slice(data);
        out.resize(out.len().div_ceil(512) * 512 + 1024, 0);
        out
    }

    fn zip_with(entries: &[(&str, &[u8])]) -> Vec<u8> {
        let mut w = zip::ZipWriter::new(io::Cursor::new(Vec::new()));
        let opts = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated);
        for (name, data) in entries {
            w.start_file(*name, opts).unwrap();
            w.write_all(data).unwrap();
        }
        w.finish().unwrap().into_inner()
    }

    #[test]
    fn links_and_devices_refused() {
        let dir = tempfile::tempdir().unwrap();
        for kind in [
            tar::EntryType::Symlink,
            tar::EntryType::Link,
            tar::EntryType::Char,
            tar::EntryType::Fifo,
        ] {
            let bytes = tar_with("link.lxs", kind, b"");
            let dest = dir.path().join(format!("{kind:?}"));
            let e = unpack(&bytes, "x.tar", &dest, Limits::default()).unwrap_err();
            assert!(e.to_string().contains("refused"), "{kind:?}: {e}");
            assert!(!dest.join("link.lxs").exists());
        }
    }

    #[test]
    fn zip_slip_and_absolute_names_refused() {
        let dir = tempfile::tempdir().unwrap();
        for name in ["../evil.lxs", "/abs.lxs", "a/../../evil.lxs"] {
            let dest = dir.path().join("z");
            let e = unpack(
                &zip_with(&[(name, b"x")]),
                "x.zip",
                &dest,
                Limits::default(),
            );
            assert!(matches!(e, Err(WireError::Bundle(_))), "{name}: {e:?}");
            let e = unpack(&raw_tar(name, b"x"), "x.tar", &dest, Limits::default());
            assert!(matches!(e, Err(WireError::Bundle(_))), "{name}: {e:?}");
        }
        assert!(!dir.path().join("evil.lxs").exists());
    }

    #[test]
    fn zip_bomb_bounded() {
        let bytes = zip_with(&[("big.lxs", &vec![b' '; 1 << 20])]);
        assert!(bytes.len() < 1 << 14);
        let dir = tempfile::tempdir().unwrap();
        let limits = Limits {
            max_unpacked: 1 << 16,
            max_entries: 10,
        };
        let e = unpack(&bytes, "x.zip", dir.path(), limits).unwrap_err();
        assert!(matches!(e, WireError::TooLarge(_)), "{e}");
        let written = fs::metadata(dir.path().join("big.lxs")).unwrap().len();
        assert!(written <= (1 << 16) + 1, "{written} bytes written");
    }

    #[test]
    fn entry_count_bounded() {
        let names: Vec<String> = (0..5).map(|i| format!("f{i}.ply")).collect();
        let entries: Vec<(&str, &[u8])> = names.iter().map(|n| (n.as_str(), &b"x"[..])).collect();
        let dir = tempfile::tempdir().unwrap();
        let limits = Limits {
            max_unpacked: 1 << 20,
            max_entries: 4,
        };
        let e = unpack(&zip_with(&entries), "x.zip", dir.path(), limits).unwrap_err();
        assert!(matches!(e, WireError::TooLarge(_)), "{e}");
    }

    #[test]
    fn repeated_entry_refused() {
        let bytes = zip_with(&[("a.lxs", b"1"), ("./a.lxs", b"2")]);
        let dir = tempfile::tempdir().unwrap();
        let e = unpack(&bytes, "x.zip", dir.path(), Limits::default()).unwrap_err();
        assert!(e.to_string().contains("repeated"), "{e}");
        assert_eq!(fs::read(dir.path().join("a.lxs")).unwrap(), b"1");
    }

    #[test]
    fn raw_scene_named_by_its_base_name() {
        let dir = tempfile::tempdir().unwrap();
        let files = unpack(
            b"WorldBegin\nWorldEnd\n",
            "../up/s.lxs",
            dir.path(),
            Limits::default(),
        )
        .unwrap();
        assert_eq!(files, vec![PathBuf::from("s.lxs")]);
        let other = tempfile::tempdir().unwrap();
        let files = unpack(
            b"WorldBegin\n",
            "notes.txt",
            other.path(),
            Limits::default(),
        )
        .unwrap();
        assert_eq!(files, vec![PathBuf::from("scene.lxs")]);
        let igs = tempfile::tempdir().unwrap();
        let files = unpack(
            b"<?xml version=\"1.0\"?>\n<scene></scene>",
            "upload",
            igs.path(),
            Limits::default(),
        )
        .unwrap();
        assert_eq!(files, vec![PathBuf::from("scene.igs")]);
        let named = tempfile::tempdir().unwrap();
        let files = unpack(
            b"<scene></scene>",
            "room.igs",
            named.path(),
            Limits::default(),
        )
        .unwrap();
        assert_eq!(files, vec![PathBuf::from("room.igs")]);
    }
}
