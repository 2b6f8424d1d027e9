//! Bundling a scene for submission: the .lxs with every file it references (its Includes, as
//! `desc.files`, and every string parameter naming an existing file: PLY meshes, image maps,
//! environment maps, IES and spectrum files), as a tar with paths relative to the scene's
//! directory. A .zip or .tar given by the user is sent as it is.

use anyhow::{bail, Context};
use luxfarm::lxs::{self, ParamValue, ParseOptions, SpectrumValue};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The bytes to upload and the file name that tells the master how to read them.
pub struct Upload {
    pub bytes: Vec<u8>,
    pub file_name: String,
    /// Files included (relative paths), for the user.
    pub files: Vec<PathBuf>,
}

/// Reads `path` for submission: bundles a .lxs, passes a .zip/.tar through.
pub fn prepare(path: &Path) -> anyhow::Result<Upload> {
    let name = path
        .file_name()
        .and_then(|s| s.to_str())
        .unwrap_or("scene")
        .to_string();
    let lower = name.to_ascii_lowercase();
    if lower.ends_with(".zip") || lower.ends_with(".tar") {
        let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
        return Ok(Upload {
            bytes,
            file_name: name,
            files: Vec::new(),
        });
    }
    let files = referenced_files(path)?;
    let root = scene_dir(path);
    let bytes = tar_files(root, &files)?;
    Ok(Upload {
        bytes,
        file_name: format!("{name}.tar"),
        files,
    })
}

/// The scene file and every file it references, relative to the scene's directory.
pub fn referenced_files(scene: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let desc =
        lxs::parse_file(scene, &ParseOptions::default()).map_err(|e| anyhow::anyhow!("{e}"))?;
    let root = scene_dir(scene);
    let root_abs = root
        .canonicalize()
        .with_context(|| format!("resolving {}", root.display()))?;
    let mut set = BTreeSet::new();
    // `from_cwd`: the path is as the parser opened it (relative to the working directory),
    // not a scene parameter (relative to the scene's directory).
    let mut add = |p: &Path, required: bool, from_cwd: bool| -> anyhow::Result<()> {
        let full = if p.is_absolute() || from_cwd {
            p.to_path_buf()
        } else {
            root.join(p)
        };
        let Ok(abs) = full.canonicalize() else {
            if required {
                bail!("{}: not found", full.display());
            }
            return Ok(());
        };
        if !abs.is_file() {
            return Ok(());
        }
        match abs.strip_prefix(&root_abs) {
            Ok(rel) => {
                set.insert(rel.to_path_buf());
                Ok(())
            }
            Err(_) if required => bail!(
                "{} is outside the scene's directory {}: move it inside to submit the scene",
                p.display(),
                root.display()
            ),
            Err(_) => Ok(()),
        }
    };
    add(scene, true, true)?;
    for f in &desc.files {
        add(Path::new(f), true, true)?;
    }
    for (label, entity) in desc.entities() {
        if label == "Film" {
            continue;
        }
        for p in &entity.params.params {
            let names: Vec<&str> = match &p.value {
                ParamValue::String(v) => v.iter().map(String::as_str).collect(),
                ParamValue::Spectrum(SpectrumValue::File(f)) => vec![f.as_str()],
                _ => continue,
            };
            for n in names {
                if !n.is_empty() && n.len() < 4096 {
                    let file_param = matches!(p.name.as_str(), "filename" | "mapname" | "iesname");
                    add(Path::new(n), file_param && root.join(n).exists(), false)?;
                }
            }
        }
    }
    Ok(set.into_iter().collect())
}

/// The directory of a scene file ("." for a bare file name).
pub fn scene_dir(scene: &Path) -> &Path {
    match scene.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// A tar of `files` (relative to `root`).
pub fn tar_files(root: &Path, files: &[PathBuf]) -> anyhow::Result<Vec<u8>> {
    let mut b = tar::Builder::new(Vec::new());
    b.follow_symlinks(true);
    for f in files {
        b.append_path_with_name(root.join(f), f)
            .with_context(|| format!("adding {}", f.display()))?;
    }
    Ok(b.into_inner()?)
}
