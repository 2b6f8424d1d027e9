//! Scene bundles cached on disk by content hash: downloaded once, checked against their hash,
//! unpacked with the master's safety rules (both from `luxfarm-wire`).

use anyhow::{bail, Context};
use luxfarm_wire::bundle;
use std::path::{Path, PathBuf};

/// The bundle cache directory.
pub struct Cache {
    dir: PathBuf,
}

impl Cache {
    /// A cache in `dir` (default: `$TMPDIR/luxfarm-worker-cache`).
    pub fn new(dir: Option<PathBuf>) -> anyhow::Result<Cache> {
        let dir = dir.unwrap_or_else(|| std::env::temp_dir().join("luxfarm-worker-cache"));
        std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
        Ok(Cache { dir })
    }

    /// The unpacked directory of a bundle when cached.
    pub fn get(&self, hash: &str) -> Option<PathBuf> {
        let d = self.dir.join(hash);
        (bundle::is_hash(hash) && d.join(".complete").exists()).then_some(d)
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
        let tmp = self.dir.join(format!(".tmp-{hash}-{}", std::process::id()));
        if tmp.exists() {
            std::fs::remove_dir_all(&tmp)?;
        }
        std::fs::create_dir_all(&tmp)?;
        bundle::unpack(tar, "bundle.tar", &tmp, bundle::Limits::default())
            .map_err(|e| anyhow::anyhow!("unpacking bundle {hash}: {e}"))?;
        std::fs::write(tmp.join(".complete"), b"")?;
        let dest = self.dir.join(hash);
        if dest.exists() {
            std::fs::remove_dir_all(&tmp)?;
        } else {
            std::fs::rename(&tmp, &dest)?;
        }
        Ok(dest)
    }

    /// The cache directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }
}
