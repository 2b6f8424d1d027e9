//! Scene bundles: the bytes a client uploads (a raw .lxs, a .zip or a .tar) unpacked safely into
//! a staging directory, then stored content-addressed as a canonical tar.
//!
//! Safety rules, for every entry: no absolute path, no `..`, no empty or odd component, no
//! symlink, hard link or device; sizes checked while reading (headers are not trusted), the
//! total unpacked size and the entry count bounded (decompression bombs).

use crate::error::{Result, ServerError};
use sha2::{Digest, Sha256};
use std::fs;
use std::io::{self, Read, Write};
use std::path::{Component, Path, PathBuf};

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
        return Err(ServerError::Unsupported(format!(
            "{file_name}: compressed tar is not accepted; send a .tar, .zip or .lxs"
        )));
    }
    if bytes.is_empty() {
        return Err(ServerError::BadRequest(format!(
            "{file_name}: empty upload"
        )));
    }
    let head = &bytes[..bytes.len().min(64 * 1024)];
    if head.contains(&0) || std::str::from_utf8(head).is_err() && head.len() == bytes.len() {
        return Err(ServerError::Unsupported(format!(
            "{file_name}: not a scene: expected a .lxs text file, a .zip or a .tar"
        )));
    }
    Ok(Kind::Lxs)
}

/// Checks an entry name and turns it into a relative path made of normal components only.
pub fn safe_relative(name: &str) -> Result<PathBuf> {
    let bad = |why: &str| ServerError::BadRequest(format!("bundle entry {name:?}: {why}"));
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
            return Err(ServerError::TooLarge(format!(
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
                    ServerError::BadRequest(format!("bundle entry {} repeated", dest.display()))
                }
                _ => ServerError::Io(e),
            })?;
        let left = self.limits.max_unpacked.saturating_sub(self.bytes);
        let n = io::copy(&mut (&mut r).take(left + 1), &mut f)
            .map_err(|e| ServerError::BadRequest(format!("bundle unreadable: {e}")))?;
        self.bytes += n;
        if self.bytes > self.limits.max_unpacked {
            return Err(ServerError::TooLarge(format!(
                "bundle unpacks to more than {} bytes",
                self.limits.max_unpacked
            )));
        }
        Ok(())
    }
}

/// Unpacks an upload into `dest` (an empty directory). A raw scene is stored as `file_name`
/// (its base name). Returns the relative paths of the files written.
pub fn unpack(bytes: &[u8], file_name: &str, dest: &Path, limits: Limits) -> Result<Vec<PathBuf>> {
    let mut budget = Budget {
        limits,
        bytes: 0,
        entries: 0,
    };
    match detect(bytes, file_name)? {
        Kind::Lxs => {
            let base = Path::new(file_name)
                .file_name()
                .and_then(|s| s.to_str())
                .filter(|s| s.ends_with(".lxs"))
                .unwrap_or("scene.lxs");
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
    let bad = |e: zip::result::ZipError| ServerError::BadRequest(format!("bad zip: {e}"));
    let mut archive = zip::ZipArchive::new(io::Cursor::new(bytes)).map_err(bad)?;
    let mut files = Vec::new();
    for i in 0..archive.len() {
        budget.entry()?;
        let entry = archive.by_index(i).map_err(bad)?;
        let name = entry.name().map_err(bad)?.to_string();
        let rel = safe_relative(&name)?;
        if entry.is_symlink() {
            return Err(ServerError::BadRequest(format!(
                "bundle entry {name:?}: symlink refused"
            )));
        }
        if entry.is_dir() {
            fs::create_dir_all(dest.join(&rel))?;
            continue;
        }
        if !entry.is_file() {
            return Err(ServerError::BadRequest(format!(
                "bundle entry {name:?}: not a regular file"
            )));
        }
        budget.copy(entry, &dest.join(&rel))?;
        files.push(rel);
    }
    Ok(files)
}

fn unpack_tar(bytes: &[u8], dest: &Path, budget: &mut Budget) -> Result<Vec<PathBuf>> {
    let bad = |e: io::Error| ServerError::BadRequest(format!("bad tar: {e}"));
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
                return Err(ServerError::BadRequest(format!(
                    "bundle entry {name:?}: {other:?} refused (only regular files and directories)"
                )))
            }
        }
    }
    Ok(files)
}

/// Picks the scene among the unpacked files: `wanted` when given, else the only `.lxs` at the
/// shallowest depth.
pub fn pick_scene(files: &[PathBuf], wanted: &str) -> Result<PathBuf> {
    if !wanted.is_empty() {
        let rel = safe_relative(wanted)?;
        return files
            .iter()
            .find(|f| **f == rel)
            .cloned()
            .ok_or_else(|| ServerError::BadRequest(format!("scene {wanted:?} not in bundle")));
    }
    let lxs: Vec<&PathBuf> = files
        .iter()
        .filter(|f| f.extension().is_some_and(|e| e.eq_ignore_ascii_case("lxs")))
        .collect();
    let depth = lxs.iter().map(|f| f.components().count()).min();
    let top: Vec<&&PathBuf> = lxs
        .iter()
        .filter(|f| Some(f.components().count()) == depth)
        .collect();
    match top.as_slice() {
        [one] => Ok((**one).clone()),
        [] => Err(ServerError::BadRequest(
            "not a scene: the bundle holds no .lxs file".into(),
        )),
        _ => Err(ServerError::BadRequest(format!(
            "the bundle holds several .lxs files ({}); name one with `scene`",
            top.iter()
                .map(|f| f.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ))),
    }
}

/// A writer that hashes what passes through.
struct HashWriter<W> {
    inner: W,
    hasher: Sha256,
}

impl<W: Write> Write for HashWriter<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.hasher.update(&buf[..n]);
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

/// Writes the files (relative to `root`) as a canonical tar (sorted, fixed metadata) to `out`
/// and returns its sha256 in hex: the same content always gives the same hash.
pub fn write_canonical_tar(root: &Path, files: &[PathBuf], out: &Path) -> Result<String> {
    let mut sorted = files.to_vec();
    sorted.sort();
    sorted.dedup();
    let file = fs::File::create(out)?;
    let hw = HashWriter {
        inner: io::BufWriter::new(file),
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
        hasher.update(&buf[..n]);
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
    fn unsafe_names_are_refused() {
        for name in ["/etc/passwd", "../x.lxs", "a/../../x", "C:\\x", "\\abs", ""] {
            assert!(safe_relative(name).is_err(), "{name}");
        }
        assert_eq!(
            safe_relative("./a/b.ply").unwrap(),
            PathBuf::from("a/b.ply")
        );
    }

    #[test]
    fn tar_symlink_refused() {
        let mut b = tar::Builder::new(Vec::new());
        let mut h = tar::Header::new_ustar();
        h.set_entry_type(tar::EntryType::Symlink);
        h.set_size(0);
        b.append_link(&mut h, "link.lxs", "/etc/passwd").unwrap();
        let bytes = b.into_inner().unwrap();
        let dir = tempfile::tempdir().unwrap();
        let e = unpack(&bytes, "x.tar", dir.path(), Limits::default()).unwrap_err();
        assert!(e.to_string().contains("refused"), "{e}");
    }

    #[test]
    fn bomb_bounded() {
        let mut w = zip::ZipWriter::new(io::Cursor::new(Vec::new()));
        let opts = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated);
        w.start_file("big.lxs", opts).unwrap();
        w.write_all(&vec![b' '; 1 << 20]).unwrap();
        let bytes = w.finish().unwrap().into_inner();
        assert!(bytes.len() < 1 << 14);
        let dir = tempfile::tempdir().unwrap();
        let limits = Limits {
            max_unpacked: 1 << 16,
            max_entries: 10,
        };
        let e = unpack(&bytes, "x.zip", dir.path(), limits).unwrap_err();
        assert!(matches!(e, ServerError::TooLarge(_)), "{e}");
    }

    #[test]
    fn canonical_tar_hash_is_stable() {
        let dir = tempfile::tempdir().unwrap();
        fs::write(dir.path().join("a.lxs"), "WorldBegin\nWorldEnd\n").unwrap();
        let files = vec![PathBuf::from("a.lxs")];
        let h1 = write_canonical_tar(dir.path(), &files, &dir.path().join("1.tar")).unwrap();
        let h2 = write_canonical_tar(dir.path(), &files, &dir.path().join("2.tar")).unwrap();
        assert_eq!(h1, h2);
        assert!(is_hash(&h1));
        assert_eq!(hash_file(&dir.path().join("1.tar")).unwrap(), h1);
    }

    #[test]
    fn pick_scene_rules() {
        let files = vec![PathBuf::from("s.lxs"), PathBuf::from("inc/geo.lxs")];
        assert_eq!(pick_scene(&files, "").unwrap(), PathBuf::from("s.lxs"));
        assert!(pick_scene(&[PathBuf::from("a.ply")], "").is_err());
    }
}
