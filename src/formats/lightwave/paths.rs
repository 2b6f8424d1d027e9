//! Finding the files a scene names, the way LightWave's content directory works, and reading
//! them within the byte budget.
//!
//! ```text
//! name as written ("Objects/x.lwo", "../LWO/x.lwo", "F:fra/cornell/02.lwo", "C:\a\b.lwo")
//!   --split: drop the device ("F:"), backslashes as separators--> components
//!   --try: each suffix (whole path, then shorter, then the bare name)
//!          × each base (the scene's directory, then its parents)--> the first existing file
//! ```
//!
//! LightWave writes paths relative to a content directory the scene does not record (usually
//! the parent of `Scenes/`), or absolute with a device name. The search tries the scene's
//! directory and its parents with the whole path and then with shorter suffixes, so a scene
//! moved with its objects still finds them. With confinement (untrusted uploads) only the
//! scene's directory and what is below it is searched, and a candidate that resolves (symlinks
//! followed) outside it is never used. Images are also looked for beside the object file that
//! names them (an object and its images usually travel together).

use crate::lxs::{Loc, LxsError, LxsErrorKind};
use std::path::{Component, Path, PathBuf};

/// Most parent directories searched above the scene's directory (unconfined).
const MAX_PARENTS: usize = 4;

/// A file that was found.
#[derive(Clone, Debug, PartialEq)]
pub struct Found {
    /// The path as the scene's location makes it (for `SceneDescription::files`).
    pub display: PathBuf,
    /// The canonical path (cache key, confinement check).
    pub canonical: PathBuf,
    /// The path relative to the scene's directory when inside it (what texture `filename`
    /// parameters use), else the canonical path.
    pub from_scene: PathBuf,
}

pub struct Resolver {
    scene_dir: PathBuf,
    scene_dir_canonical: PathBuf,
    confined: bool,
}

impl Resolver {
    /// A resolver for the scene file `scene`.
    pub fn new(scene: &Path, confined: bool) -> Resolver {
        let scene_dir = match scene.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let scene_dir_canonical =
            std::fs::canonicalize(&scene_dir).unwrap_or_else(|_| scene_dir.clone());
        Resolver {
            scene_dir,
            scene_dir_canonical,
            confined,
        }
    }

    /// Finds the file LightWave means by `written`, else (images) the same suffixes in the
    /// directory of the object file that names it.
    pub fn find_near(&self, written: &str, object_dir: &Path) -> Option<Found> {
        self.find(written).or_else(|| {
            let (comps, _) = split(written);
            (0..comps.len()).find_map(|start| {
                let p = object_dir.join(comps[start..].iter().collect::<PathBuf>());
                self.check(&p, &p)
            })
        })
    }

    /// Finds the file LightWave means by `written`.
    pub fn find(&self, written: &str) -> Option<Found> {
        let (comps, absolute) = split(written);
        if comps.is_empty() {
            return None;
        }
        if absolute && !self.confined && written.starts_with('/') {
            let p = PathBuf::from(written);
            if let Some(f) = self.check(&p, &p) {
                return Some(f);
            }
        }
        let levels = if self.confined { 0 } else { MAX_PARENTS };
        for start in 0..comps.len() {
            let suffix: PathBuf = comps[start..].iter().collect();
            let mut base = self.scene_dir.clone();
            for level in 0..=levels {
                if level > 0 {
                    base = base.join("..");
                }
                let display = base.join(&suffix);
                if let Some(f) = self.check(&display, &display) {
                    return Some(f);
                }
            }
        }
        None
    }

    /// `p` when it is an existing file allowed by confinement.
    fn check(&self, p: &Path, display: &Path) -> Option<Found> {
        let canonical = std::fs::canonicalize(p).ok()?;
        if !canonical.is_file() {
            return None;
        }
        let inside = canonical.strip_prefix(&self.scene_dir_canonical).ok();
        if self.confined && inside.is_none() {
            return None;
        }
        Some(Found {
            display: tidy(display),
            from_scene: inside.map_or_else(|| canonical.clone(), Path::to_path_buf),
            canonical,
        })
    }

    /// The error for a file that was not found.
    pub fn missing(&self, what: &str, written: &str, loc: &Loc) -> LxsError {
        let where_ = if self.confined {
            format!("in {} and below", self.scene_dir.display())
        } else {
            format!(
                "in {}, its parent directories, and by shorter suffixes of the path",
                self.scene_dir.display()
            )
        };
        LxsError::new(
            LxsErrorKind::MissingInclude,
            loc.clone(),
            format!("{what} \"{written}\" not found (searched {where_})"),
        )
    }
}

/// Components of a LightWave path and whether it was absolute (device or root).
fn split(written: &str) -> (Vec<String>, bool) {
    let unified = written.trim().replace('\\', "/");
    let (rest, device) = match unified.split_once(':') {
        Some((dev, rest)) if !dev.contains('/') && !dev.is_empty() => (rest.to_string(), true),
        _ => (unified.clone(), false),
    };
    let absolute = device || rest.starts_with('/');
    let comps = rest
        .split('/')
        .filter(|c| !c.is_empty() && *c != ".")
        .map(str::to_string)
        .collect();
    (comps, absolute)
}

/// Removes `.` components and folds `dir/..` pairs where `dir` is a normal name.
fn tidy(p: &Path) -> PathBuf {
    let mut out: Vec<Component> = Vec::new();
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir if matches!(out.last(), Some(Component::Normal(_))) => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    if out.is_empty() {
        return PathBuf::from(".");
    }
    out.iter().collect()
}

/// Reads a file whole, refusing it when it would take more than `budget` bytes (the rest of
/// `ParseOptions::max_total_bytes`); the budget shrinks by what was read.
pub fn read_within(path: &Path, budget: &mut u64, loc: &Loc) -> Result<Vec<u8>, LxsError> {
    use std::io::Read;
    let io = |e: std::io::Error| {
        LxsError::new(
            LxsErrorKind::Io,
            loc.clone(),
            format!("cannot read {}: {e}", path.display()),
        )
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let len = file.metadata().map_err(io)?.len();
    let too_large = || {
        LxsError::new(
            LxsErrorKind::InputTooLarge,
            loc.clone(),
            format!(
                "{} would exceed the scene's byte limit ({} bytes left)",
                path.display(),
                budget
            ),
        )
    };
    if len > *budget {
        return Err(too_large());
    }
    let mut bytes = Vec::with_capacity(usize::try_from(len).unwrap_or(0));
    file.take(budget.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > *budget {
        return Err(too_large());
    }
    *budget -= bytes.len() as u64;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splits_lightwave_paths() {
        assert_eq!(
            split("F:fra/cornell/02.lwo"),
            (vec!["fra".into(), "cornell".into(), "02.lwo".into()], true)
        );
        assert_eq!(split("..\\LWO\\x.lwo").0, vec!["..", "LWO", "x.lwo"]);
        assert_eq!(
            split("Objects/./a.lwo"),
            (vec!["Objects".into(), "a.lwo".into()], false)
        );
        assert!(split("/abs/a.lwo").1);
    }

    fn tree() -> tempfile::TempDir {
        let d = tempfile::tempdir().unwrap();
        std::fs::create_dir_all(d.path().join("Content/Scenes")).unwrap();
        std::fs::create_dir_all(d.path().join("Content/Objects")).unwrap();
        std::fs::write(d.path().join("Content/Objects/box.lwo"), b"x").unwrap();
        std::fs::write(d.path().join("Content/Scenes/here.lwo"), b"x").unwrap();
        std::fs::write(d.path().join("Content/Scenes/s.lws"), b"x").unwrap();
        d
    }

    #[test]
    fn finds_objects_through_the_content_directory() {
        let d = tree();
        let r = Resolver::new(&d.path().join("Content/Scenes/s.lws"), false);
        let f = r.find("Objects/box.lwo").unwrap();
        assert!(f.canonical.ends_with("Content/Objects/box.lwo"));
        assert!(f.from_scene.is_absolute());
        assert!(r.find("F:some/where/Objects/box.lwo").is_some());
        assert!(r.find("../Objects/box.lwo").is_some());
        assert!(r.find("box.lwo").is_none());
        let near = r
            .find_near("F:x/box.lwo", &d.path().join("Content/Objects"))
            .unwrap();
        assert!(near.canonical.ends_with("Objects/box.lwo"));
        let here = r.find("C:\\old\\disk\\here.lwo").unwrap();
        assert_eq!(here.from_scene, PathBuf::from("here.lwo"));
        assert!(r.find("nothere.lwo").is_none());
    }

    #[test]
    fn confinement_keeps_to_the_scene_directory() {
        let d = tree();
        let r = Resolver::new(&d.path().join("Content/Scenes/s.lws"), true);
        assert!(r.find("Objects/box.lwo").is_none());
        assert!(r.find("../Objects/box.lwo").is_none());
        assert!(r.find("/etc/passwd").is_none());
        assert!(r.find("Objects/here.lwo").is_some());
        let e = r.missing("object", "Objects/box.lwo", &Loc::default());
        assert!(e.message.contains("not found"), "{e}");
    }

    #[test]
    fn reading_respects_the_budget() {
        let d = tree();
        let p = d.path().join("Content/Scenes/s.lws");
        let mut budget = 10;
        assert_eq!(read_within(&p, &mut budget, &Loc::default()).unwrap(), b"x");
        assert_eq!(budget, 9);
        let mut small = 0;
        let e = read_within(&p, &mut small, &Loc::default()).unwrap_err();
        assert_eq!(e.kind, LxsErrorKind::InputTooLarge);
    }
}
