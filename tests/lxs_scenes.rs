//! Integration tests over the real scenes in ../shared/scenes: every scene parses (except the
//! SunSky_Params pair, whose geometry file is missing on purpose), and cornell.lxs matches
//! hand-checked values.

use glam::DVec3;
use luxfarm::lxs::{self, LxsErrorKind, ParseOptions, SceneDescription};
use std::path::Path;

mod common;

use common::{all_scenes, shared};

/// Scenes that include the missing `SunSky_Params-geom.lxo`.
fn includes_missing_geometry(p: &Path) -> bool {
    p.parent().is_some_and(|d| d.ends_with("sunsky_params"))
}

#[test]
fn every_shared_scene_parses() {
    let scenes = all_scenes(&shared().join("scenes"));
    assert!(scenes.len() >= 19, "found only {} scenes", scenes.len());
    for s in scenes.iter().filter(|s| !includes_missing_geometry(s)) {
        let d = lxs::parse_file(s, &ParseOptions::default())
            .unwrap_or_else(|e| panic!("{} failed: {e}", s.display()));
        assert!(d.camera.is_some(), "{}", s.display());
        assert!(
            !d.shapes.is_empty() || !d.instances.is_empty(),
            "{}",
            s.display()
        );
        // The server's confinement accepts every shipped scene too.
        let confined = ParseOptions {
            confine_to_root: true,
            ..ParseOptions::default()
        };
        lxs::parse_file(s, &confined).unwrap_or_else(|e| panic!("{} confined: {e}", s.display()));
    }
}

#[test]
fn sunsky_params_names_the_missing_include_and_its_location() {
    let scene = shared().join("scenes/testsuite/sunsky_params/SunSky_Params.lxs");
    let err = lxs::parse_file(&scene, &ParseOptions::default()).unwrap_err();
    assert_eq!(err.kind, LxsErrorKind::MissingInclude);
    assert!(err.loc.file.ends_with("SunSky_Params.lxs"), "{err}");
    assert_eq!((err.loc.line, err.loc.col), (47, 1));
    assert!(err.message.contains("SunSky_Params-geom.lxo"), "{err}");
    let shown = err.to_string();
    assert!(shown.contains("SunSky_Params.lxs:47:1:"), "{shown}");
    // Its sibling includes the same missing geometry file.
    let scene = shared().join("scenes/testsuite/sunsky_params/SunSky_Default.lxs");
    let err = lxs::parse_file(&scene, &ParseOptions::default()).unwrap_err();
    assert_eq!(
        (err.kind, err.loc.line, err.loc.col),
        (LxsErrorKind::MissingInclude, 45, 1)
    );
}

fn cornell() -> SceneDescription {
    let scene = shared().join("scenes/cornell/cornell.lxs");
    lxs::parse_file(&scene, &ParseOptions::default()).unwrap()
}

#[test]
fn cornell_camera_and_film() {
    let d = cornell();
    let cam = d.camera.as_ref().unwrap();
    assert_eq!(cam.entity.kind, "perspective");
    assert_eq!(cam.entity.params.float("fov"), Some(39.3));
    assert!(!cam.world_to_camera.is_animated());
    let w2c = cam.world_to_camera.start();
    // LookAt 0 -3.9 1  0 0 1  0 0 1: the eye goes to the origin, the target onto +z.
    assert!(w2c.transform_point3(DVec3::new(0.0, -3.9, 1.0)).length() < 1e-9);
    let t = w2c.transform_point3(DVec3::new(0.0, 0.0, 1.0));
    assert!((t - DVec3::new(0.0, 0.0, 3.9)).length() < 1e-9);
    assert!((w2c.transform_vector3(DVec3::Z) - DVec3::Y).length() < 1e-9);
    let cam_cs = d.coordinate_systems["camera"];
    assert!((cam_cs * w2c).abs_diff_eq(glam::DMat4::IDENTITY, 1e-12));

    let film = d.film.as_ref().unwrap();
    assert_eq!(film.kind, "fleximage");
    assert_eq!(film.params.int("xresolution"), Some(256));
    assert_eq!(film.params.int("yresolution"), Some(256));
    assert_eq!(film.params.int("haltspp"), Some(64));
    assert_eq!(film.params.bool("write_exr"), Some(true));
    assert_eq!(
        d.sampler.as_ref().unwrap().params.int("pixelsamples"),
        Some(1)
    );
    assert_eq!(
        d.surface_integrator
            .as_ref()
            .unwrap()
            .params
            .int("maxdepth"),
        Some(8)
    );
    assert!(d.warnings.is_empty(), "{:?}", d.warnings);
    assert_eq!(d.light_groups, vec!["default".to_string()]);
}

#[test]
fn cornell_materials_lamp_and_spheres() {
    let d = cornell();
    assert_eq!(d.named_materials.len(), 4);
    let kinds: Vec<(&str, &str)> = ["white", "red", "green", "glass"]
        .iter()
        .map(|n| (*n, d.named_material(n).unwrap().entity.kind.as_str()))
        .collect();
    assert_eq!(
        kinds,
        vec![
            ("white", "matte"),
            ("red", "matte"),
            ("green", "matte"),
            ("glass", "glass")
        ]
    );
    let red = d.named_material("red").unwrap();
    assert_eq!(red.entity.params.color("Kd"), Some([0.63, 0.065, 0.05]));
    assert_eq!(
        d.named_material("glass")
            .unwrap()
            .entity
            .params
            .float("index"),
        Some(1.5)
    );

    assert_eq!(d.shapes.len(), 6);
    let lit: Vec<_> = d.shapes.iter().filter(|s| s.area_light.is_some()).collect();
    assert_eq!(lit.len(), 1);
    let lamp = lit[0];
    assert_eq!(lamp.entity.kind, "trianglemesh");
    assert_eq!((lamp.entity.loc.line, lamp.entity.loc.col), (36, 3));
    let p = lamp.entity.params.points("P").unwrap();
    assert_eq!(p.len(), 4);
    assert!(p.iter().all(|v| v[2] == 1.99));
    assert_eq!(
        lamp.entity.params.ints("indices"),
        Some(&[0, 2, 1, 0, 3, 2][..])
    );
    let al = lamp.area_light.as_ref().unwrap();
    assert_eq!(al.entity.kind, "area");
    assert_eq!(al.entity.params.color("L"), Some([17.0, 12.0, 4.0]));
    assert_eq!(al.light_group, "default");
    assert_eq!(lamp.material, d.named_materials.get("white").copied());

    let spheres: Vec<_> = d
        .shapes
        .iter()
        .filter(|s| s.entity.kind == "sphere")
        .collect();
    assert_eq!(spheres.len(), 2);
    let expect = [
        ([-0.4, 0.3, 0.4], 0.4f32, "white"),
        ([0.45, -0.3, 0.35], 0.35, "glass"),
    ];
    for (s, (t, r, mat)) in spheres.iter().zip(expect) {
        let m = s.object_to_world.start();
        let c = m.transform_point3(DVec3::ZERO);
        assert!((c - DVec3::from(t)).length() < 1e-9, "{c}");
        assert!(m.transform_vector3(DVec3::X).abs_diff_eq(DVec3::X, 1e-12));
        assert_eq!(s.entity.params.float("radius"), Some(r));
        assert_eq!(s.material, d.named_materials.get(mat).copied());
    }
    // Walls were declared in attribute blocks with identity transforms.
    assert_eq!(d.shapes[0].object_to_world.start(), glam::DMat4::IDENTITY);
}

#[test]
fn description_json_roundtrip() {
    let d = cornell();
    let json = serde_json::to_string(&d).unwrap();
    let back: SceneDescription = serde_json::from_str(&json).unwrap();
    assert_eq!(back, d);
    assert!(json.contains("\"haltspp\""));
}

#[test]
fn description_with_textures_json_roundtrip() {
    let scene = shared().join("scenes/testsuite/uvmaptest/uvmaptest.lxs");
    let d = lxs::parse_file(&scene, &lxs::ParseOptions::default()).unwrap();
    assert!(!d.named_textures.is_empty());
    let json = serde_json::to_string(&d).unwrap();
    let back: SceneDescription = serde_json::from_str(&json).unwrap();
    assert_eq!(back, d);
}
