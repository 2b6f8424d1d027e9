//! Content addressing of bundles: the master stores every accepted bundle as a canonical tar
//! (sorted entries, fixed metadata) named by its sha256, so the same content always gets the
//! same name; a worker checks a fetched tar against that name before unpacking it.

use crate::Result;
use sha2::{Digest, Sha256};
use std::fs;
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};

/// A writer that hashes what passes through.
struct HashWriter<W> {
    inner: W,
    hasher: Sha256,
}

impl<W: Write> Write for HashWriter<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.hasher.update(buf.get(..n).unwrap_or(buf));
        Ok(n)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

/// Lowercase hex of bytes.
pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Hex sha256 of bytes in memory (a fetched bundle).
pub fn sha256_hex(bytes: &[u8]) -> String {
    hex(&Sha256::digest(bytes))
}

/// Writes the files (relative to `root`) as a canonical tar (sorted, fixed metadata) to `out`
/// and returns its sha256 in hex: the same content always gives the same hash.
pub fn write_canonical_tar(root: &Path, files: &[PathBuf], out: &Path) -> Result<String> {
    let file = fs::File::create(out)?;
    canonical_tar(root, files, io::BufWriter::new(file))
}

/// The sha256 of the canonical tar of every regular file under `root` but `skip` (the name a
/// bundle was stored under when `root` is its unpacked copy): how a worker checks, before
/// each use, that its cached copy of a bundle is still the bundle. A link or special file
/// under `root` is an error.
pub fn hash_dir(root: &Path, skip: &str) -> Result<String> {
    let mut files = Vec::new();
    list_files(root, Path::new(""), skip, &mut files)?;
    canonical_tar(root, &files, io::sink())
}

fn list_files(root: &Path, rel: &Path, skip: &str, out: &mut Vec<PathBuf>) -> Result<()> {
    for entry in fs::read_dir(root.join(rel))? {
        let entry = entry?;
        let name = rel.join(entry.file_name());
        let ty = entry.file_type()?;
        if rel.as_os_str().is_empty() && entry.file_name() == skip {
            continue;
        }
        if ty.is_dir() {
            list_files(root, &name, skip, out)?;
        } else if ty.is_file() {
            out.push(name);
        } else {
            return Err(crate::WireError::Bundle(format!(
                "{}: not a regular file",
                name.display()
            )));
        }
    }
    Ok(())
}

fn canonical_tar(root: &Path, files: &[PathBuf], out: impl Write) -> Result<String> {
    let mut sorted = files.to_vec();
    sorted.sort();
    sorted.dedup();
    let hw = HashWriter {
        inner: out,
        hasher: Sha256::new(),
    };
    let mut builder = tar::Builder::new(hw);
    builder.mode(tar::HeaderMode::Deterministic);
    for rel in &sorted {
        let mut f = fs::File::open(root.join(rel))?;
        let len = f.metadata()?.len();
        let mut header = tar::Header::new_ustar();
        header.set_size(len);
        header.set_mode(0o644);
        header.set_mtime(0);
        header.set_entry_type(tar::EntryType::Regular);
        builder.append_data(&mut header, rel, &mut f)?;
    }
    let mut hw = builder.into_inner()?;
    hw.flush()?;
    Ok(hex(&hw.hasher.finalize()))
}

/// Hex sha256 of a file's content.
pub fn hash_file(path: &Path) -> Result<String> {
    let mut f = fs::File::open(path)?;
    let mut hasher = Sha256::new();
    let mut buf = vec![0u8; 1 << 16];
    loop {
        let n = f.read(&mut buf)?;
        if n == 0 {
            break;
        }
        hasher.update(buf.get(..n).unwrap_or(&buf));
    }
    Ok(hex(&hasher.finalize()))
}

/// True when `s` looks like a content hash we produce (64 lowercase hex digits): hashes become
/// file names, so nothing else is accepted.
pub fn is_hash(s: &str) -> bool {
    s.len() == 64
        && s.bytes()
            .all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn canonical_tar_hash_is_stable() {
        let dir = tempfile::tempdir().unwrap();
        fs::write(dir.path().join("a.lxs"), "WorldBegin\nWorldEnd\n").unwrap();
        fs::create_dir(dir.path().join("m")).unwrap();
        fs::write(dir.path().join("m/b.ply"), "ply").unwrap();
        let files = vec![PathBuf::from("m/b.ply"), PathBuf::from("a.lxs")];
        let h1 = write_canonical_tar(dir.path(), &files, &dir.path().join("1.tar")).unwrap();
        let reversed: Vec<PathBuf> = files.iter().rev().cloned().collect();
        let h2 = write_canonical_tar(dir.path(), &reversed, &dir.path().join("2.tar")).unwrap();
        assert_eq!(h1, h2);
        assert!(is_hash(&h1));
        assert_eq!(hash_file(&dir.path().join("1.tar")).unwrap(), h1);
        let bytes = fs::read(dir.path().join("1.tar")).unwrap();
        assert_eq!(sha256_hex(&bytes), h1);
        // The unpacked directory hashes the same (the tars and a marker left out).
        fs::write(dir.path().join(".complete"), b"").unwrap();
        fs::remove_file(dir.path().join("1.tar")).unwrap();
        fs::remove_file(dir.path().join("2.tar")).unwrap();
        assert_eq!(hash_dir(dir.path(), ".complete").unwrap(), h1);
        fs::write(dir.path().join("m/b.ply"), "changed").unwrap();
        assert_ne!(hash_dir(dir.path(), ".complete").unwrap(), h1);
    }

    #[test]
    fn only_our_hashes_are_hashes() {
        assert!(is_hash(&"0123456789abcdef".repeat(4)));
        assert!(!is_hash(&"0123456789ABCDEF".repeat(4)));
        assert!(!is_hash("../../etc/passwd"));
        assert!(!is_hash(&"a".repeat(63)));
    }

    #[test]
    fn known_digest() {
        assert_eq!(
            sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }
}
