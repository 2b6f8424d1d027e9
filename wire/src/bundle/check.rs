//! The master's check, at submission, that every file a scene names lies inside its bundle:
//! the same rules a worker's render core applies when it opens them
//! (`luxfarm::fileio::SceneFiles`, confined), applied to the scene's description before a job
//! is queued, so a scene naming `/etc/passwd` or `../../secret.exr` is refused with its
//! location instead of failing (or worse) on a worker.
//!
//! Which parameters name files is the knowledge [`pack`](super::pack) shares: the
//! [`FILE_PARAMS`] of every statement but the Film (whose `filename` is an output), spectrum
//! files, and a metal's `name` when it is not one of the preset metals.

use crate::{Result, WireError};
use luxfarm::fileio::{FileError, SceneFiles};
use luxfarm::lxs::{Param, ParamValue, SceneDescription, SpectrumValue};

/// String parameters that name an input file (meshes, images, maps, IES profiles, lens
/// descriptions).
pub const FILE_PARAMS: &[&str] = &["filename", "mapname", "iesname", "specfile"];

/// LuxRender's preset metals: a metal `name` that is one of them names no file.
const METAL_PRESETS: &[&str] = &["amorphous carbon", "silver", "gold", "copper", "aluminium"];

/// Checks every file the scene names through `files` (confined to the bundle): each must be
/// a regular file inside it, within the size bound. The first failure is a located
/// [`WireError::Scene`] (`file:line:column: parameter "name": reason`).
pub fn check_scene_files(desc: &SceneDescription, files: &SceneFiles) -> Result<()> {
    for (label, entity) in desc.entities() {
        if label == "Film" {
            continue;
        }
        let metal = label == "Material" && entity.kind == "metal";
        for p in &entity.params.params {
            for (name, optional) in named_files(p, metal) {
                check_one(files, p, name, optional)?;
            }
        }
    }
    Ok(())
}

/// The file names a parameter holds, each with whether a missing file is allowed (a metal's
/// `name` falls back to a preset, as in LuxRender).
fn named_files(p: &Param, metal: bool) -> Vec<(&str, bool)> {
    match &p.value {
        ParamValue::Spectrum(SpectrumValue::File(f)) => vec![(f.as_str(), false)],
        ParamValue::String(v) if FILE_PARAMS.contains(&p.name.as_str()) => v
            .iter()
            .filter(|s| !s.is_empty())
            .map(|s| (s.as_str(), false))
            .collect(),
        ParamValue::String(v) if metal && p.name == "name" => v
            .iter()
            .filter(|s| !s.is_empty() && !METAL_PRESETS.contains(&s.as_str()))
            .map(|s| (s.as_str(), true))
            .collect(),
        _ => Vec::new(),
    }
}

fn check_one(files: &SceneFiles, p: &Param, name: &str, optional: bool) -> Result<()> {
    match files.resolve(name) {
        Ok(_) => Ok(()),
        Err(FileError::NotFound { .. }) if optional => Ok(()),
        Err(e) => Err(WireError::Scene(format!(
            "{}: parameter \"{}\": {e}",
            p.loc, p.name
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use luxfarm::lxs::{parse_file, ParseOptions};
    use std::fs;

    /// A bundle root holding `scene.lxs` with `body` after WorldBegin, a mesh and an image;
    /// `secret.exr` lies beside the root.
    fn check(body: &str) -> Result<()> {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().join("bundle");
        fs::create_dir_all(root.join("tex")).unwrap();
        fs::write(dir.path().join("secret.exr"), b"secret").unwrap();
        fs::write(root.join("m.ply"), b"ply\n").unwrap();
        fs::write(root.join("tex/a.png"), b"png").unwrap();
        let text = format!(
            "Film \"fleximage\" \"string filename\" [\"/tmp/out\"]\nWorldBegin\n{body}\nWorldEnd\n"
        );
        fs::write(root.join("scene.lxs"), text).unwrap();
        let desc = parse_file(&root.join("scene.lxs"), &ParseOptions::default()).unwrap();
        let files = SceneFiles::confined(&root, &root).unwrap();
        let r = check_scene_files(&desc, &files);
        if let Err(e) = &r {
            let host = dir.path().join("secret.exr");
            assert!(!e.to_string().contains(host.to_str().unwrap()), "{e}");
        }
        r
    }

    #[test]
    fn files_inside_the_bundle_pass() {
        check(
            "Shape \"plymesh\" \"string filename\" [\"m.ply\"]\n\
             Texture \"t\" \"color\" \"imagemap\" \"string filename\" [\"tex/a.png\"]\n\
             Material \"metal\" \"string name\" [\"gold\"]\n\
             MakeNamedMaterial \"m\" \"string type\" [\"metal\"] \"string name\" [\"missing.nk\"]",
        )
        .unwrap();
    }

    #[test]
    fn every_kind_of_outside_file_is_refused_with_its_location() {
        let cases = [
            "Texture \"t\" \"color\" \"imagemap\" \"string filename\" [\"/abs/secret.exr\"]",
            "Shape \"plymesh\" \"string filename\" [\"/etc/passwd\"]",
            "Shape \"plymesh\" \"string filename\" [\"/dev/zero\"]",
            "Shape \"stlmesh\" \"string filename\" [\"../secret.exr\"]",
            "LightSource \"infinite\" \"string mapname\" [\"../secret.exr\"]",
            "Material \"metal\" \"string name\" [\"/root/.ssh/id_rsa\"]",
            "Shape \"plymesh\" \"string filename\" [\"missing.ply\"]",
            "Shape \"plymesh\" \"string filename\" [\"tex\"]",
        ];
        for body in cases {
            let e = check(body).unwrap_err().to_string();
            assert!(e.contains("scene.lxs:3:"), "{body}: {e}");
            assert!(e.contains("parameter \""), "{body}: {e}");
        }
    }

    #[test]
    fn the_film_output_name_is_not_an_input() {
        check("").unwrap();
    }
}
