//! Opening the files a scene names (meshes, image maps, environment maps, nk data, and the
//! files of any importer): the one place where a name written in a scene becomes an open file.
//!
//! ```text
//! name in the scene --SceneFiles::resolve (relative to the scene's directory; when confined:
//!     no absolute path, lexically inside the root, canonical path inside the root)-->
//!     path --regular file? size within the bound?--> open file / bytes
//! ```
//!
//! A local render ([`SceneFiles::unconfined`]) resolves names as LuxRender does: relative to the
//! scene's directory, absolute paths as they are. A farm ([`SceneFiles::confined`]: the master
//! at submission, a worker at load) confines every name to the bundle's root directory, and its
//! errors show the name as the scene wrote it, never a path of the host. Both refuse anything
//! but a regular file (a device such as `/dev/zero`, a FIFO, a directory) before opening it,
//! and read at most [`SceneFiles::max_bytes`].
//!
//! The build contexts (`ShapeCtx`, `MaterialCtx`, `TextureCtx`) and the light builder carry a
//! `SceneFiles`, so every plugin opens its files through it.

use std::fs::File;
use std::io::Read;
use std::path::{Component, Path, PathBuf};

/// The largest file a confined scene may name (bytes): a bundle never unpacks to more.
pub const CONFINED_MAX_BYTES: u64 = 4 << 30;

/// Why a file named by a scene cannot be read. Messages name the file as the scene wrote it
/// (callers add the scene location).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum FileError {
    /// An absolute path in a confined scene.
    #[error("\"{name}\" is an absolute path: files must be inside the scene's directory")]
    Absolute { name: String },
    /// A name that leaves the confinement root (`..`, or a symlink pointing out).
    #[error("\"{name}\" leaves the scene's directory")]
    Outside { name: String },
    /// Nothing at that name.
    #[error("\"{name}\" not found{shown}")]
    NotFound { name: String, shown: String },
    /// A directory, device, FIFO or socket.
    #[error("\"{name}\" is not a regular file")]
    NotRegular { name: String },
    /// Larger than the bound.
    #[error("\"{name}\" is {size} bytes, more than the limit of {max}")]
    TooLarge { name: String, size: u64, max: u64 },
    /// An empty name.
    #[error("empty file name")]
    Empty,
    /// Reading failed.
    #[error("\"{name}\": {message}")]
    Io { name: String, message: String },
}

/// Where the files of one scene are found, and how far they may be looked for.
#[derive(Clone, Debug)]
pub struct SceneFiles {
    /// Directory relative names resolve against (the scene's directory).
    base: PathBuf,
    /// Canonical confinement root, when confined.
    root: Option<PathBuf>,
    /// Largest file read.
    max_bytes: u64,
}

impl Default for SceneFiles {
    /// Unconfined, relative to the working directory.
    fn default() -> Self {
        SceneFiles::unconfined(PathBuf::new())
    }
}

impl From<&Path> for SceneFiles {
    fn from(base: &Path) -> Self {
        SceneFiles::unconfined(base)
    }
}

impl From<PathBuf> for SceneFiles {
    fn from(base: PathBuf) -> Self {
        SceneFiles::unconfined(base)
    }
}

impl From<&PathBuf> for SceneFiles {
    fn from(base: &PathBuf) -> Self {
        SceneFiles::unconfined(base.clone())
    }
}

impl From<&SceneFiles> for SceneFiles {
    fn from(files: &SceneFiles) -> Self {
        files.clone()
    }
}

impl FileError {
    /// The reason alone, without the file name (for messages that name the file already).
    pub fn reason(&self) -> String {
        match self {
            FileError::Absolute { .. } => {
                "an absolute path: files must be inside the scene's directory".into()
            }
            FileError::Outside { .. } => "leaves the scene's directory".into(),
            FileError::NotFound { shown, .. } => format!("not found{shown}"),
            FileError::NotRegular { .. } => "not a regular file".into(),
            FileError::TooLarge { size, max, .. } => {
                format!("{size} bytes, more than the limit of {max}")
            }
            FileError::Empty => "empty file name".into(),
            FileError::Io { message, .. } => message.clone(),
        }
    }
}

impl SceneFiles {
    /// A local scene: names relative to `base`, absolute names as they are, no size bound.
    pub fn unconfined(base: impl Into<PathBuf>) -> SceneFiles {
        SceneFiles {
            base: base.into(),
            root: None,
            max_bytes: u64::MAX,
        }
    }

    /// An untrusted scene: names relative to `base`, which must lie inside `root`, and every
    /// file inside `root` (symlinks resolved), at most [`CONFINED_MAX_BYTES`].
    pub fn confined(root: &Path, base: &Path) -> std::io::Result<SceneFiles> {
        let root = root.canonicalize()?;
        let base_abs = base.canonicalize()?;
        if !base_abs.starts_with(&root) {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "the scene's directory is outside its confinement root",
            ));
        }
        Ok(SceneFiles {
            base: base_abs,
            root: Some(root),
            max_bytes: CONFINED_MAX_BYTES,
        })
    }

    /// The same, reading at most `max` bytes per file.
    pub fn with_max_bytes(mut self, max: u64) -> SceneFiles {
        self.max_bytes = max;
        self
    }

    /// The directory relative names resolve against.
    pub fn base_dir(&self) -> &Path {
        &self.base
    }

    /// True when names are confined to a root.
    pub fn is_confined(&self) -> bool {
        self.root.is_some()
    }

    /// The largest file read (bytes).
    pub fn max_bytes(&self) -> u64 {
        self.max_bytes
    }

    /// The path of the regular file `name` names (canonical when confined), checked as
    /// [`SceneFiles::open`] checks it, without opening it.
    pub fn resolve(&self, name: &str) -> Result<PathBuf, FileError> {
        let path = self.locate(name)?;
        let meta = std::fs::metadata(&path).map_err(|e| self.io_error(name, &path, &e))?;
        self.check_meta(name, &meta)?;
        Ok(path)
    }

    /// True when `name` resolves to a readable regular file within the bounds.
    pub fn exists(&self, name: &str) -> bool {
        self.resolve(name).is_ok()
    }

    /// Opens the regular file `name` names; returns it with its size.
    pub fn open(&self, name: &str) -> Result<(File, u64), FileError> {
        let path = self.resolve(name)?;
        let file = File::open(&path).map_err(|e| self.io_error(name, &path, &e))?;
        // The open file itself is checked again (it may have changed since the lookup).
        let meta = file
            .metadata()
            .map_err(|e| self.io_error(name, &path, &e))?;
        self.check_meta(name, &meta)?;
        Ok((file, meta.len()))
    }

    /// The whole content of the file `name` names, at most [`SceneFiles::max_bytes`].
    pub fn read(&self, name: &str) -> Result<Vec<u8>, FileError> {
        let (file, size) = self.open(name)?;
        let mut out = Vec::with_capacity(usize::try_from(size).unwrap_or(0).min(1 << 30));
        let n = file
            .take(self.max_bytes.saturating_add(1))
            .read_to_end(&mut out)
            .map_err(|e| FileError::Io {
                name: name.to_string(),
                message: e.to_string(),
            })?;
        if n as u64 > self.max_bytes {
            return Err(FileError::TooLarge {
                name: name.to_string(),
                size: n as u64,
                max: self.max_bytes,
            });
        }
        Ok(out)
    }

    /// The content of the small text file `name` names (lens, camera response, spectral and
    /// nk data), refused above `max` bytes as well as above [`SceneFiles::max_bytes`].
    pub fn read_small_text(&self, name: &str, max: u64) -> Result<String, FileError> {
        let limited = SceneFiles {
            max_bytes: self.max_bytes.min(max),
            ..self.clone()
        };
        limited.read_to_string(name)
    }

    /// The content of the file `name` names as UTF-8 text.
    pub fn read_to_string(&self, name: &str) -> Result<String, FileError> {
        String::from_utf8(self.read(name)?).map_err(|_| FileError::Io {
            name: name.to_string(),
            message: "not UTF-8 text".into(),
        })
    }

    /// The path `name` designates, confinement checked (lexically, then with symlinks
    /// resolved); not yet checked to be a regular file.
    fn locate(&self, name: &str) -> Result<PathBuf, FileError> {
        if name.is_empty() {
            return Err(FileError::Empty);
        }
        let rel = Path::new(name);
        let Some(root) = &self.root else {
            return Ok(self.base.join(rel));
        };
        if rel.has_root() || rel.is_absolute() || name.contains('\0') {
            return Err(FileError::Absolute {
                name: name.to_string(),
            });
        }
        // Checked before touching the file system: whether an outside file exists is not
        // revealed.
        if !lexically_inside(&self.base.join(rel), root) {
            return Err(FileError::Outside {
                name: name.to_string(),
            });
        }
        let canonical = self
            .base
            .join(rel)
            .canonicalize()
            .map_err(|e| self.io_error(name, Path::new(""), &e))?;
        if !canonical.starts_with(root) {
            return Err(FileError::Outside {
                name: name.to_string(),
            });
        }
        Ok(canonical)
    }

    fn check_meta(&self, name: &str, meta: &std::fs::Metadata) -> Result<(), FileError> {
        if !meta.is_file() {
            return Err(FileError::NotRegular {
                name: name.to_string(),
            });
        }
        if meta.len() > self.max_bytes {
            return Err(FileError::TooLarge {
                name: name.to_string(),
                size: meta.len(),
                max: self.max_bytes,
            });
        }
        Ok(())
    }

    /// An I/O error about `name`; the host path is shown only for a local (unconfined) scene.
    fn io_error(&self, name: &str, path: &Path, e: &std::io::Error) -> FileError {
        let shown = if self.root.is_none() && path != Path::new(name) {
            format!(" ({})", path.display())
        } else {
            String::new()
        };
        match e.kind() {
            std::io::ErrorKind::NotFound => FileError::NotFound {
                name: name.to_string(),
                shown,
            },
            _ if self.root.is_some() => FileError::Io {
                name: name.to_string(),
                message: e.kind().to_string(),
            },
            _ => FileError::Io {
                name: name.to_string(),
                message: format!("{e}{shown}"),
            },
        }
    }
}

/// True when `path`, with `.` and `..` applied lexically, stays under `root`.
fn lexically_inside(path: &Path, root: &Path) -> bool {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                if !out.pop() {
                    return false;
                }
            }
            other => out.push(other.as_os_str()),
        }
    }
    out.starts_with(root)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs;

    /// A root with `scene/` inside, a file in it, a file beside the root and a symlink out.
    fn tree() -> (tempfile::TempDir, SceneFiles) {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().join("root");
        fs::create_dir_all(root.join("scene/sub")).unwrap();
        fs::write(root.join("scene/sub/m.ply"), b"ply\n").unwrap();
        fs::write(root.join("shared.png"), b"png").unwrap();
        fs::write(dir.path().join("secret.exr"), b"secret").unwrap();
        std::os::unix::fs::symlink(dir.path().join("secret.exr"), root.join("scene/link.exr"))
            .unwrap();
        let files = SceneFiles::confined(&root, &root.join("scene")).unwrap();
        (dir, files)
    }

    #[test]
    fn confined_names_resolve_inside_the_root() {
        let (_d, files) = tree();
        assert_eq!(files.read("sub/m.ply").unwrap(), b"ply\n");
        assert_eq!(files.read("./sub/../sub/m.ply").unwrap(), b"ply\n");
        // Up from the scene's directory, still inside the root.
        assert_eq!(files.read("../shared.png").unwrap(), b"png");
    }

    #[test]
    fn confined_scene_cannot_reach_outside_files() {
        let (d, files) = tree();
        let secret = d.path().join("secret.exr");
        let abs = secret.to_str().unwrap();
        assert!(matches!(files.read(abs), Err(FileError::Absolute { .. })));
        assert!(matches!(
            files.read("../../secret.exr"),
            Err(FileError::Outside { .. })
        ));
        // The same error whether or not the outside file exists.
        assert!(matches!(
            files.read("../../missing.exr"),
            Err(FileError::Outside { .. })
        ));
        assert!(matches!(
            files.read("link.exr"),
            Err(FileError::Outside { .. })
        ));
        for name in ["/etc/passwd", "/dev/zero", "/root/.ssh/id_rsa"] {
            let e = files.read(name).unwrap_err();
            assert!(matches!(e, FileError::Absolute { .. }), "{name}: {e}");
        }
    }

    #[test]
    fn errors_never_show_host_paths_when_confined() {
        let (d, files) = tree();
        let host = d.path().to_str().unwrap().to_string();
        for name in ["missing.ply", "sub", "../../secret.exr", "link.exr"] {
            let e = files.read(name).unwrap_err().to_string();
            assert!(!e.contains(&host), "{name}: {e}");
            assert!(e.contains(name), "{name}: {e}");
        }
    }

    #[test]
    fn only_regular_files_within_the_size_bound() {
        let (_d, files) = tree();
        assert!(matches!(
            files.read("sub"),
            Err(FileError::NotRegular { .. })
        ));
        let small = files.clone().with_max_bytes(2);
        assert!(matches!(
            small.read("sub/m.ply"),
            Err(FileError::TooLarge { size: 4, .. })
        ));
        // Devices are refused unconfined too, before anything is read.
        let local = SceneFiles::unconfined("/");
        assert!(matches!(
            local.read("/dev/zero"),
            Err(FileError::NotRegular { .. })
        ));
        assert!(matches!(local.read(""), Err(FileError::Empty)));
    }

    #[test]
    fn unconfined_names_resolve_as_luxrender_does() {
        let (d, _) = tree();
        let local = SceneFiles::unconfined(d.path().join("root/scene"));
        assert_eq!(local.read("sub/m.ply").unwrap(), b"ply\n");
        let abs = d.path().join("secret.exr");
        assert_eq!(local.read(abs.to_str().unwrap()).unwrap(), b"secret");
        let e = local.read("nope.ply").unwrap_err().to_string();
        assert!(e.contains("nope.ply"), "{e}");
    }

    #[test]
    fn a_base_outside_the_root_is_refused() {
        let (d, _) = tree();
        assert!(SceneFiles::confined(&d.path().join("root/scene"), d.path()).is_err());
    }

    #[test]
    fn lexical_containment() {
        let root = Path::new("/r/a");
        assert!(lexically_inside(Path::new("/r/a/b/../c"), root));
        assert!(!lexically_inside(Path::new("/r/a/../b"), root));
        assert!(!lexically_inside(Path::new("/r/ab"), root));
        assert!(lexically_inside(Path::new("/r/a"), root));
    }
}
