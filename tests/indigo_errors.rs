//! Malformed Indigo input, class by class, through the scene-format seam: every error is a
//! value naming file:line:column, and limits for untrusted uploads hold.

use luxfarm::formats;
use luxfarm::lxs::{LxsError, LxsErrorKind, ParseOptions, SceneDescription};
use std::path::Path;

const HEAD: &str =
    "<scene><camera><pos>0 -3 0</pos><forwards>0 1 0</forwards><up>0 0 1</up></camera>\
    <material><name>m</name><diffuse/></material>\n";

fn write(dir: &Path, name: &str, text: &[u8]) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn load_text(
    text: &str,
    opts: &ParseOptions,
) -> (tempfile::TempDir, Result<SceneDescription, LxsError>) {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "s.igs", text.as_bytes());
    let r = formats::load(&p, opts);
    (dir, r)
}

fn err(text: &str) -> LxsError {
    load_text(text, &ParseOptions::default()).1.unwrap_err()
}

fn quad_mesh(extra: &str) -> String {
    format!(
        "<mesh><name>q</name><embedded><vertex pos=\"0 0 0\"/><vertex pos=\"1 0 0\"/><vertex pos=\"0 0 1\"/>{extra}\
         <triangle_set><material_name>m</material_name><tri>0 1 2</tri></triangle_set></embedded></mesh>\n"
    )
}

#[test]
fn malformed_xml_and_wrong_roots() {
    let e = err("<scene>\n<camera>\n</scene>");
    assert_eq!((e.kind, e.loc.line), (LxsErrorKind::Syntax, 3), "{e}");
    assert!(e.to_string().starts_with(&format!("{}:3:", e.loc.file)));
    let e = err("<?xml version=\"1.0\"?>\n<scenedata/>");
    assert_eq!((e.kind, e.loc.line), (LxsErrorKind::Syntax, 2));
    let e = err("<!DOCTYPE scene [<!ENTITY x \"y\">]><scene>&x;</scene>");
    assert_eq!(e.kind, LxsErrorKind::Syntax);
}

#[test]
fn bad_values_and_references_are_located() {
    let e = err(&format!(
        "{HEAD}<renderer_settings>\n<width>wide</width></renderer_settings></scene>"
    ));
    assert_eq!(
        (e.kind, e.loc.line),
        (LxsErrorKind::InvalidNumber, 3),
        "{e}"
    );
    let e = err(&format!(
        "{HEAD}{}<model>\n<pos>0 0 0</pos><mesh_name>nope</mesh_name></model></scene>",
        quad_mesh("")
    ));
    assert_eq!((e.kind, e.loc.line), (LxsErrorKind::Undefined, 3), "{e}");
    let e = err(&format!(
        "{HEAD}<mesh><name>q</name><embedded><vertex pos=\"0 0 0\"/>\n<triangle_set><material_name>m</material_name>\n<tri>0 1 2</tri></triangle_set></embedded></mesh></scene>"
    ));
    assert_eq!((e.kind, e.loc.line), (LxsErrorKind::InvalidValue, 4), "{e}");
    let e = err(&format!("{HEAD}{}<model><pos>0 0 0</pos><mesh_name>q</mesh_name></model>\n<sphere><center>0 0 0</center><radius>1</radius><material_name>x</material_name></sphere></scene>", quad_mesh("")));
    assert_eq!((e.kind, e.loc.line), (LxsErrorKind::Undefined, 4), "{e}");
    let e = err(&format!(
        "{HEAD}<mesh><name>q</name><external>\n<path>a.3ds</path></external></mesh></scene>"
    ));
    assert_eq!((e.kind, e.loc.line), (LxsErrorKind::Unsupported, 3), "{e}");
}

#[test]
fn damaged_igmesh_files_name_the_file_and_the_element() {
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../shared/scenes/formats/indigo/igmesh/tilted_prism.igmesh")
            .canonicalize()
            .unwrap_or_else(|_| {
                Path::new("/work/shared/scenes/formats/indigo/igmesh/tilted_prism.igmesh")
                    .to_path_buf()
            }),
    )
    .unwrap();
    // Truncated.
    write(dir.path(), "cut.igmesh", &good[..good.len() / 2]);
    // A vertex count of 4 billion in a small file.
    let mut huge = good.clone();
    huge[32..36].copy_from_slice(&u32::MAX.to_le_bytes());
    write(dir.path(), "huge.igmesh", &huge);
    for f in ["cut", "huge"] {
        let scene = format!(
            "{HEAD}<mesh><name>q</name><external>\n  <path>{f}.igmesh</path></external></mesh></scene>"
        );
        let p = write(dir.path(), "s.igs", scene.as_bytes());
        let e = formats::load(&p, &ParseOptions::default()).unwrap_err();
        assert_eq!((e.loc.line, e.loc.col), (3, 3), "{e}");
        assert!(e.message.contains(&format!("{f}.igmesh")), "{e}");
    }
}

#[test]
fn limits_for_untrusted_uploads() {
    let confined = ParseOptions {
        confine_to_root: true,
        ..ParseOptions::default()
    };
    let (_d, r) = load_text(
        &format!("{HEAD}<include>\n<pathname>../../etc/passwd</pathname></include></scene>"),
        &confined,
    );
    assert_eq!(r.unwrap_err().kind, LxsErrorKind::IncludeOutsideRoot);
    let (_d, r) = load_text(&format!("{HEAD}<mesh><name>q</name><external><path>/etc/hosts.obj</path></external></mesh></scene>"), &confined);
    assert_eq!(r.unwrap_err().kind, LxsErrorKind::IncludeOutsideRoot);
    let small = ParseOptions {
        max_total_bytes: 100,
        ..ParseOptions::default()
    };
    let (_d, r) = load_text(&format!("{HEAD}{}</scene>", quad_mesh("")), &small);
    assert_eq!(r.unwrap_err().kind, LxsErrorKind::InputTooLarge);
    let short = ParseOptions {
        max_array_len: 4,
        ..ParseOptions::default()
    };
    let (_d, r) = load_text(
        &format!(
            "{HEAD}{}</scene>",
            quad_mesh("<vertex pos=\"1 1 1\"/><vertex pos=\"2 2 2\"/>")
        ),
        &short,
    );
    assert_eq!(r.unwrap_err().kind, LxsErrorKind::ArrayTooLong);
    // An include cycle.
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "a.igs",
        b"<scene><include><pathname>b.igs</pathname></include></scene>",
    );
    write(
        dir.path(),
        "b.igs",
        b"<scene>\n<include><pathname>a.igs</pathname></include></scene>",
    );
    let e = formats::load(&dir.path().join("a.igs"), &ParseOptions::default()).unwrap_err();
    assert_eq!(e.kind, LxsErrorKind::IncludeCycle);
    assert!(e.loc.file.ends_with("b.igs"));
}

#[test]
fn what_indigo_accepts_is_accepted_with_warnings() {
    let text = format!(
        "{HEAD}<!============ geometry ============>\n<renderer_settings><width>40</width>\n<width>80</width><height>20</height></renderer_settings>\n\
         {}<model><pos>0 0 0</pos><mesh_name>q</mesh_name></model>\n<fluffy_clouds/>\n</scene>",
        quad_mesh("")
    );
    let (_d, r) = load_text(&text, &ParseOptions::default());
    let d = r.unwrap();
    assert_eq!(d.film.as_ref().unwrap().params.int("xresolution"), Some(40));
    let dup = d
        .warnings
        .iter()
        .find(|w| w.message.contains("duplicated <width>"))
        .unwrap();
    assert_eq!(dup.loc.line, 4);
    let unknown = d
        .warnings
        .iter()
        .find(|w| w.message.contains("fluffy_clouds"))
        .unwrap();
    assert_eq!(unknown.loc.line, 7);
}
