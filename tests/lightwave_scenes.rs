//! LightWave scenes end to end: every sample .lws renders at frame 0 and at a later frame, the
//! LWSC 2 sample is refused clearly, the samples' objects sit where their envelopes put them
//! (values computed by hand from the LWSC specification's envelope rules), envelope behaviours
//! and span types of our own scene evaluate as the specification says, heading +90° turns +Z
//! into +X, and broken scenes give located errors.

// Key values are written exactly as the sample files print them.
#![allow(clippy::excessive_precision)]

mod lightwave_util;
mod render_util;

use glam::{DMat4, DVec3};
use lightwave_util::*;
use luxfarm::lxs::{LxsErrorKind, ParseOptions, SceneDescription};
use luxfarm::render::SessionOptions;

fn lws(name: &str) -> std::path::PathBuf {
    samples().join("LWS").join(name)
}

fn close(a: DVec3, b: DVec3, what: &str) {
    assert!((a - b).length() < 1e-5, "{what}: {a} != {b}");
}

/// luxfarm position of a LightWave position (x, y, z) -> (x, z, y).
fn lux(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, z, y)
}

#[test]
fn every_sample_scene_renders_at_frame_0_and_a_later_frame() {
    let mut names: Vec<String> = std::fs::read_dir(samples().join("LWS"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".lws") && n != "move_x_oldformat_56.lws")
        .collect();
    names.sort();
    assert_eq!(names.len(), 7, "{names:?}");
    for name in &names {
        let path = lws(name);
        let mut origins = Vec::new();
        for frame in [0, 30] {
            let mut desc = load_at(&path, Some(frame));
            assert_eq!(desc.shapes.len(), 1, "{name}");
            origins.push(shape_origin(&desc, 0));
            let film = desc.film.as_ref().unwrap();
            assert_eq!(
                film.params.string("filename"),
                Some(format!("{}_{frame:04}", name.trim_end_matches(".lws")).as_str())
            );
            shrink(&mut desc, 32, 24);
            let f =
                render_util::render(&desc, &samples().join("LWS"), SessionOptions::default(), 1);
            let xyz = render_util::normalized_xyz(&f);
            assert!(
                xyz.iter().flatten().all(|v| v.is_finite()),
                "{name} frame {frame}"
            );
            let mut ys: Vec<f64> = xyz.iter().map(|p| p[1]).collect();
            ys.sort_by(f64::total_cmp);
            let q = |f: f64| ys[((ys.len() - 1) as f64 * f) as usize];
            // the ambient background and the lit cube each fill part of the view; the cube
            // is several times brighter (the minimum can be negative next to its edge:
            // Mitchell's negative lobes)
            let (bg, cube) = (q(0.1), q(0.9));
            assert!(
                bg > 0.0 && cube > 3.0 * bg,
                "{name} frame {frame}: {bg} .. {cube}"
            );
        }
        assert!(
            (origins[0] - origins[1]).length() > 0.1,
            "{name}: the cube moves"
        );
    }
}

#[test]
fn the_lwsc_2_sample_is_refused_clearly() {
    let e = luxfarm::formats::load(&lws("move_x_oldformat_56.lws"), &ParseOptions::default())
        .unwrap_err();
    assert_eq!(e.kind, LxsErrorKind::Unsupported);
    let s = e.to_string();
    assert!(s.contains("move_x_oldformat_56.lws:2:1"), "{s}");
    assert!(
        s.contains("LWSC version 2") && s.contains("LightWave 6"),
        "{s}"
    );
}

#[test]
fn sample_objects_follow_their_envelopes() {
    // TCB spans with zero tension, continuity and bias. move_x channel 0 keys:
    // (0 @ 0), (2.0691125392913818 @ 2/3), (-2.3748657703399658 @ 4/3).
    // Frame 10 (1/3 s) is the middle of the first span: outgoing tangent of the first key
    // d = 2.0691125; incoming tangent of the second (v2 - v0)·(2/3)/(4/3) = -1.1874329;
    // Hermite at s = 1/2: 0.5·v1 + 0.125·out - 0.125·in = 1.4416244.
    let at = |name: &str, frame: i64| shape_origin(&load_at(&lws(name), Some(frame)), 0);
    let v1 = 2.0691125392913818;
    let v2 = -2.3748657703399658;
    let x10 = 0.5 * v1 + 0.125 * v1 - 0.125 * (0.5 * v2);
    close(
        at("move_x.lws", 10),
        lux(x10, -0.040000002831220627, 0.0),
        "move_x frame 10",
    );
    close(
        at("move_x.lws", 40),
        lux(v2, -0.040000002831220627, 0.0),
        "move_x key",
    );
    close(
        at("move_x.lws", 60),
        lux(v2, -0.040000002831220627, 0.0),
        "move_x post constant",
    );

    // Linear spans. x: (0 @ 0), (1.924918483918713 @ 2/3), (-0.52300345897674561 @ 2);
    // z: (0 @ 0), (-2.6561167240142822 @ 4/3), (-0.095800442759067794 @ 89/30).
    let (x1, x2) = (1.924918483918713, -0.52300345897674561);
    let z1 = -2.6561167240142822;
    close(
        at("move_xz_linear.lws", 10),
        lux(0.5 * x1, 0.0, 0.25 * z1),
        "linear frame 10",
    );
    close(
        at("move_xz_linear.lws", 40),
        lux(x1 + 0.5 * (x2 - x1), 0.0, z1),
        "linear frame 40",
    );
    // Stepped spans hold the key before them.
    close(
        at("move_xz_stepped.lws", 10),
        lux(0.0, 0.0, 0.0),
        "stepped frame 10",
    );
    close(
        at("move_xz_stepped.lws", 25),
        lux(x1, 0.0, 0.0),
        "stepped frame 25",
    );
    close(
        at("move_xz_stepped.lws", 50),
        lux(x1, 0.0, z1),
        "stepped frame 50",
    );
    // TCB spline: x keys (0 @ 0), (2.0153336524963379 @ 2/3), (-0.52300345897674561 @ 2);
    // in-tangent of the middle key (v2 - v0)·(2/3)/2.
    let s1 = 2.0153336524963379;
    let s_in = x2 / 3.0;
    let sx = 0.5 * s1 + 0.125 * s1 - 0.125 * s_in;
    assert!((at("move_xz_spline.lws", 10).x - sx).abs() < 1e-5);
    // Post behaviours after the last key (1.3 s): reset gives 0, constant the last value.
    assert!(at("move_x_post_reset.lws", 60).x.abs() < 1e-9);
    assert!((at("move_x_post_constant.lws", 60).x - -1.6381832361221313).abs() < 1e-6);
    // Without a frame the scene's CurrentFrame (40 in move_x.lws) is used.
    let current = load_at(&lws("move_x.lws"), None);
    close(
        shape_origin(&current, 0),
        at("move_x.lws", 40),
        "CurrentFrame",
    );
}

/// Origins of the placed objects, in item order (instances when the object is shared).
fn placed_origins(desc: &SceneDescription) -> Vec<DVec3> {
    if desc.instances.is_empty() {
        (0..desc.shapes.len())
            .map(|i| shape_origin(desc, i))
            .collect()
    } else {
        desc.instances
            .iter()
            .map(|i| i.instance_to_world.start().transform_point3(DVec3::ZERO))
            .collect()
    }
}

/// A scene of eight squares, each moved along X by one envelope (4 frames per second).
fn behaviours_scene() -> String {
    let envs = [
        // repeat, linear span
        "  2\n  Key 0 0 0 0 0 0 0 0 0\n  Key 1 1 3 0 0 0 0 0 0\n  Behaviors 1 2\n",
        // oscillate
        "  2\n  Key 0 0 0 0 0 0 0 0 0\n  Key 1 1 3 0 0 0 0 0 0\n  Behaviors 1 3\n",
        // offset repeat
        "  2\n  Key 0 0 0 0 0 0 0 0 0\n  Key 1 1 3 0 0 0 0 0 0\n  Behaviors 4 4\n",
        // linear before and after
        "  2\n  Key 0 0 0 0 0 0 0 0 0\n  Key 2 1 3 0 0 0 0 0 0\n  Behaviors 5 5\n",
        // reset before
        "  2\n  Key 3 0 0 0 0 0 0 0 0\n  Key 3 1 3 0 0 0 0 0 0\n  Behaviors 0 1\n",
        // Hermite: out tangent 3, in tangent -1
        "  2\n  Key 0 0 1 0 0 0 0 3 0\n  Key 1 2 1 0 0 0 -1 0 0\n  Behaviors 1 1\n",
        // 2-D Bezier: handles (1/3, 1) out of the first key, (-1/3, 0) into the second
        "  2\n  Key 0 0 5 0 0 0.33333333333333333 1 0 0\n  Key 1 1 5 -0.33333333333333333 0 0 0 0 0\n  Behaviors 1 1\n",
        // TCB with tension 1: zero tangents (ease in and out)
        "  2\n  Key 0 0 0 1 0 0 0 0 0\n  Key 1 1 0 1 0 0 0 0 0\n  Behaviors 1 1\n",
    ];
    let mut s = String::from("LWSC\n5\n\nFirstFrame 0\nLastFrame 20\nFramesPerSecond 4\n\n");
    for (i, e) in envs.iter().enumerate() {
        s += &format!("LoadObjectLayer 1 1000000{i} square.lwo\nObjectMotion\nNumChannels 1\nChannel 0\n{{ Envelope\n{e}}}\n");
    }
    s + "AddLight 20000000\nLightType 0\n" + &camera_block()
}

#[test]
fn envelope_behaviours_and_spans_of_our_own_scene() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("square.lwo"), square_lwo([0.8; 3])).unwrap();
    let scene = dir.path().join("behaviours.lws");
    std::fs::write(&scene, behaviours_scene()).unwrap();
    let xs = |frame: i64| -> Vec<f64> {
        let d = load_at(&scene, Some(frame));
        assert_eq!(
            d.objects.len(),
            1,
            "the square is defined once and instanced"
        );
        placed_origins(&d).iter().map(|p| p.x).collect()
    };
    let check = |frame: i64, item: usize, want: f64| {
        let got = xs(frame)[item];
        assert!(
            (got - want).abs() < 1e-9,
            "item {item} frame {frame}: {got} != {want}"
        );
    };
    // t = frame / 4
    check(6, 0, 0.5); // repeat: 1.5 s -> 0.5 s
    check(9, 0, 0.25); // 2.25 s -> 0.25 s
    check(5, 1, 0.75); // oscillate: 1.25 s is 0.25 s into the reversed copy -> 0.75
    check(10, 2, 2.5); // offset repeat: 2.5 s -> 0.5 + 2 cycles x 1
    check(-2, 2, -0.5); // offset repeat before: -0.5 s -> 0.5 - 1
    check(12, 3, 6.0); // linear after: 2 + 2 x (3 - 1)
    check(-4, 3, -2.0); // linear before: 2 x -1
    check(-2, 4, 0.0); // reset before the first key
    check(2, 4, 3.0);
    // Hermite at s = 1/2 of a 2 s span: 0.5 x 1 + 0.125 x 3 - 0.125 x (-1) = 1
    check(4, 5, 1.0);
    // 2-D Bezier: control times equally spaced, so s = 0.5 at t = 0.5: values 0,1,1,1 -> 0.875
    check(2, 6, 0.875);
    // tension 1 at s = 1/4: h2 = -2/64 + 3/16 = 0.15625
    check(1, 7, 0.15625);
}

#[test]
fn heading_plus_90_turns_plus_z_into_plus_x() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("square.lwo"), square_lwo([0.8; 3])).unwrap();
    let text = format!(
        "LWSC\n3\n\nLoadObjectLayer 1 square.lwo\nObjectMotion\n{}AddLight\n{}",
        motion([
            0.0,
            0.0,
            0.0,
            std::f64::consts::FRAC_PI_2,
            0.0,
            0.0,
            1.0,
            1.0,
            1.0
        ]),
        camera_block().replace(" 30000000", "")
    );
    let scene = dir.path().join("turn.lws");
    std::fs::write(&scene, text).unwrap();
    let d = load_at(&scene, Some(0));
    let m: DMat4 = d.shapes[0].object_to_world.start();
    // LightWave +Z is luxfarm +Y, LightWave +X is luxfarm +X.
    close(m.transform_vector3(DVec3::Y), DVec3::X, "heading +90");
}

#[test]
fn broken_scenes_give_located_errors() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("square.lwo"), square_lwo([0.8; 3])).unwrap();
    let cases: &[(&str, &str, u32)] = &[
        ("LWSC\n3\nLoadObjectLayer 1 missing.lwo\n", "missing.lwo", 3),
        ("LWSC\n3\nLoadObjectLayer 7 square.lwo\n", "no layer 7", 3),
        ("LWSC\n3\nAddLight\nLightType 12\n", "LightType 12", 4),
        ("LWSC\n3\nLoadObjectLayer 1 square.lwo\nObjectMotion\nChannel 0\n{ Envelope\n  2\n  Key 1 0 0\n}\n", "declares 2 keys", 7),
        ("LWSC\n3\nLoadObjectLayer 1 square.lwo\nParentItem 10000009\nAddCamera\n", "no item 10000009", 4),
        ("LWSC\n3\nLoadObjectLayer 1 square.lwo\n", "no camera", 0),
    ];
    for (text, needle, line) in cases {
        let scene = dir.path().join("broken.lws");
        std::fs::write(&scene, text).unwrap();
        let e = luxfarm::formats::load(&scene, &ParseOptions::default()).unwrap_err();
        let s = e.to_string();
        assert!(s.contains(needle), "{s}");
        assert_eq!(e.loc.line, *line, "{s}");
        assert!(s.contains("broken.lws"), "{s}");
    }
    // An error inside an object names the object and the scene line that loaded it.
    std::fs::write(
        dir.path().join("bad.lwo"),
        b"FORM\0\0\0\x10LWO2PNTS\0\0\0\x40xxxx",
    )
    .unwrap();
    let scene = dir.path().join("badobj.lws");
    std::fs::write(
        &scene,
        format!("LWSC\n3\nLoadObjectLayer 1 bad.lwo\n{}", camera_block()),
    )
    .unwrap();
    let s = luxfarm::formats::load(&scene, &ParseOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        s.contains("bad.lwo") && s.contains("PNTS") && s.contains("badobj.lws:3:1"),
        "{s}"
    );
}

#[test]
fn confinement_and_the_byte_budget_hold_for_objects() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("scenes")).unwrap();
    std::fs::write(dir.path().join("square.lwo"), square_lwo([0.8; 3])).unwrap();
    let scene = dir.path().join("scenes/s.lws");
    std::fs::write(
        &scene,
        format!(
            "LWSC\n3\nLoadObjectLayer 1 ../square.lwo\n{}",
            camera_block()
        ),
    )
    .unwrap();
    // Unconfined: found in the parent directory (a content directory) and listed.
    let d = load_at(&scene, Some(0));
    assert!(
        d.files.iter().any(|f| f.ends_with("square.lwo")),
        "{:?}",
        d.files
    );
    let confined = ParseOptions {
        confine_to_root: true,
        ..ParseOptions::default()
    };
    let e = luxfarm::formats::load(&scene, &confined).unwrap_err();
    assert!(
        e.to_string().contains("not found") && e.loc.line == 3,
        "{e}"
    );
    // Room for the scene but not for its object.
    let small = ParseOptions {
        max_total_bytes: std::fs::metadata(&scene).unwrap().len() + 10,
        ..ParseOptions::default()
    };
    let e = luxfarm::formats::load(&scene, &small).unwrap_err();
    assert_eq!(e.kind, LxsErrorKind::InputTooLarge, "{e}");
    assert_eq!(e.loc.line, 3, "{e}");
}
