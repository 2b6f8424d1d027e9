//! Scene bundles cached on disk by content hash: downloaded once, checked against their hash,
//! unpacked with the master's safety rules (both from `luxfarm-wire`), and checked again
//! before each use: the cached files must still hash to the bundle's name (a cache in a
//! shared temporary directory could have been changed), else the bundle is fetched again.
//! The default cache directory is the user's own (mode 0700).

use anyhow::{bail, Context};
use luxfarm_wire::bundle;
use std::path::{Path, PathBuf};

/// The marker written once a bundle is completely unpacked.
const COMPLETE: &str = ".complete";

/// A number unique within this process, for temporary directory names.
fn unique() -> u64 {
    use std::sync::atomic::{AtomicU64, Ordering};
    static NEXT: AtomicU64 = AtomicU64::new(0);
    NEXT.fetch_add(1, Ordering::Relaxed)
}

/// The bundle cache directory.
pub struct Cache {
    dir: PathBuf,
}

impl Cache {
    /// A cache in `dir` (default: `$TMPDIR/luxfarm-worker-cache-UID`, private to the user).
    pub fn new(dir: Option<PathBuf>) -> anyhow::Result<Cache> {
        let dir = dir.unwrap_or_else(|| {
            // SAFETY: getuid has no preconditions and cannot fail.
            let uid = unsafe { libc::getuid() };
            std::env::temp_dir().join(format!("luxfarm-worker-cache-{uid}"))
        });
        std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o700))
            .with_context(|| format!("making {} private", dir.display()))?;
        Ok(Cache { dir })
    }

    /// The unpacked directory of a bundle when cached and still intact (its files hash to
    /// `hash`); a damaged copy is removed.
    pub fn get(&self, hash: &str) -> Option<PathBuf> {
        if !bundle::is_hash(hash) {
            return None;
        }
        let d = self.dir.join(hash);
        if !d.join(COMPLETE).exists() {
            return None;
        }
        match bundle::hash_dir(&d, COMPLETE) {
            Ok(h) if h == hash => Some(d),
            other => {
                tracing::warn!(bundle = %hash, found = ?other.ok(), "cached bundle changed; fetching it again");
                let _ = std::fs::remove_dir_all(&d);
                None
            }
        }
    }

    /// Stores downloaded tar bytes after checking them against `hash`; returns the directory.
    pub fn put(&self, hash: &str, tar: &[u8]) -> anyhow::Result<PathBuf> {
        if !bundle::is_hash(hash) {
            bail!("not a bundle hash: {hash:?}");
        }
        let got = bundle::sha256_hex(tar);
        if got != hash {
            bail!("bundle {hash} arrived with hash {got}");
        }
        // Several workers may share one cache (`luxfarm render --workers N` runs them in one
        // process): each unpacks into its own temporary directory, and a bundle already in
        // place (another worker's, still in use) is never removed while it is intact.
        let tmp = self
            .dir
            .join(format!(".tmp-{hash}-{}-{}", std::process::id(), unique()));
        if tmp.exists() {
            std::fs::remove_dir_all(&tmp)?;
        }
        std::fs::create_dir_all(&tmp)?;
        let unpacked = bundle::unpack(tar, "bundle.tar", &tmp, bundle::Limits::default())
            .map_err(|e| anyhow::anyhow!("unpacking bundle {hash}: {e}"))
            .and_then(|_| Ok(std::fs::write(tmp.join(COMPLETE), b"")?));
        if let Err(e) = unpacked {
            let _ = std::fs::remove_dir_all(&tmp);
            return Err(e);
        }
        if let Some(d) = self.get(hash) {
            let _ = std::fs::remove_dir_all(&tmp);
            return Ok(d);
        }
        let dest = self.dir.join(hash);
        if let Err(e) = std::fs::rename(&tmp, &dest) {
            // Another worker placed the same bundle between our check and the rename.
            let _ = std::fs::remove_dir_all(&tmp);
            return self
                .get(hash)
                .with_context(|| format!("placing bundle {hash} in the cache: {e}"));
        }
        Ok(dest)
    }

    /// The cache directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A canonical bundle tar of one scene file, and its hash.
    fn bundle_tar() -> (Vec<u8>, String) {
        let src = tempfile::tempdir().unwrap();
        std::fs::write(src.path().join("s.lxs"), "WorldBegin\nWorldEnd\n").unwrap();
        let out = src.path().join("b.tar");
        let hash =
            bundle::write_canonical_tar(src.path(), &[PathBuf::from("s.lxs")], &out).unwrap();
        (std::fs::read(out).unwrap(), hash)
    }

    #[test]
    fn workers_sharing_a_cache_never_pull_a_bundle_from_under_each_other() {
        let dir = tempfile::tempdir().unwrap();
        let cache = std::sync::Arc::new(Cache::new(Some(dir.path().join("c"))).unwrap());
        let (tar, hash) = bundle_tar();
        let threads: Vec<_> = (0..4)
            .map(|_| {
                let (cache, tar, hash) = (cache.clone(), tar.clone(), hash.clone());
                std::thread::spawn(move || {
                    for _ in 0..25 {
                        let d = cache.put(&hash, &tar).unwrap();
                        // The scene must be readable the moment put returns, whatever the
                        // other workers are doing.
                        std::fs::read(d.join("s.lxs")).unwrap();
                    }
                })
            })
            .collect();
        for t in threads {
            t.join().unwrap();
        }
        assert!(cache.get(&hash).is_some());
        let leftovers: Vec<_> = std::fs::read_dir(dir.path().join("c"))
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .filter(|n| n.to_string_lossy().starts_with(".tmp-"))
            .collect();
        assert!(leftovers.is_empty(), "{leftovers:?}");
    }

    #[test]
    fn a_changed_cached_bundle_is_not_trusted() {
        let dir = tempfile::tempdir().unwrap();
        let cache = Cache::new(Some(dir.path().join("c"))).unwrap();
        let (tar, hash) = bundle_tar();
        let d = cache.put(&hash, &tar).unwrap();
        assert_eq!(cache.get(&hash), Some(d.clone()));
        // Someone rewrites the scene and leaves the marker in place.
        std::fs::write(d.join("s.lxs"), "Include \"/etc/passwd\"\n").unwrap();
        assert_eq!(cache.get(&hash), None);
        assert!(!d.exists());
        // An added file is a change too.
        let d = cache.put(&hash, &tar).unwrap();
        std::fs::write(d.join("extra.ply"), "x").unwrap();
        assert_eq!(cache.get(&hash), None);
        // The directory is private.
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(dir.path().join("c"))
            .unwrap()
            .permissions()
            .mode();
        assert_eq!(mode & 0o777, 0o700);
    }
}
