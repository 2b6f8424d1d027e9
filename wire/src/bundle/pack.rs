//! Packing a scene for submission: the .lxs with every file it references, as a tar with paths
//! relative to the scene's directory (the layout [`super::unpack`] and [`super::pick_scene`]
//! expect). A .zip or .tar given by the user is sent as it is.
//!
//! What a scene references: the files its importer read (`luxfarm::formats::load`; for a .lxs,
//! the scene and its Includes, recorded in `SceneDescription::files` as the parser opened them,
//! i.e. relative to the working directory or absolute), and every string parameter naming an existing file, relative to the scene's
//! directory (PLY meshes, image maps, environment maps, IES and spectrum files). Each must lie
//! inside the scene's directory, since the master unpacks the bundle there and confines the
//! scene to it; a `filename`, `mapname` or `iesname` outside it is an error, any other string
//! that happens to name an outside file is left out.

use crate::{Result, WireError};
use luxfarm::formats;
use luxfarm::lxs::{ParamValue, ParseOptions, SpectrumValue};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Longest string parameter still considered as a file name.
const MAX_NAME: usize = 4096;

/// The bytes to upload and the file name that tells the master how to read them.
#[derive(Debug)]
pub struct Upload {
    pub bytes: Vec<u8>,
    pub file_name: String,
    /// Files included (relative paths), for the user.
    pub files: Vec<PathBuf>,
}

/// Reads `path` for submission: bundles a .lxs, passes a .zip/.tar through.
pub fn prepare(path: &Path) -> Result<Upload> {
    let name = path
        .file_name()
        .and_then(|s| s.to_str())
        .unwrap_or("scene")
        .to_string();
    let lower = name.to_ascii_lowercase();
    if lower.ends_with(".zip") || lower.ends_with(".tar") {
        let bytes = std::fs::read(path).map_err(|e| file_error(path, e))?;
        return Ok(Upload {
            bytes,
            file_name: name,
            files: Vec::new(),
        });
    }
    let files = referenced_files(path)?;
    let bytes = tar_files(scene_dir(path), &files)?;
    Ok(Upload {
        bytes,
        file_name: format!("{name}.tar"),
        files,
    })
}

fn file_error(path: &Path, source: std::io::Error) -> WireError {
    WireError::File {
        path: path.to_path_buf(),
        source,
    }
}

/// The files of a scene's bundle, relative to its directory and canonicalised.
struct Collector {
    root: PathBuf,
    root_abs: PathBuf,
    set: BTreeSet<PathBuf>,
}

impl Collector {
    /// Adds the file at `full` (a path usable from the working directory). A `required` file
    /// must exist and lie inside the scene's directory; others are skipped when they do not.
    fn add(&mut self, full: &Path, shown: &Path, required: bool) -> Result<()> {
        let Ok(abs) = full.canonicalize() else {
            if required {
                return Err(WireError::Scene(format!("{}: not found", full.display())));
            }
            return Ok(());
        };
        if !abs.is_file() {
            return Ok(());
        }
        match abs.strip_prefix(&self.root_abs) {
            Ok(rel) => {
                self.set.insert(rel.to_path_buf());
                Ok(())
            }
            Err(_) if required => Err(WireError::Scene(format!(
                "{} is outside the scene's directory {}: move it inside to submit the scene",
                shown.display(),
                self.root.display()
            ))),
            Err(_) => Ok(()),
        }
    }

    /// Adds a file named by a scene parameter, relative to the scene's directory unless
    /// absolute.
    fn add_param(&mut self, name: &Path, required: bool) -> Result<()> {
        let full = if name.is_absolute() {
            name.to_path_buf()
        } else {
            self.root.join(name)
        };
        self.add(&full, name, required)
    }
}

/// The scene file and every file it references, relative to the scene's directory.
pub fn referenced_files(scene: &Path) -> Result<Vec<PathBuf>> {
    let desc = formats::load(scene, &ParseOptions::default()).map_err(WireError::SceneParse)?;
    let root = scene_dir(scene).to_path_buf();
    let root_abs = root.canonicalize().map_err(|e| file_error(&root, e))?;
    let mut c = Collector {
        root,
        root_abs,
        set: BTreeSet::new(),
    };
    c.add(scene, scene, true)?;
    // The parser's own paths: usable as they are, from the working directory.
    for f in &desc.files {
        c.add(Path::new(f), Path::new(f), true)?;
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
            let file_param = super::FILE_PARAMS.contains(&p.name.as_str());
            for n in names {
                if !n.is_empty() && n.len() < MAX_NAME {
                    let exists = c.root.join(n).exists();
                    c.add_param(Path::new(n), file_param && exists)?;
                }
            }
        }
    }
    Ok(c.set.into_iter().collect())
}

/// The directory of a scene file ("." for a bare file name).
fn scene_dir(scene: &Path) -> &Path {
    match scene.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// A tar of `files` (relative to `root`, as [`referenced_files`] gives them), symlinks
/// followed so that only regular files travel.
fn tar_files(root: &Path, files: &[PathBuf]) -> Result<Vec<u8>> {
    let mut b = tar::Builder::new(Vec::new());
    b.follow_symlinks(true);
    for f in files {
        if f.is_absolute()
            || f.components()
                .any(|c| !matches!(c, std::path::Component::Normal(_)))
        {
            return Err(WireError::Scene(format!(
                "{}: not a path inside the scene's directory",
                f.display()
            )));
        }
        let full = root.join(f);
        b.append_path_with_name(&full, f)
            .map_err(|e| file_error(&full, e))?;
    }
    Ok(b.into_inner()?)
}

#[cfg(test)]
mod tests {
    use super::super::{pick_scene, unpack, Limits};
    use super::*;
    use std::fs;

    /// A scene directory: the scene includes `inc/geo.lxs`, which names a PLY mesh; a texture
    /// map; an unrelated file that must stay out.
    fn scene_tree() -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        fs::create_dir_all(d.join("sub/inc")).unwrap();
        fs::create_dir_all(d.join("sub/tex")).unwrap();
        fs::write(
            d.join("sub/scene.lxs"),
            "Film \"fleximage\" \"integer xresolution\" [8] \"integer yresolution\" [8] \
             \"string filename\" [\"out\"]\nWorldBegin\nInclude \"inc/geo.lxs\"\n\
             Texture \"t\" \"color\" \"imagemap\" \"string filename\" [\"tex/map.png\"]\n\
             WorldEnd\n",
        )
        .unwrap();
        fs::write(
            d.join("sub/inc/geo.lxs"),
            "Shape \"plymesh\" \"string filename\" [\"inc/m.ply\"]\n",
        )
        .unwrap();
        fs::write(d.join("sub/inc/m.ply"), "ply\n").unwrap();
        fs::write(d.join("sub/tex/map.png"), "png").unwrap();
        fs::write(d.join("sub/unrelated.txt"), "x").unwrap();
        dir
    }

    fn expected() -> Vec<PathBuf> {
        ["inc/geo.lxs", "inc/m.ply", "scene.lxs", "tex/map.png"]
            .iter()
            .map(PathBuf::from)
            .collect()
    }

    /// An Indigo scene: an included .igm material file, an external .obj mesh named with a
    /// Windows path, a texture, and an unrelated file.
    #[test]
    fn indigo_scene_bundles_its_includes_meshes_and_textures() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        for sub in ["mats", "meshes", "tex"] {
            fs::create_dir_all(d.join(sub)).unwrap();
        }
        fs::write(
            d.join("room.igs"),
            "<?xml version=\"1.0\"?>\n<scene>\n<renderer_settings><width>8</width><height>8</height></renderer_settings>\n\
             <camera><pos>0 -3 0</pos><forwards>0 1 0</forwards><up>0 0 1</up></camera>\n\
             <include><pathname>mats\\wood.igm</pathname></include>\n\
             <mesh><name>m</name><external><path>meshes\\tri.obj</path></external></mesh>\n\
             <model><pos>0 0 0</pos><scale>1</scale><mesh_name>m</mesh_name></model>\n</scene>\n",
        )
        .unwrap();
        fs::write(
            d.join("mats/wood.igm"),
            "<scenedata><material><name>wood</name><diffuse><texture><path>tex/wood.png</path></texture>\
             <albedo><texture><texture_index>0</texture_index></texture></albedo></diffuse></material></scenedata>",
        )
        .unwrap();
        fs::write(
            d.join("meshes/tri.obj"),
            "v 0 0 0\nv 1 0 0\nv 0 0 1\nusemtl wood\nf 1 2 3\n",
        )
        .unwrap();
        fs::write(d.join("tex/wood.png"), "png").unwrap();
        fs::write(d.join("unrelated.txt"), "x").unwrap();
        let files = referenced_files(&d.join("room.igs")).unwrap();
        let want: Vec<PathBuf> = [
            "mats/wood.igm",
            "meshes/tri.obj",
            "room.igs",
            "tex/wood.png",
        ]
        .iter()
        .map(PathBuf::from)
        .collect();
        assert_eq!(files, want);
        let up = prepare(&d.join("room.igs")).unwrap();
        let out = tempfile::tempdir().unwrap();
        let unpacked = unpack(&up.bytes, &up.file_name, out.path(), Limits::default()).unwrap();
        assert_eq!(
            pick_scene(&unpacked, "").unwrap(),
            PathBuf::from("room.igs")
        );
        // The worker imports the unpacked copy again.
        let again =
            luxfarm::formats::load(&out.path().join("room.igs"), &ParseOptions::default()).unwrap();
        assert_eq!(again.shapes.len(), 1);
    }

    #[test]
    fn referenced_files_of_a_scene_in_a_subfolder() {
        let dir = scene_tree();
        let scene = dir.path().join("sub/scene.lxs");
        assert_eq!(referenced_files(&scene).unwrap(), expected());
    }

    #[test]
    fn packed_scene_unpacks_to_the_same_files() {
        let dir = scene_tree();
        let up = prepare(&dir.path().join("sub/scene.lxs")).unwrap();
        assert_eq!(up.file_name, "scene.lxs.tar");
        assert_eq!(up.files, expected());
        let out = tempfile::tempdir().unwrap();
        let mut files = unpack(&up.bytes, &up.file_name, out.path(), Limits::default()).unwrap();
        files.sort();
        assert_eq!(files, expected());
        assert_eq!(pick_scene(&files, "").unwrap(), PathBuf::from("scene.lxs"));
        for f in &files {
            assert_eq!(
                fs::read(out.path().join(f)).unwrap(),
                fs::read(dir.path().join("sub").join(f)).unwrap(),
                "{}",
                f.display()
            );
        }
    }

    /// The scene named by a relative path from the working directory, through `..`: the
    /// parser records its files relative to the working directory, not the scene's.
    #[test]
    fn relative_scene_path_from_the_working_directory() {
        let dir = scene_tree();
        let cwd = std::env::current_dir().unwrap();
        let ups = cwd.components().count().saturating_sub(1);
        let mut rel = PathBuf::new();
        for _ in 0..ups {
            rel.push("..");
        }
        let inside = dir.path().strip_prefix("/").unwrap();
        let scene = rel.join(inside).join("sub/scene.lxs");
        assert!(scene.is_relative() && scene.exists(), "{}", scene.display());
        assert_eq!(referenced_files(&scene).unwrap(), expected());
    }

    #[test]
    fn file_outside_the_scene_directory_refused() {
        let dir = scene_tree();
        fs::write(dir.path().join("outside.ply"), "ply\n").unwrap();
        fs::write(
            dir.path().join("sub/inc/geo.lxs"),
            "Shape \"plymesh\" \"string filename\" [\"../outside.ply\"]\n",
        )
        .unwrap();
        let e = referenced_files(&dir.path().join("sub/scene.lxs")).unwrap_err();
        assert!(
            e.to_string().contains("outside the scene's directory"),
            "{e}"
        );
    }

    #[test]
    fn archives_pass_through() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("b.ZIP");
        fs::write(&p, b"PK\x03\x04whatever").unwrap();
        let up = prepare(&p).unwrap();
        assert_eq!(up.bytes, b"PK\x03\x04whatever");
        assert_eq!(up.file_name, "b.ZIP");
        assert!(matches!(
            prepare(&dir.path().join("missing.tar")),
            Err(WireError::File { .. })
        ));
    }

    #[test]
    fn scene_errors_are_values() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("bad.lxs");
        fs::write(
            &p,
            "WorldBegin\nShape \"sphere\" \"float radius\" [\nWorldEnd\n",
        )
        .unwrap();
        let e = prepare(&p).unwrap_err();
        let source = std::error::Error::source(&e).map(ToString::to_string);
        assert!(matches!(e, WireError::SceneParse(_)), "{e:?}");
        assert!(source.is_some_and(|s| s.contains("bad.lxs:")), "{e:?}");
    }
}
