//! Malformed inputs: each one must fail with the right kind of error at the right line and
//! column (and never panic).

use luxfarm::lxs::{self, LxsError, LxsErrorKind as K, ParseOptions};
use std::path::{Path, PathBuf};

const OPTS: ParseOptions = ParseOptions {
    confine_to_root: false,
    max_include_depth: 32,
    max_array_len: 1 << 28,
    max_total_bytes: u64::MAX,
    max_copied_values: luxfarm::lxs::describe::MAX_COPIED_VALUES,
    frame: None,
};

/// Line and column (1-based) of the first occurrence of `needle` in `text`.
fn pos(text: &str, needle: &str) -> (u32, u32) {
    let at = text
        .find(needle)
        .unwrap_or_else(|| panic!("{needle:?} not in {text:?}"));
    let before = &text[..at];
    let line = before.matches('\n').count() as u32 + 1;
    let col = (at - before.rfind('\n').map_or(0, |i| i + 1)) as u32 + 1;
    (line, col)
}

fn parse_err(text: &str, opts: &ParseOptions) -> LxsError {
    match lxs::parse_str(text, "t.lxs", opts) {
        Ok(_) => panic!("parsed without error: {text:?}"),
        Err(e) => e,
    }
}

/// Asserts kind, and line/column at the first occurrence of `at`.
fn check(text: &str, at: &str, kind: K) -> LxsError {
    let e = parse_err(text, &OPTS);
    assert_eq!(e.kind, kind, "{text:?}: {e}");
    assert_eq!((e.loc.line, e.loc.col), pos(text, at), "{text:?}: {e}");
    assert_eq!(&*e.loc.file, "t.lxs");
    assert!(!e.message.contains('\n'), "one-line reason: {e}");
    e
}

/// Asserts kind and an explicit line/column.
fn check_at(text: &str, at: (u32, u32), kind: K) -> LxsError {
    let e = parse_err(text, &OPTS);
    assert_eq!(e.kind, kind, "{text:?}: {e}");
    assert_eq!((e.loc.line, e.loc.col), at, "{text:?}: {e}");
    e
}

const W: &str = "WorldBegin\n";

fn world(body: &str) -> String {
    format!("{W}{body}\nWorldEnd\n")
}

#[test]
fn unknown_statement_suggests_nearest() {
    let e = check("Shap \"sphere\"\n", "Shap", K::UnknownStatement);
    assert!(e.message.contains("'Shape'"), "{e}");
    let e = check(
        &world("  AtributeBegin"),
        "AtributeBegin",
        K::UnknownStatement,
    );
    assert!(e.message.contains("AttributeBegin"), "{e}");
    let e = check("Zzyzx\n", "Zzyzx", K::UnknownStatement);
    assert!(!e.message.contains("did you mean"), "{e}");
}

#[test]
fn unterminated_strings() {
    check(
        "Camera \"perspective\nWorldBegin\n",
        "\"perspective",
        K::UnterminatedString,
    );
    let t = "Film \"fleximage\" \"string filename\" [\"abc";
    check(t, "\"abc", K::UnterminatedString);
}

#[test]
fn unterminated_arrays() {
    let t = world("Shape \"trianglemesh\" \"point P\" [0 0 0");
    check(&t, "[", K::UnterminatedArray);
    let t = "WorldBegin\nShape \"sphere\" \"float radius\" [1\n";
    check(t, "[", K::UnterminatedArray);
    check("Transform [1 0 0\n", "[", K::UnterminatedArray);
}

#[test]
fn wrong_value_counts() {
    let t = world("Shape \"trianglemesh\" \"integer indices\" [0 1 2] \"point P\" [0 0 0 1]");
    let e = check(&t, "\"point P\"", K::WrongValueCount);
    assert!(e.message.contains("multiple of 3"), "{e}");
    check(
        "Camera \"perspective\" \"float fov\"\nWorldBegin\n",
        "\"float fov\"",
        K::WrongValueCount,
    );
    check(
        &world("Material \"matte\" \"texture Kd\" [\"a\" \"b\"]"),
        "\"texture Kd\"",
        K::WrongValueCount,
    );
    check(
        "Translate 1 2\nWorldBegin\n",
        "Translate",
        K::WrongValueCount,
    );
    check(
        "LookAt 0 0 0 1 1 1 0 0\nWorldBegin\n",
        "LookAt",
        K::WrongValueCount,
    );
    check(
        "Transform [1 0 0 0 0 1 0 0 0 0 1 0 0 0 0]\n",
        "Transform",
        K::WrongValueCount,
    );
    check("Scale 1 2 3 4\n", "Scale", K::WrongValueCount);
    let t = world("MotionBegin [0 1]\nTranslate 1 0 0\nMotionEnd");
    check(&t, "MotionEnd", K::WrongValueCount);
}

#[test]
fn wrong_value_types() {
    check(
        "Camera \"perspective\" \"float fov\" [45 \"x\"]\n",
        "\"x\"",
        K::WrongValueType,
    );
    check(
        "Film \"fleximage\" \"string filename\" [3]\n",
        "3]",
        K::WrongValueType,
    );
    check(
        "Film \"fleximage\" \"string filename\" 3\n",
        "3\n",
        K::WrongValueType,
    );
    check(
        "Film \"fleximage\" \"bool write_png\" [\"yes\"]\n",
        "\"bool",
        K::WrongValueType,
    );
    check("Camera 45\n", "45", K::WrongValueType);
    check("Translate 1 2 \"z\"\n", "\"z\"", K::WrongValueType);
    check(
        &world("Texture \"t\" \"vector\" \"constant\""),
        "Texture",
        K::WrongValueType,
    );
}

#[test]
fn unknown_parameter_types_and_bad_declarations() {
    let e = check(
        "Camera \"perspective\" \"flaot fov\" [45]\n",
        "\"flaot",
        K::UnknownParamType,
    );
    assert!(e.message.contains("'float'"), "{e}");
    check(
        "Camera \"perspective\" \"float\" [45]\n",
        "\"float\"",
        K::Syntax,
    );
}

#[test]
fn bad_numbers_and_characters() {
    check("Translate 1 2 3.4.5\n", "3.4.5", K::InvalidNumber);
    check(
        "Camera \"perspective\" \"float fov\" [1e99]\n",
        "1e99",
        K::InvalidNumber,
    );
    check(
        "Shape \"x\" \"integer n\" [3000000000]\n",
        "3000000000",
        K::InvalidNumber,
    );
    check(&world("@"), "@", K::Syntax);
    check("Translate 1 2 3abc\n", "3abc", K::Syntax);
    check("[1 2]\n", "[", K::Syntax);
}

#[test]
fn invalid_values() {
    check("Rotate 30 0 0 0\n", "Rotate", K::InvalidValue);
    check("LookAt 0 0 0 0 0 0 0 0 1\n", "LookAt", K::InvalidValue);
    check("LookAt 0 0 0 0 0 1 0 0 1\n", "LookAt", K::InvalidValue);
    check(
        "Scale 0 0 0\nCamera \"perspective\"\n",
        "Camera",
        K::InvalidValue,
    );
}

#[test]
fn statements_in_the_wrong_block() {
    check(
        "Shape \"sphere\"\nWorldBegin\nWorldEnd\n",
        "Shape",
        K::WrongBlock,
    );
    check(&world("Camera \"perspective\""), "Camera", K::WrongBlock);
    check("AttributeBegin\n", "AttributeBegin", K::WrongBlock);
    check(
        &world("MotionBegin [0 1]\nMaterial \"matte\""),
        "Material",
        K::WrongBlock,
    );
    check(
        "WorldBegin\nWorldEnd\nShape \"sphere\"\n",
        "Shape",
        K::WrongBlock,
    );
    check_at("WorldBegin\nWorldBegin\n", (2, 1), K::WrongBlock);
    let t = world("ObjectBegin \"a\"\nObjectBegin \"b\"");
    check(&t, "ObjectBegin \"b\"", K::WrongBlock);
    check(
        "Sampler \"random\"\nWorldBegin\nSampler \"sobol\"\n",
        "Sampler \"sobol\"",
        K::WrongBlock,
    );
}

#[test]
fn unmatched_ends() {
    check(&world("AttributeEnd"), "AttributeEnd", K::UnmatchedEnd);
    check(
        &world("AttributeBegin\nTransformEnd"),
        "TransformEnd",
        K::UnmatchedEnd,
    );
    let e = check(
        &world("TransformBegin\nAttributeEnd"),
        "AttributeEnd",
        K::UnmatchedEnd,
    );
    assert!(e.message.contains("TransformBegin at t.lxs:2:1"), "{e}");
    check(&world("ObjectEnd"), "ObjectEnd", K::UnmatchedEnd);
    check(&world("MotionEnd"), "MotionEnd", K::UnmatchedEnd);
    check(
        &world("ObjectBegin \"o\"\nAttributeBegin\nObjectEnd"),
        "ObjectEnd",
        K::UnmatchedEnd,
    );
}

#[test]
fn unclosed_blocks() {
    check(
        "WorldBegin\n  AttributeBegin\nWorldEnd\n",
        "AttributeBegin",
        K::UnclosedBlock,
    );
    check(
        "WorldBegin\nShape \"sphere\"\n",
        "WorldBegin",
        K::UnclosedBlock,
    );
    check(
        "TransformBegin\nTranslate 1 0 0\n",
        "TransformBegin",
        K::UnclosedBlock,
    );
    check(
        "TransformBegin\nWorldBegin\n",
        "TransformBegin",
        K::UnclosedBlock,
    );
    check(
        "WorldBegin\nMotionBegin [0 1]\nTranslate 1 0 0\n",
        "MotionBegin",
        K::UnclosedBlock,
    );
    // WorldEnd inside a motion block is refused where it stands.
    check(
        &world("MotionBegin [0 1]\nTranslate 1 0 0"),
        "WorldEnd",
        K::WrongBlock,
    );
}

#[test]
fn undefined_names() {
    let t =
        world("MakeNamedMaterial \"white\" \"string type\" [\"matte\"]\nNamedMaterial \"whte\"");
    let e = check(&t, "NamedMaterial \"whte\"", K::Undefined);
    assert!(e.message.contains("\"white\""), "{e}");
    // Named materials are scoped by AttributeBegin/AttributeEnd, as in LuxRender.
    let t = world("AttributeBegin\nMakeNamedMaterial \"m\"\nAttributeEnd\nNamedMaterial \"m\"");
    check_at(&t, (5, 1), K::Undefined);
    check(
        &world("Material \"matte\" \"texture Kd\" \"wood\""),
        "\"texture Kd\"",
        K::Undefined,
    );
    // A float texture is not a color texture.
    let t = world("Texture \"t\" \"float\" \"constant\" \"float value\" [1]\nMaterial \"matte\" \"texture Kd\" \"t\"");
    check(&t, "\"texture Kd\"", K::Undefined);
    let t = world("Texture \"a\" \"color\" \"scale\" \"texture tex1\" \"b\"");
    check(&t, "\"texture tex1\"", K::Undefined);
    check(
        &world("ObjectInstance \"tree\""),
        "ObjectInstance",
        K::Undefined,
    );
    check(&world("Interior \"water\""), "Interior", K::Undefined);
    check(&world("Exterior \"fog\""), "Exterior", K::Undefined);
    check(
        &world("CoordSysTransform \"lamp\""),
        "CoordSysTransform",
        K::Undefined,
    );
    let t = world(
        "Material \"mix\" \"string namedmaterial1\" [\"a\"] \"string namedmaterial2\" [\"b\"]",
    );
    check(&t, "\"string namedmaterial1\"", K::Undefined);
    check(
        &world("ObjectBegin \"o\"\nObjectInstance \"o\""),
        "ObjectInstance",
        K::InvalidValue,
    );
}

#[test]
fn limits() {
    let small = ParseOptions {
        max_array_len: 4,
        ..OPTS
    };
    let t = "Camera \"perspective\" \"float screenwindow\" [1 2 3 4 5]\n";
    let e = parse_err(t, &small);
    assert_eq!((e.kind, e.loc.line, e.loc.col), (K::ArrayTooLong, 1, 22));
    let tiny = ParseOptions {
        max_total_bytes: 16,
        ..OPTS
    };
    let e = parse_err("LookAt 0 0 0 0 1 0 0 0 1\nWorldBegin\nWorldEnd\n", &tiny);
    assert_eq!(e.kind, K::InputTooLarge);
    assert_eq!(e.loc.line, 1);
}

fn data(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/lxs")
        .join(p)
}

fn file_err(p: &str, opts: &ParseOptions) -> LxsError {
    match lxs::parse_file(&data(p), opts) {
        Ok(_) => panic!("{p} parsed"),
        Err(e) => e,
    }
}

#[test]
fn missing_include_names_file_and_include_location() {
    let e = file_err("missing_include.lxs", &OPTS);
    assert_eq!((e.kind, e.loc.line, e.loc.col), (K::MissingInclude, 3, 1));
    assert!(e.loc.file.ends_with("missing_include.lxs"));
    assert!(e.message.contains("no-such-file.lxo"), "{e}");
}

#[test]
fn include_cycle_and_depth() {
    let e = file_err("cycle_a.lxs", &OPTS);
    assert_eq!((e.kind, e.loc.line, e.loc.col), (K::IncludeCycle, 2, 3));
    assert!(e.loc.file.ends_with("cycle_b.lxo"), "{e}");
    let shallow = ParseOptions {
        max_include_depth: 1,
        ..OPTS
    };
    let e = file_err("deep_a.lxs", &shallow);
    assert_eq!((e.kind, e.loc.line, e.loc.col), (K::IncludeTooDeep, 1, 1));
    assert!(e.loc.file.ends_with("deep_b.lxo"), "{e}");
    lxs::parse_file(&data("deep_a.lxs"), &OPTS).unwrap();
}

#[test]
fn errors_inside_nested_includes_name_that_file() {
    let e = file_err("nested/scene.lxs", &OPTS);
    assert_eq!((e.kind, e.loc.line, e.loc.col), (K::WrongValueType, 2, 51));
    assert!(e.loc.file.ends_with("nested/sub/more.lxo"), "{e}");
    // Includes resolve relative to the including file, and the CTM follows the blocks.
    let d = lxs::parse_file(&data("nested/good.lxs"), &OPTS).unwrap();
    assert_eq!(d.files.len(), 3);
    assert_eq!(d.shapes.len(), 1);
    let t = d.shapes[0]
        .object_to_world
        .start()
        .transform_point3(glam::DVec3::ZERO);
    assert_eq!(t, glam::DVec3::X);
    assert!(d.shapes[0].entity.loc.file.ends_with("ok2.lxo"));
}

#[test]
fn confinement_to_the_root_directory() {
    let confined = ParseOptions {
        confine_to_root: true,
        ..OPTS
    };
    let e = file_err("confine/escape.lxs", &confined);
    assert_eq!(
        (e.kind, e.loc.line, e.loc.col),
        (K::IncludeOutsideRoot, 2, 1)
    );
    let e = file_err("confine/absolute.lxs", &confined);
    assert_eq!(
        (e.kind, e.loc.line, e.loc.col),
        (K::IncludeOutsideRoot, 2, 1)
    );
    lxs::parse_file(&data("confine/inside.lxs"), &confined).unwrap();
    // Without confinement the escape is allowed (the file exists).
    lxs::parse_file(&data("confine/escape.lxs"), &OPTS).unwrap();
}

#[cfg(unix)]
#[test]
fn confinement_follows_symlinks() {
    let dir = tempfile::tempdir().unwrap();
    let outside = tempfile::tempdir().unwrap();
    std::fs::write(outside.path().join("secret.lxo"), "Shape \"sphere\"\n").unwrap();
    std::os::unix::fs::symlink(
        outside.path().join("secret.lxo"),
        dir.path().join("link.lxo"),
    )
    .unwrap();
    let scene = dir.path().join("s.lxs");
    std::fs::write(&scene, "WorldBegin\n Include \"link.lxo\"\nWorldEnd\n").unwrap();
    let confined = ParseOptions {
        confine_to_root: true,
        ..OPTS
    };
    let e = lxs::parse_file(&scene, &confined).unwrap_err();
    assert_eq!(
        (e.kind, e.loc.line, e.loc.col),
        (K::IncludeOutsideRoot, 2, 2)
    );
    lxs::parse_file(&scene, &OPTS).unwrap();
}

#[test]
fn missing_root_file_is_an_io_error() {
    let e = lxs::parse_file(Path::new("/nonexistent/scene.lxs"), &OPTS).unwrap_err();
    assert_eq!(e.kind, K::Io);
    assert!(e.to_string().starts_with("/nonexistent/scene.lxs:"), "{e}");
}

/// Instancing copies shapes (an object instanced inside another definition; emitting shapes
/// placed per instance), so a small file could ask for unbounded memory: past
/// `max_copied_values` the instance that would copy more is an error at its line.
#[test]
fn instancing_beyond_the_copy_limit_is_an_error_at_the_instance() {
    // A 4-vertex emitting quad: 12 point values and 6 indices per copy.
    let lamp = "ObjectBegin \"lamp\"\nAreaLightSource \"area\" \"color L\" [1 1 1]\n\
                Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" \
                [0 0 0 1 0 0 1 1 0 0 1 0]\nObjectEnd\n";
    let scene = |instances: usize| {
        let mut t = format!("WorldBegin\n{lamp}");
        for i in 0..instances {
            t.push_str(&format!(
                "AttributeBegin\nTranslate {i} 0 0\nObjectInstance \"lamp\"\nAttributeEnd\n"
            ));
        }
        t + "WorldEnd\n"
    };
    let small = ParseOptions {
        max_copied_values: 18 * 3,
        ..OPTS
    };
    let desc = lxs::parse_str(&scene(3), "t.lxs", &small).expect("three copies fit");
    assert_eq!(
        desc.shapes
            .iter()
            .filter(|s| s.area_light.is_some())
            .count(),
        3
    );
    let text = scene(4);
    let e = parse_err(&text, &small);
    assert_eq!(e.kind, K::InputTooLarge, "{e}");
    // The fourth ObjectInstance.
    let fourth = text
        .match_indices("ObjectInstance")
        .nth(3)
        .map(|(i, _)| i)
        .unwrap_or(0);
    let line = text[..fourth].matches('\n').count() as u32 + 1;
    assert_eq!(e.loc.line, line, "{e}");
    // Nested instances are charged the same way.
    let nested =
        "WorldBegin\nObjectBegin \"a\"\nShape \"trianglemesh\" \"integer indices\" [0 1 2] \
         \"point P\" [0 0 0 1 0 0 0 1 0]\nObjectEnd\nObjectBegin \"b\"\nObjectInstance \"a\"\n\
         ObjectInstance \"a\"\nObjectEnd\nWorldEnd\n";
    let tight = ParseOptions {
        max_copied_values: 15,
        ..OPTS
    };
    let e = parse_err(nested, &tight);
    assert_eq!(e.kind, K::InputTooLarge, "{e}");
    assert_eq!(e.loc.line, 7, "{e}");
}
