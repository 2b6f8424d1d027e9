//! Issue 21's "model only what a scene requires": a scene with hundreds of unused textures
//! (a third of them image maps with their own files), materials and objects (half of them
//! naming PLY files that do not exist) builds exactly what the same scene without them
//! builds. Controls show the check can fail: referencing one unused object or material
//! makes the build read its file.

use luxfarm_bench::unused::{generate, parse_and_build};

const COUNT: usize = 300;

#[test]
fn unused_textures_materials_and_objects_are_not_built() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = generate(dir.path(), COUNT).unwrap();
    let base = parse_and_build(&scenes.base).unwrap().built;
    let padded = parse_and_build(&scenes.padded).unwrap().built;
    assert_eq!(base.materials, ["ball", "floor"]);
    assert_eq!(base.textures, ["floortex"]);
    assert_eq!((base.images, base.objects, base.lights), (1, 0, 1));
    assert_eq!(padded, base, "the unused statements changed what was built");
}

/// Appends `extra` before `WorldEnd` of the padded scene and builds it.
fn padded_with(extra: &str) -> anyhow::Result<luxfarm::scene::BuiltSummary> {
    let dir = tempfile::tempdir().unwrap();
    let scenes = generate(dir.path(), COUNT).unwrap();
    let text = std::fs::read_to_string(&scenes.padded).unwrap();
    let text = text.replace("WorldEnd", &format!("{extra}\nWorldEnd"));
    std::fs::write(&scenes.padded, text).unwrap();
    parse_and_build(&scenes.padded).map(|r| r.built)
}

#[test]
fn a_referenced_object_or_material_is_built_with_its_files() {
    // u_obj0 names a PLY file that does not exist: instancing it must fail on that file.
    let err = padded_with("ObjectInstance \"u_obj0\"").unwrap_err();
    assert!(err.to_string().contains("u_mesh0.ply"), "{err}");
    // u_mat0 is a matte with an image-mapped Kd: using it reads one more image.
    let built = padded_with(
        "AttributeBegin\nNamedMaterial \"u_mat0\"\nShape \"sphere\" \"float radius\" [0.1]\nAttributeEnd",
    )
    .unwrap();
    assert_eq!(built.images, 2);
    assert_eq!(built.textures, ["floortex", "u_tex0"]);
    assert_eq!(built.materials, ["ball", "floor", "u_mat0"]);
}
