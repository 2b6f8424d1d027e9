//! A scene built confined to its bundle (as a farm worker builds it) opens no file outside the
//! bundle: image maps, PLY and STL meshes, environment maps and nk files named by absolute
//! paths, `..` or symlinks are refused with the scene location (or, for an nk file, fall back
//! to the preset with a located warning), and no message shows a host path.

use luxfarm::fileio::SceneFiles;
use luxfarm::lxs::{parse_file, ParseOptions};
use luxfarm::render::setup::Renderable;
use std::fs;
use std::path::Path;

const HEADER: &str = "LookAt 0 -3 1 0 0 1 0 0 1\nCamera \"perspective\"\n\
Film \"fleximage\" \"integer xresolution\" [8] \"integer yresolution\" [8]\nWorldBegin\n";

/// Writes `bundle/scene.lxs` (HEADER + `body`) and `secret.*` files beside the bundle, then
/// builds it confined; returns the result as text, and the host directory.
fn build(dir: &Path, body: &str) -> Result<Vec<String>, String> {
    let root = dir.join("bundle");
    fs::create_dir_all(&root).unwrap();
    let text = format!("{HEADER}{body}\nWorldEnd\n");
    fs::write(root.join("scene.lxs"), text).unwrap();
    let desc = parse_file(&root.join("scene.lxs"), &ParseOptions::default()).unwrap();
    let files = SceneFiles::confined(&root, &root).unwrap();
    // Locations are shown relative to the bundle, as the master and the workers show them.
    let shown = |s: String| s.replace(&format!("{}/", root.display()), "");
    match Renderable::build(&desc, files) {
        Ok(r) => Ok(r.warnings.iter().map(|w| shown(w.to_string())).collect()),
        Err(e) => Err(shown(e.to_string())),
    }
}

fn secrets(dir: &Path) {
    // A real image and PLY mesh outside the bundle: readable if confinement failed.
    image::RgbImage::from_pixel(2, 2, image::Rgb([255, 0, 0]))
        .save(dir.join("secret.png"))
        .unwrap();
    fs::write(
        dir.join("secret.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
         0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    )
    .unwrap();
    fs::write(dir.join("secret.nk"), "# nk\n400 1.0 2.0\n700 1.5 2.5\n").unwrap();
}

#[test]
fn every_file_a_confined_scene_names_stays_inside_the_bundle() {
    let dir = tempfile::tempdir().unwrap();
    secrets(dir.path());
    let abs = |n: &str| dir.path().join(n).display().to_string();
    let host = dir.path().display().to_string();
    let cases = [
        format!(
            "Texture \"t\" \"color\" \"imagemap\" \"string filename\" [\"{}\"]\n\
             Material \"matte\" \"texture Kd\" \"t\"\nShape \"sphere\"",
            abs("secret.png")
        ),
        "Texture \"t\" \"color\" \"imagemap\" \"string filename\" [\"../secret.png\"]\n\
         Material \"matte\" \"texture Kd\" \"t\"\nShape \"sphere\""
            .to_string(),
        format!(
            "Shape \"plymesh\" \"string filename\" [\"{}\"]",
            abs("secret.ply")
        ),
        "Shape \"plymesh\" \"string filename\" [\"/etc/passwd\"]".to_string(),
        "Shape \"plymesh\" \"string filename\" [\"/dev/zero\"]".to_string(),
        "Shape \"stlmesh\" \"string filename\" [\"../secret.ply\"]".to_string(),
        "LightSource \"infinite\" \"string mapname\" [\"../secret.png\"]".to_string(),
    ];
    for body in &cases {
        let e = build(dir.path(), body).expect_err(body);
        assert!(e.starts_with("scene.lxs:5:"), "{body}: {e}");
        // The only host path in the message is the one the scene wrote.
        assert!(!e.contains(&host) || body.contains(&host), "{body}: {e}");
        assert!(!e.contains("No such file"), "{body}: {e}");
        assert!(
            e.contains("absolute path") || e.contains("leaves the scene's directory"),
            "{body}: {e}"
        );
    }
}

#[test]
fn a_symlink_out_of_the_bundle_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    secrets(dir.path());
    fs::create_dir_all(dir.path().join("bundle")).unwrap();
    std::os::unix::fs::symlink(
        dir.path().join("secret.ply"),
        dir.path().join("bundle/m.ply"),
    )
    .unwrap();
    let e = build(
        dir.path(),
        "Shape \"plymesh\" \"string filename\" [\"m.ply\"]",
    )
    .unwrap_err();
    assert!(e.contains("leaves the scene's directory"), "{e}");
}

#[test]
fn an_outside_nk_file_is_not_read() {
    let dir = tempfile::tempdir().unwrap();
    secrets(dir.path());
    let body = format!(
        "Material \"metal\" \"string name\" [\"{}\"]\nShape \"sphere\"",
        dir.path().join("secret.nk").display()
    );
    let warnings = build(dir.path(), &body).unwrap();
    let w = warnings.join("\n");
    assert!(w.contains("absolute path"), "{w}");
    assert!(w.contains("scene.lxs:5:"), "{w}");
    assert!(w.contains("using aluminium"), "{w}");
}

#[test]
fn files_inside_the_bundle_still_load() {
    let dir = tempfile::tempdir().unwrap();
    secrets(dir.path());
    fs::create_dir_all(dir.path().join("bundle/m")).unwrap();
    fs::copy(
        dir.path().join("secret.ply"),
        dir.path().join("bundle/m/a.ply"),
    )
    .unwrap();
    fs::copy(
        dir.path().join("secret.png"),
        dir.path().join("bundle/m/a.png"),
    )
    .unwrap();
    build(
        dir.path(),
        "Texture \"t\" \"color\" \"imagemap\" \"string filename\" [\"m/a.png\"]\n\
         Material \"matte\" \"texture Kd\" \"t\"\n\
         Shape \"plymesh\" \"string filename\" [\"m/./a.ply\"]",
    )
    .unwrap();
}
