//! Indigo scenes (`.igs`) through the `luxfarm` binary: `parse` shows a scene's medium (the
//! absorbing glass slab of `tests/data/indigo/slab.igs`, whose render `tests/indigo_media.rs`
//! checks against Beer–Lambert), and `submit` bundles a scene with the external `.igmesh`
//! meshes it names (the glare-core samples under `../shared/scenes/formats/indigo/igmesh/`,
//! versions 3 and 4, named with Windows paths as exporters write them) for a master whose
//! worker renders it from the bundle alone.

mod farm_common;

use farm_common::cli_common::{luxfarm, stdout_ok};
use farm_common::*;
use serde_json::Value;
use std::path::{Path, PathBuf};

fn slab() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/indigo/slab.igs")
}

#[test]
fn parse_shows_the_medium() {
    let scene = slab();
    let summary = stdout_ok(&luxfarm(&["parse", &scene.to_string_lossy()]));
    assert!(
        summary.lines().any(|l| l == "volumes: 1 (ink: clear)"),
        "{summary}"
    );
    assert!(summary.contains("warnings: 0"), "{summary}");

    let out = luxfarm(&["parse", &scene.to_string_lossy(), "--json"]);
    let j: Value = serde_json::from_str(&stdout_ok(&out)).expect("JSON");
    let v = &j["volumes"][0];
    assert_eq!(v["name"], "ink");
    let param = |name: &str| {
        v["entity"]["params"]["params"]
            .as_array()
            .and_then(|ps| ps.iter().find(|p| p["name"] == name))
            .map(|p| p["value"]["values"][0].clone())
            .unwrap_or(Value::Null)
    };
    // The absorption coefficient (per metre) and the medium's index.
    assert_eq!(param("absorption"), serde_json::json!([2.0, 2.0, 2.0]));
    assert_eq!(param("fresnel"), 1.5);
    // The slab (not the black screen) has the medium inside, and its glass takes the index.
    let shapes = j["shapes"].as_array().unwrap();
    let inside: Vec<&Value> = shapes.iter().filter(|s| s["interior"] == "ink").collect();
    assert_eq!(inside.len(), 1, "{shapes:?}");
    assert_eq!(shapes.len(), 2);
}

/// `dir/two.igs`: a uniform background, a grey diffuse material, and two external meshes in
/// `dir/meshes/` (cuboid: .igmesh v3; teapot: v4, zstd-compressed).
fn two_meshes(dir: &Path) -> PathBuf {
    let meshes = dir.join("meshes");
    std::fs::create_dir_all(&meshes).unwrap();
    for name in ["cuboid", "teapot"] {
        let from = shared().join(format!("scenes/formats/indigo/igmesh/{name}.igmesh"));
        std::fs::write(
            meshes.join(format!("{name}.igmesh")),
            std::fs::read(from).unwrap(),
        )
        .unwrap();
    }
    let scene = dir.join("two.igs");
    std::fs::write(
        &scene,
        r#"<?xml version="1.0" encoding="utf-8"?>
<scene>
	<renderer_settings>
		<width>24</width>
		<height>24</height>
		<metropolis>false</metropolis>
		<bidirectional>false</bidirectional>
		<max_depth>3</max_depth>
	</renderer_settings>
	<camera>
		<pos>0 -3.5 0.5</pos>
		<forwards>0 1 0</forwards>
		<up>0 0 1</up>
		<sensor_width>0.036</sensor_width>
		<lens_sensor_dist>0.03</lens_sensor_dist>
	</camera>
	<background><spectrum><uniform><value>1</value></uniform></spectrum></background>
	<material>
		<uid>1</uid>
		<name>grey</name>
		<diffuse><albedo><constant><uniform><value>0.5</value></uniform></constant></albedo></diffuse>
	</material>
	<mesh><uid>2</uid><name>box</name><external><path>meshes\cuboid.igmesh</path></external></mesh>
	<mesh><uid>3</uid><name>teapot</name><external><path>meshes\teapot.igmesh</path></external></mesh>
	<model2><geometry_uid>2</geometry_uid><pos>-1.3 0 0</pos><scale>1</scale><materials><material_uid>1</material_uid></materials></model2>
	<model2><geometry_uid>3</geometry_uid><pos>1 0 0</pos><scale>4</scale><materials><material_uid>1</material_uid></materials></model2>
</scene>
"#,
    )
    .unwrap();
    scene
}

#[test]
fn submit_bundles_the_external_meshes_and_renders_on_the_farm() {
    let dir = tempfile::tempdir().unwrap();
    let scene = two_meshes(&dir.path().join("scene"));
    // An unrelated file beside the scene stays out of the bundle.
    std::fs::write(dir.path().join("scene/notes.txt"), "x").unwrap();
    let files = luxfarm_wire::bundle::referenced_files(&scene).unwrap();
    let want: Vec<PathBuf> = ["meshes/cuboid.igmesh", "meshes/teapot.igmesh", "two.igs"]
        .iter()
        .map(PathBuf::from)
        .collect();
    assert_eq!(files, want);

    let s = server(&dir.path().join("data"), &["--upload-interval", "1"]);
    let id = submit_scene(&s, &scene, &["--haltspp", "4"]);
    // The master stored the scene with its meshes, byte for byte.
    let stored = files_under(&s.data.join("scenes"));
    for name in ["cuboid", "teapot"] {
        let copy = stored
            .iter()
            .find(|p| p.ends_with(format!("meshes/{name}.igmesh")))
            .unwrap_or_else(|| panic!("{name}.igmesh not in the stored bundle: {stored:?}"));
        assert_eq!(
            std::fs::read(copy).unwrap(),
            std::fs::read(
                scene
                    .parent()
                    .unwrap()
                    .join(format!("meshes/{name}.igmesh"))
            )
            .unwrap()
        );
    }
    assert!(!stored.iter().any(|p| p.ends_with("notes.txt")));
    let _w = worker(&s.url(), 1, &[]);
    let v = wait_job(&s, &id, 600, |v| {
        v["state"] != "queued" && v["state"] != "rendering"
    });
    assert_eq!(v["state"], "done", "{v}");
    assert!(v["spp"].as_f64().is_some_and(|spp| spp >= 4.0), "{v}");
    assert_eq!(
        (v["width"].clone(), v["height"].clone()),
        (24.into(), 24.into())
    );
    // The meshes were drawn: the grey models darken part of the white background.
    let y = luma(&final_checkpoint(&s, &id));
    let white = y.iter().cloned().fold(0.0, f64::max);
    assert!(white > 0.0, "nothing rendered");
    let dark = y.iter().filter(|&&v| v < 0.9 * white).count();
    assert!(
        dark * 20 >= y.len(),
        "the meshes cover {dark} of {} pixels",
        y.len()
    );
}

/// The weight-normalised Y of every pixel of a film's first light group.
fn luma(film: &luxfarm::film::Film) -> Vec<f64> {
    let mut out = Vec::with_capacity(film.pixel_count());
    for y in 0..film.height() {
        for x in 0..film.width() {
            let p = film.pixel(0, 0, x, y).expect("pixel in range");
            out.push(if p[4] > 0.0 { p[1] / p[4] } else { 0.0 });
        }
    }
    out
}
