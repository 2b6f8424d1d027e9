//! Indigo scenes end to end: the Cornell box sample against its LuxRender twin (camera,
//! transforms, the meshes it lacks), .igm material files, a scene written for these tests
//! rendered against its hand-written .lxs twin, and instancing at scale.

mod render_util;

use glam::DMat4;
use luxfarm::formats::{self, indigo};
use luxfarm::lxs::{LxsErrorKind, ParamValue, ParseOptions, SceneDescription};
use luxfarm::render::SessionOptions;
use render_util::*;
use std::path::{Path, PathBuf};

fn cornell() -> PathBuf {
    scene_path("formats/cornell_box/cornell_box.igs")
}

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/indigo")
        .join(name)
}

/// The lines of cornell_box.igs whose `<path>` names each of its four meshes.
const MESH_LINES: [(u32, &str); 4] = [
    (203, "mesh_1810852719_103.igmesh"),
    (238, "mesh_970142982_336.igmesh"),
    (256, "mesh_2799352261_336.igmesh"),
    (325, "mesh_3079769271_319.igmesh"),
];

#[test]
fn cornell_box_parses_and_rendering_names_each_missing_mesh_and_its_element() {
    let path = cornell();
    // `luxfarm parse`: the scene reads; each missing mesh is a located warning.
    let desc = formats::inspect(&path, &ParseOptions::default()).expect("cornell_box.igs parses");
    assert_eq!(desc.materials.len(), 6);
    for (line, file) in MESH_LINES {
        let w = desc
            .warnings
            .iter()
            .find(|w| w.message.contains(file))
            .unwrap_or_else(|| panic!("no warning names {file}: {:?}", desc.warnings));
        assert_eq!(w.loc.line, line, "{w}");
        assert!(w.loc.file.ends_with("cornell_box.igs"));
    }
    // `luxfarm render` / `submit`, the master and the workers: one error naming all four.
    let e = formats::load(&path, &ParseOptions::default()).unwrap_err();
    assert_eq!(e.kind, LxsErrorKind::MissingInclude);
    let msg = e.to_string();
    for (line, file) in MESH_LINES {
        assert!(msg.contains(file), "{msg}");
        assert!(msg.contains(&format!("cornell_box.igs:{line}:")), "{msg}");
    }
}

/// Copies cornell_box.igs into a directory with stand-in meshes (the glare-core samples) at
/// the paths it names, so that it imports completely.
fn cornell_with_meshes() -> (tempfile::TempDir, SceneDescription) {
    let dir = tempfile::tempdir().unwrap();
    let meshes = dir.path().join("cornell_box_meshes");
    std::fs::create_dir_all(&meshes).unwrap();
    std::fs::copy(cornell(), dir.path().join("cornell_box.igs")).unwrap();
    let sample = |f: &str| scene_path(&format!("formats/indigo/igmesh/{f}"));
    for (i, (_, file)) in MESH_LINES.iter().enumerate() {
        let src = [
            "single_quad.igmesh",
            "cuboid.igmesh",
            "cuboid.igmesh",
            "cornell_box.igmesh",
        ][i];
        std::fs::copy(sample(src), meshes.join(file)).unwrap();
    }
    let desc = formats::load(
        &dir.path().join("cornell_box.igs"),
        &ParseOptions::default(),
    )
    .expect("imports with its meshes");
    (dir, desc)
}

fn close(a: &DMat4, b: &DMat4, tol: f64) -> bool {
    a.to_cols_array()
        .iter()
        .zip(b.to_cols_array())
        .all(|(x, y)| (x - y).abs() <= tol * (1.0 + y.abs()))
}

/// Distinct object-to-world matrices of the world shapes, in order.
fn transforms(d: &SceneDescription) -> Vec<DMat4> {
    let mut v: Vec<DMat4> = Vec::new();
    for s in &d.shapes {
        let m = s.object_to_world.start();
        if v.last() != Some(&m) {
            v.push(m);
        }
    }
    v
}

#[test]
fn cornell_box_camera_and_transforms_equal_the_lxs_twin() {
    let twin = parse(&scene_path("formats/cornell_box/cornell_box.lxs"));
    let (_dir, desc) = cornell_with_meshes();
    let cam = desc.camera.as_ref().unwrap();
    let fov = cam.entity.params.float("fov").unwrap();
    assert!((fov - 39.146).abs() < 1e-3, "fov {fov}");
    let twin_fov = twin
        .camera
        .as_ref()
        .unwrap()
        .entity
        .params
        .float("fov")
        .unwrap();
    assert!((fov - twin_fov).abs() < 1e-4, "{fov} vs {twin_fov}");
    assert_eq!(
        desc.film.as_ref().unwrap().params.int("xresolution"),
        Some(500)
    );
    // The twin's LookAt target is eye + forwards/1000 printed with 16 digits, which loses the
    // forwards vector's x and z components (3e-7 and 8e-8): equal to that precision.
    let (a, b) = (
        cam.world_to_camera.start(),
        twin.camera.as_ref().unwrap().world_to_camera.start(),
    );
    assert!(close(&a, &b, 1e-6), "{a} vs {b}");
    let (mine, theirs) = (transforms(&desc), transforms(&twin));
    assert_eq!(mine.len(), 4, "light, two boxes, the box");
    assert_eq!(theirs.len(), 4);
    for (a, b) in mine.iter().zip(&theirs) {
        assert!(close(a, b, 1e-12), "{a} vs {b}");
    }
    // The emitter is an area light in the "Emitter" light group (layer 3 of the settings).
    let lit: Vec<_> = desc
        .shapes
        .iter()
        .filter(|s| s.area_light.is_some())
        .collect();
    assert_eq!(lit.len(), 1);
    assert_eq!(lit[0].area_light.as_ref().unwrap().light_group, "Emitter");
    assert_eq!(
        lit[0].area_light.as_ref().unwrap().entity.params.color("L"),
        Some([10000.0; 3])
    );
    // The meshes are in the file list, so a farm bundle carries them.
    assert_eq!(
        desc.files.iter().filter(|f| f.ends_with(".igmesh")).count(),
        4
    );
}

#[test]
fn igm_material_files_load() {
    let dir = tempfile::tempdir().unwrap();
    for f in ["Metal_Iridiscent.igm", "red-laser.igm"] {
        std::fs::copy(
            scene_path(&format!("formats/indigo/igm/{f}")),
            dir.path().join(f),
        )
        .unwrap();
    }
    std::fs::write(
        dir.path().join("s.igs"),
        "<scene><include><pathname>Metal_Iridiscent.igm</pathname></include>\
         <include><pathname>red-laser.igm</pathname></include>\
         <camera><pos>0 -3 0</pos><forwards>0 1 0</forwards><up>0 0 1</up></camera>\
         <mesh><name>q</name><embedded><vertex pos=\"0 0 0\"/><vertex pos=\"1 0 0\"/><vertex pos=\"0 0 1\"/>\
         <triangle_set><material_name>red-laser</material_name><tri>0 1 2</tri></triangle_set></embedded></mesh>\
         <model><pos>0 0 0</pos><scale>1</scale><mesh_name>q</mesh_name></model></scene>",
    )
    .unwrap();
    let desc = formats::load(&dir.path().join("s.igs"), &ParseOptions::default()).unwrap();
    assert_eq!(desc.files.len(), 3);
    let metal = desc
        .named_material("Metal Iridiscent")
        .expect("metal material");
    assert_eq!(metal.entity.kind, "glossy");
    let laser = desc.named_material("red-laser").expect("laser material");
    assert_eq!(laser.entity.kind, "glossy");
    // Its emission is a tabulated spectrum peaking in the red: the area light is red.
    let l = desc.shapes[0]
        .area_light
        .as_ref()
        .expect("emits")
        .entity
        .params
        .color("L")
        .unwrap();
    assert!(l[0] > 4.0 * l[1] && l[0] > 4.0 * l[2], "{l:?}");
    // The ISL shader of the iridescent metal is reported where it is written.
    assert!(desc
        .warnings
        .iter()
        .any(|w| w.message.contains("shader") && w.loc.file.ends_with("Metal_Iridiscent.igm")));
}

/// Film Y in 8×8 blocks, rendered with `seed`.
fn blocks(desc: &SceneDescription, seed: u64) -> Vec<f64> {
    let opts = SessionOptions {
        threads: 1,
        seed,
        stream: 0,
    };
    let film = render(desc, &data(""), opts, 4);
    block_means(&film, 8)
}

#[test]
fn small_indigo_scene_renders_as_its_hand_written_lxs_twin() {
    let igs = formats::load(&data("twin.igs"), &ParseOptions::default()).expect("twin.igs imports");
    let lxs = parse(&data("twin.lxs"));
    assert_eq!(igs.shapes.len(), lxs.shapes.len());
    // The noise of the twin, per block, from four independent renders.
    let runs: Vec<Vec<f64>> = (1..=4).map(|s| blocks(&lxs, s)).collect();
    let n = runs[0].len();
    let mean: Vec<f64> = (0..n)
        .map(|b| runs.iter().map(|r| r[b]).sum::<f64>() / 4.0)
        .collect();
    let sd: Vec<f64> = (0..n)
        .map(|b| (runs.iter().map(|r| (r[b] - mean[b]).powi(2)).sum::<f64>() / 3.0).sqrt())
        .collect();
    let ind = blocks(&igs, 99);
    assert!(mean.iter().sum::<f64>() > 0.0, "the twin is lit");
    for b in 0..n {
        // Independent renders differ by sd·√(1 + 1/4) typically; allow 5 of those, and 2% for
        // the rounding of transforms applied to the Indigo meshes.
        let tol = 5.0 * sd[b] * 1.25f64.sqrt() + 0.02 * mean[b] + 1e-9;
        assert!(
            (ind[b] - mean[b]).abs() <= tol,
            "block {b}: indigo {} vs lxs {} (sd {})",
            ind[b],
            mean[b],
            sd[b]
        );
    }
    // A scene that differs does not pass: the lamp twice as bright.
    let text = std::fs::read_to_string(data("twin.igs"))
        .unwrap()
        .replace("<value>8</value>", "<value>16</value>");
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bright.igs"), text).unwrap();
    let bright = formats::load(&dir.path().join("bright.igs"), &ParseOptions::default()).unwrap();
    let b2 = blocks(&bright, 99);
    let failing = (0..n)
        .filter(|&b| (b2[b] - mean[b]).abs() > 5.0 * sd[b] * 1.25f64.sqrt() + 0.02 * mean[b])
        .count();
    assert!(failing > n / 2, "only {failing} of {n} blocks differ");
}

#[test]
fn thousands_of_instances_of_two_meshes_build_small() {
    let mut text = String::from(
        "<scene><renderer_settings><width>8</width><height>8</height></renderer_settings>\
         <camera><pos>0 -50 5</pos><forwards>0 1 0</forwards><up>0 0 1</up></camera>\
         <material><name>a</name><diffuse><albedo><constant><uniform><value>0.5</value></uniform></constant></albedo></diffuse></material>\
         <material><name>b</name><phong><exponent><constant>50</constant></exponent></phong></material>",
    );
    for (name, mat) in [("tet", "a"), ("tri", "b")] {
        text += &format!(
            "<mesh><name>{name}</name><embedded><vertex pos=\"0 0 0\"/><vertex pos=\"0.1 0 0\"/><vertex pos=\"0 0.1 0\"/><vertex pos=\"0 0 0.1\"/>\
             <triangle_set><material_name>{mat}</material_name><tri>0 1 2</tri><tri>0 1 3</tri><tri>0 2 3</tri><tri>1 2 3</tri></triangle_set></embedded></mesh>"
        );
    }
    for i in 0..15_000 {
        let mesh = if i % 2 == 0 { "tet" } else { "tri" };
        text += &format!(
            "<model><pos>{} {} 0</pos><scale>1</scale><mesh_name>{mesh}</mesh_name></model>",
            i % 150,
            i / 150
        );
    }
    text += "</scene>";
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("many.igs");
    std::fs::write(&path, text).unwrap();
    let desc = formats::load(&path, &ParseOptions::default()).unwrap();
    assert_eq!(desc.objects.len(), 2);
    assert_eq!(desc.instances.len(), 15_000);
    assert!(desc.shapes.is_empty());
    // Each mesh is held once, whatever the number of placements.
    let points: usize = desc
        .objects
        .iter()
        .flat_map(|o| &o.shapes)
        .map(|s| s.entity.params.points("P").map_or(0, |p| p.len()))
        .sum();
    assert_eq!(points, 8);
    let last = desc.instances[14_999].instance_to_world.start();
    assert_eq!(last.w_axis.truncate(), glam::DVec3::new(149.0, 99.0, 0.0));
    assert_eq!(desc.instances[1].object, 1);
}

#[test]
fn material_parameters_reach_the_description() {
    let desc = formats::load(&data("twin.igs"), &ParseOptions::default()).unwrap();
    let shiny = &desc.named_material("shiny").unwrap().entity;
    assert_eq!(shiny.kind, "glossy");
    assert_eq!(shiny.params.float("index"), Some(1.5));
    let glass = &desc.named_material("glass").unwrap().entity;
    assert_eq!(glass.params.float("index"), Some(1.5));
    // The sphere's interior is the glass medium.
    let sphere = desc
        .shapes
        .iter()
        .find(|s| s.entity.kind == "sphere")
        .unwrap();
    assert_eq!(sphere.interior.as_deref(), Some("glass"));
    assert_eq!(desc.sampler.as_ref().unwrap().kind, "random");
    assert_eq!(desc.surface_integrator.as_ref().unwrap().kind, "path");
    assert_eq!(desc.film.as_ref().unwrap().params.int("haltspp"), Some(16));
    assert_eq!(
        desc.film
            .as_ref()
            .unwrap()
            .params
            .get("tonemapkernel")
            .map(|p| p.value.clone()),
        Some(ParamValue::String(vec!["linear".into()]))
    );
    // Every element of the scene was understood: no "not supported" warning.
    assert!(
        !desc
            .warnings
            .iter()
            .any(|w| w.message.contains("not supported")),
        "{:?}",
        desc.warnings
    );
    let _ = indigo::is_indigo(b"<scene>");
}
