//! Malformed .mi input: each case must fail with the right kind of error at the line and
//! column of the offending token (never a panic), and a well-formed scene built from the
//! same pieces must import, so every case fails for its one defect.

use luxfarm::formats::mi;
use luxfarm::lxs::{LxsError, LxsErrorKind as K, ParseOptions};

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
    match mi::parse_str(text, "t.mi", opts) {
        Ok(_) => panic!("imported without error: {text:?}"),
        Err(e) => e,
    }
}

/// Asserts the kind, and the line/column of the first occurrence of `at`.
fn check(text: &str, at: &str, kind: K) -> LxsError {
    check_with(text, at, kind, &ParseOptions::default())
}

fn check_with(text: &str, at: &str, kind: K, opts: &ParseOptions) -> LxsError {
    let e = parse_err(text, opts);
    assert_eq!(e.kind, kind, "{text:?}: {e}");
    assert_eq!((e.loc.line, e.loc.col), pos(text, at), "{text:?}: {e}");
    assert_eq!(&*e.loc.file, "t.mi");
    assert!(!e.message.contains('\n'), "one-line reason: {e}");
    e
}

const OPTIONS: &str = "options \"opt\"\n  trace depth 2 2 4\nend options\n";
const CAMERA: &str = "camera \"cam\"\n  focal 50\n  aperture 36\n  aspect 1\n  resolution 32 32\nend camera\ninstance \"cam_inst\" \"cam\"\nend instance\n";
const OBJECT: &str = "object \"quad\"\n  group\n    0 0 0\n    1 0 0\n    1 1 0\n    0 1 0\n    v 0\n    v 1\n    v 2\n    v 3\n    p 0 1 2 3\n  end group\nend object\ninstance \"quad_inst\" \"quad\"\nend instance\n";
const LIGHT: &str = "shader \"pl\" \"mib_light_point\" (\n  \"color\" 1 1 1\n)\nlight \"pt\"\n  = \"pl\"\n  origin 0 0 5\nend light\ninstance \"pt_inst\" \"pt\"\nend instance\n";
const GROUP: &str = "instgroup \"root\"\n  \"cam_inst\" \"quad_inst\" \"pt_inst\"\nend instgroup\nrender \"root\" \"cam_inst\" \"opt\"\n";

/// The well-formed scene with `part` replaced by `with`.
fn scene_with(part: &str, with: &str) -> String {
    let s = [OPTIONS, CAMERA, OBJECT, LIGHT, GROUP].concat();
    assert!(s.contains(part), "{part:?}");
    s.replacen(part, with, 1)
}

#[test]
fn the_base_scene_imports() {
    let s = scene_with("", "");
    let d = mi::parse_str(&s, "t.mi", &ParseOptions::default()).expect("imports");
    assert_eq!(d.shapes.len(), 1);
    assert_eq!(d.lights.len(), 1);
    assert!(d.camera.is_some());
}

#[test]
fn malformed_scenes_give_located_errors() {
    // (the replaced text, its replacement, where the error is, its kind)
    let cases: &[(&str, &str, &str, K)] = &[
        // 1. A statement mental ray does not have.
        (
            "options \"opt\"",
            "optoins \"opt\"",
            "optoins",
            K::UnknownStatement,
        ),
        // 2. A string without its closing quote.
        (
            "camera \"cam\"",
            "camera \"cam",
            "\"cam\n",
            K::UnterminatedString,
        ),
        // 3. A vertex with a word among its coordinates.
        ("    1 0 0\n", "    1 zero 0\n", "zero", K::Syntax),
        // 4. A polygon naming a vertex record that does not exist.
        ("p 0 1 2 3", "p 0 1 2 9", "9\n", K::InvalidValue),
        // 5. An object whose group never ends: the next statement cannot be in a group.
        (
            "  end group\nend object\n",
            "",
            "instance \"quad_inst\"",
            K::Unsupported,
        ),
        // 6. A stray end.
        (
            "end options\n",
            "end options\nend camera\n",
            "end camera",
            K::UnknownStatement,
        ),
        // 7. A transform with 15 numbers.
        (
            "instance \"quad_inst\" \"quad\"\n",
            "instance \"quad_inst\" \"quad\"\n  transform 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0\n",
            "end instance\nshader",
            K::Syntax,
        ),
        // 8. A singular transform.
        (
            "instance \"quad_inst\" \"quad\"\n",
            "instance \"quad_inst\" \"quad\"\n  transform 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 1\n",
            "transform",
            K::InvalidValue,
        ),
        // 9. An instance of something never defined.
        (
            "\"quad_inst\" \"quad\"",
            "\"quad_inst\" \"nothing\"",
            "\"nothing\"",
            K::Undefined,
        ),
        // 10. A render statement naming a missing root.
        (
            "render \"root\"",
            "render \"rooot\"",
            "\"rooot\"",
            K::Undefined,
        ),
        // 11. A camera resolution of zero.
        (
            "resolution 32 32",
            "resolution 0 32",
            "0 32",
            K::InvalidValue,
        ),
        // 12. A number too large for its type.
        (
            "resolution 32 32",
            "resolution 99999999999999999999 32",
            "99999999999999999999",
            K::InvalidValue,
        ),
        // 13. A shader parameter list without its closing parenthesis.
        (
            "  \"color\" 1 1 1\n)\n",
            "  \"color\" 1 1 1\n",
            "light \"pt\"",
            K::Syntax,
        ),
        // 14. A light whose area primitive has a negative radius.
        (
            "  origin 0 0 5\n",
            "  origin 0 0 5\n  disc 0 0 -1 -2\n",
            "disc",
            K::InvalidValue,
        ),
        // 15. A missing .mi include.
        (
            OPTIONS,
            "$include \"missing.mi\"\noptions \"opt\"\n  trace depth 2 2 4\nend options\n",
            "$include",
            K::MissingInclude,
        ),
        // 16. A stray character.
        ("  focal 50\n", "  focal 50 @\n", "@", K::Syntax),
        // 17. $endif without $ifdef.
        (OPTIONS, "$endif\n", "$endif", K::UnmatchedEnd),
        // 18. An instgroup naming a missing instance.
        (
            "\"cam_inst\" \"quad_inst\" \"pt_inst\"",
            "\"cam_inst\" \"quad_inst\" \"pt_inst\" \"ghost\"",
            "\"ghost\"",
            K::Undefined,
        ),
    ];
    let mut failures = Vec::new();
    for (i, (part, with, at, kind)) in cases.iter().enumerate() {
        let text = scene_with(part, with);
        let r = std::panic::catch_unwind(|| check(&text, at, *kind));
        match r {
            Ok(e) => eprintln!("case {}: {e}", i + 1),
            Err(_) => failures.push(i + 1),
        }
    }
    assert!(failures.is_empty(), "failing cases: {failures:?}");
}

#[test]
fn upload_limits_are_located_errors() {
    let text = scene_with("", "");
    // 19. More vertices than a list may hold.
    let small = ParseOptions {
        max_array_len: 3,
        ..ParseOptions::default()
    };
    let e = parse_err(&text, &small);
    assert_eq!(e.kind, K::ArrayTooLong, "{e}");
    assert!(e.loc.line > 0 && &*e.loc.file == "t.mi", "{e}");
    // 20. More bytes than the budget.
    let tiny = ParseOptions {
        max_total_bytes: 64,
        ..ParseOptions::default()
    };
    let e = parse_err(&text, &tiny);
    assert_eq!(e.kind, K::InputTooLarge, "{e}");
}

/// Every prefix of a valid scene and every single-byte corruption of it imports or fails
/// with an error; none panics.
#[test]
fn truncations_and_corruptions_never_panic() {
    let text = scene_with("", "");
    let opts = ParseOptions::default();
    let mut errors = 0;
    for cut in 0..text.len() {
        if text.is_char_boundary(cut) && mi::parse_str(&text[..cut], "t.mi", &opts).is_err() {
            errors += 1;
        }
    }
    // Most prefixes end inside a block or before the render statement.
    assert!(errors > text.len() / 2, "{errors} of {}", text.len());
    let bytes = text.as_bytes();
    for i in (0..bytes.len()).step_by(3) {
        for b in [b'"', b'(', b'-', b'9', b'\n', b'e', b'$'] {
            let mut v = bytes.to_vec();
            v[i] = b;
            let s = String::from_utf8_lossy(&v);
            let _ = mi::parse_str(&s, "t.mi", &opts);
        }
    }
}
