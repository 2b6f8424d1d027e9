//! The import context: options, the files read, the byte budget, warnings, and the external
//! files found missing. Every reader and converter of the importer borrows it.
//!
//! ```text
//! path written in the scene --normalise (\ -> /)--> resolve against the element's file dir
//!   --confine (ParseOptions::confine_to_root)--> read under the byte budget --> bytes
//!   (missing: recorded with the element's location, reported together at the end)
//! ```

use crate::lxs::{Diagnostic, Loc, LxsError, LxsErrorKind, ParseOptions};
use std::cell::{Cell, RefCell};
use std::collections::HashSet;
use std::path::{Component, Path, PathBuf};

/// An external file the scene needs that could not be found.
#[derive(Clone, Debug, PartialEq)]
pub struct Missing {
    /// What kind of file ("mesh", "include", ...).
    pub what: &'static str,
    /// The path as resolved (display form).
    pub path: String,
    /// The element that names it.
    pub loc: Loc,
}

/// State shared by the whole import.
pub struct Ctx {
    pub opts: ParseOptions,
    /// The root scene's directory as given (relative paths in locations stay relative).
    pub root_dir: PathBuf,
    /// The canonical root directory, when confinement is on.
    root_canon: Option<PathBuf>,
    warnings: RefCell<Vec<Diagnostic>>,
    seen: RefCell<HashSet<(Loc, String)>>,
    files: RefCell<Vec<String>>,
    budget: Cell<u64>,
    missing: RefCell<Vec<Missing>>,
}

/// Normalises a path written in a scene: trimmed, Windows separators turned into `/`.
pub fn normalise_path(s: &str) -> String {
    s.trim().replace('\\', "/")
}

/// True for `C:/...` style paths (absolute on Windows, meaningless here).
fn is_drive_path(s: &str) -> bool {
    let b = s.as_bytes();
    b.len() >= 3 && b[0].is_ascii_alphabetic() && b[1] == b':' && b[2] == b'/'
}

/// Removes `.` and `..` lexically; None when `..` climbs above the start.
fn lexical(p: &Path) -> Option<PathBuf> {
    let mut out = PathBuf::new();
    let mut depth = 0usize;
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                if depth == 0 {
                    return None;
                }
                out.pop();
                depth -= 1;
            }
            Component::Normal(s) => {
                out.push(s);
                depth += 1;
            }
            Component::RootDir | Component::Prefix(_) => out.push(c.as_os_str()),
        }
    }
    Some(out)
}

pub fn err(kind: LxsErrorKind, loc: &Loc, msg: impl Into<String>) -> LxsError {
    LxsError::new(kind, loc.clone(), msg)
}

impl Ctx {
    pub fn new(root_file: &Path, opts: &ParseOptions) -> Ctx {
        let root_dir = root_file
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default();
        let root_canon = if opts.confine_to_root {
            let dir = if root_dir.as_os_str().is_empty() {
                Path::new(".")
            } else {
                root_dir.as_path()
            };
            Some(std::fs::canonicalize(dir).unwrap_or_else(|_| dir.to_path_buf()))
        } else {
            None
        };
        Ctx {
            opts: opts.clone(),
            root_dir,
            root_canon,
            warnings: RefCell::new(Vec::new()),
            seen: RefCell::new(HashSet::new()),
            files: RefCell::new(Vec::new()),
            budget: Cell::new(opts.max_total_bytes),
            missing: RefCell::new(Vec::new()),
        }
    }

    /// A located warning (the same message at the same place is kept once).
    pub fn warn(&self, loc: &Loc, message: impl Into<String>) {
        let message = message.into();
        if self
            .seen
            .borrow_mut()
            .insert((loc.clone(), message.clone()))
        {
            self.warnings.borrow_mut().push(Diagnostic {
                loc: loc.clone(),
                message,
            });
        }
    }

    pub fn push_warnings(&self, ws: Vec<Diagnostic>) {
        for w in ws {
            self.warn(&w.loc, w.message);
        }
    }

    pub fn take_warnings(&self) -> Vec<Diagnostic> {
        std::mem::take(&mut self.warnings.borrow_mut())
    }

    pub fn take_files(&self) -> Vec<String> {
        std::mem::take(&mut self.files.borrow_mut())
    }

    pub fn take_missing(&self) -> Vec<Missing> {
        std::mem::take(&mut self.missing.borrow_mut())
    }

    /// Charges `n` bytes to the scene's budget (`ParseOptions::max_total_bytes`).
    pub fn charge(&self, n: u64, loc: &Loc) -> Result<(), LxsError> {
        match self.budget.get().checked_sub(n) {
            Some(left) => {
                self.budget.set(left);
                Ok(())
            }
            None => Err(err(
                LxsErrorKind::InputTooLarge,
                loc,
                "the scene and the files it reads exceed the size limit \
                 (ParseOptions::max_total_bytes)",
            )),
        }
    }

    /// Bytes left in the budget.
    pub fn budget_left(&self) -> u64 {
        self.budget.get()
    }

    /// Checks a count read from input against `ParseOptions::max_array_len`.
    pub fn check_count(&self, n: u64, what: &str, loc: &Loc) -> Result<(), LxsError> {
        if n > self.opts.max_array_len as u64 {
            return Err(err(
                LxsErrorKind::ArrayTooLong,
                loc,
                format!(
                    "{n} {what} exceed the limit of {} (ParseOptions::max_array_len)",
                    self.opts.max_array_len
                ),
            ));
        }
        Ok(())
    }

    /// Resolves `written` (as in the scene) against `dir`, the directory of the file whose
    /// element names it. Refuses paths leaving the root directory when confined.
    pub fn resolve(&self, written: &str, dir: &Path, loc: &Loc) -> Result<PathBuf, LxsError> {
        let name = normalise_path(written);
        if name.is_empty() {
            return Err(err(LxsErrorKind::InvalidValue, loc, "empty file path"));
        }
        let rel = Path::new(&name);
        let absolute = rel.is_absolute() || is_drive_path(&name);
        if let Some(root) = &self.root_canon {
            let outside = |why: &str| {
                err(
                    LxsErrorKind::IncludeOutsideRoot,
                    loc,
                    format!("\"{name}\" {why}: files are confined to the scene's directory"),
                )
            };
            if absolute {
                return Err(outside("is an absolute path"));
            }
            let dir_canon = std::fs::canonicalize(if dir.as_os_str().is_empty() {
                Path::new(".")
            } else {
                dir
            })
            .unwrap_or_else(|_| dir.to_path_buf());
            let inside = lexical(&dir_canon.join(rel)).is_some_and(|p| p.starts_with(root));
            if !inside {
                return Err(outside("leaves the scene's directory"));
            }
            if let Ok(c) = std::fs::canonicalize(dir_canon.join(rel)) {
                if !c.starts_with(root) {
                    return Err(outside(
                        "resolves (through a symlink) outside the scene's directory",
                    ));
                }
            }
        }
        Ok(if absolute {
            rel.to_path_buf()
        } else {
            dir.join(rel)
        })
    }

    /// Reads the file `written` names (relative to `dir`) under the byte budget and records it
    /// in the scene's file list. A missing file is recorded and gives `None`.
    pub fn read(
        &self,
        written: &str,
        dir: &Path,
        loc: &Loc,
        what: &'static str,
    ) -> Result<Option<(PathBuf, Vec<u8>)>, LxsError> {
        let path = self.resolve(written, dir, loc)?;
        let meta = match std::fs::metadata(&path) {
            Ok(m) if m.is_file() => m,
            _ => {
                self.missing.borrow_mut().push(Missing {
                    what,
                    path: path.to_string_lossy().into_owned(),
                    loc: loc.clone(),
                });
                return Ok(None);
            }
        };
        self.charge(meta.len(), loc)?;
        let bytes = std::fs::read(&path).map_err(|e| {
            err(
                LxsErrorKind::Io,
                loc,
                format!("cannot read {what} file {}: {e}", path.display()),
            )
        })?;
        self.record_file(&path);
        Ok(Some((path, bytes)))
    }

    /// Adds a file to the scene's file list (once).
    pub fn record_file(&self, path: &Path) {
        let s = path.to_string_lossy().into_owned();
        let mut files = self.files.borrow_mut();
        if !files.contains(&s) {
            files.push(s);
        }
    }

    /// A path written in the scene, as a LuxRender parameter (relative to the root scene's
    /// directory, confined like every file the scene reads). Indigo takes such paths (textures,
    /// nk data, environment maps, IES files) relative to the scene's directory; a path that
    /// exists only relative to `dir`, the directory of the included file that names it, is
    /// taken from there.
    pub fn scene_relative(&self, written: &str, dir: &Path, loc: &Loc) -> Result<String, LxsError> {
        let from_root = self.resolve(written, &self.root_dir, loc)?;
        let full = if from_root.exists() {
            from_root
        } else {
            match self.resolve(written, dir, loc) {
                Ok(p) if p.exists() => p,
                _ => from_root,
            }
        };
        let rel = full
            .strip_prefix(&self.root_dir)
            .map(Path::to_path_buf)
            .unwrap_or(full);
        Ok(rel.to_string_lossy().into_owned())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn loc() -> Loc {
        Loc {
            file: "s.igs".into(),
            line: 1,
            col: 1,
        }
    }

    #[test]
    fn windows_paths_are_normalised_and_confined() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir_all(dir.path().join("meshes")).unwrap();
        std::fs::write(dir.path().join("meshes/a.igmesh"), b"x").unwrap();
        let root = dir.path().join("s.igs");
        let confined = Ctx::new(
            &root,
            &ParseOptions {
                confine_to_root: true,
                ..ParseOptions::default()
            },
        );
        let p = confined
            .resolve("meshes\\a.igmesh", dir.path(), &loc())
            .unwrap();
        assert_eq!(p, dir.path().join("meshes/a.igmesh"));
        for bad in [
            "..\\outside.igmesh",
            "/etc/passwd",
            "C:\\x\\y.igmesh",
            "a/../../b",
        ] {
            let e = confined.resolve(bad, dir.path(), &loc()).unwrap_err();
            assert_eq!(e.kind, LxsErrorKind::IncludeOutsideRoot, "{bad}");
        }
        let free = Ctx::new(&root, &ParseOptions::default());
        assert!(free.resolve("../x", dir.path(), &loc()).is_ok());
    }

    #[test]
    fn missing_files_are_recorded_and_budget_is_charged() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("a.bin"), vec![0u8; 100]).unwrap();
        let ctx = Ctx::new(
            &dir.path().join("s.igs"),
            &ParseOptions {
                max_total_bytes: 150,
                ..ParseOptions::default()
            },
        );
        assert!(ctx
            .read("nope.igmesh", dir.path(), &loc(), "mesh")
            .unwrap()
            .is_none());
        assert_eq!(ctx.take_missing().len(), 1);
        assert!(ctx
            .read("a.bin", dir.path(), &loc(), "mesh")
            .unwrap()
            .is_some());
        let e = ctx.read("a.bin", dir.path(), &loc(), "mesh").unwrap_err();
        assert_eq!(e.kind, LxsErrorKind::InputTooLarge);
        assert_eq!(ctx.take_files().len(), 1);
    }
}
