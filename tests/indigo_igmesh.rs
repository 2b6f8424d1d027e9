//! Every .igmesh sample of ../shared (versions 1 to 4) loads with the counts it holds, and
//! renders inside an Indigo scene that references it.

mod render_util;

use luxfarm::formats::{self, indigo::igmesh, indigo::mesh::UvLayout};
use luxfarm::lxs::ParseOptions;
use luxfarm::render::SessionOptions;
use render_util::*;

const LIMITS: igmesh::Limits = igmesh::Limits {
    max_array_len: 1 << 28,
    max_decompressed: 1 << 30,
};

/// What a sample holds. The uncompressed files' sizes check these counts independently:
/// e.g. tilted_prism (v2) is 32 header bytes + 2 × (4 + 24·12) + 4 + (4 + 8·28) + 4 = 852
/// bytes, its size on disk.
struct Sample {
    name: &'static str,
    version: u32,
    vertices: usize,
    tris: usize,
    quads: usize,
    uv_sets: u32,
    uvs: usize,
    materials: usize,
}

const SAMPLES: [Sample; 6] = [
    Sample {
        name: "bug-2",
        version: 1,
        vertices: 734,
        tris: 944,
        quads: 0,
        uv_sets: 1,
        uvs: 496,
        materials: 1,
    },
    Sample {
        name: "tilted_prism",
        version: 2,
        vertices: 24,
        tris: 8,
        quads: 0,
        uv_sets: 0,
        uvs: 0,
        materials: 1,
    },
    Sample {
        name: "cuboid",
        version: 3,
        vertices: 24,
        tris: 12,
        quads: 0,
        uv_sets: 1,
        uvs: 24,
        materials: 0,
    },
    Sample {
        name: "cornell_box",
        version: 4,
        vertices: 102,
        tris: 34,
        quads: 0,
        uv_sets: 1,
        uvs: 102,
        materials: 3,
    },
    Sample {
        name: "single_quad",
        version: 4,
        vertices: 4,
        tris: 0,
        quads: 1,
        uv_sets: 1,
        uvs: 4,
        materials: 1,
    },
    Sample {
        name: "teapot",
        version: 4,
        vertices: 3918,
        tris: 7656,
        quads: 0,
        uv_sets: 1,
        uvs: 4608,
        materials: 1,
    },
];

fn sample(name: &str) -> std::path::PathBuf {
    scene_path(&format!("formats/indigo/igmesh/{name}.igmesh"))
}

#[test]
fn every_sample_loads_with_its_counts() {
    for smp in &SAMPLES {
        let (name, version, v, t, q) = (smp.name, smp.version, smp.vertices, smp.tris, smp.quads);
        let (sets, uvs, mats) = (smp.uv_sets, smp.uvs, smp.materials);
        let bytes = std::fs::read(sample(name)).unwrap();
        assert_eq!(
            u32::from_le_bytes([bytes[4], bytes[5], bytes[6], bytes[7]]),
            version,
            "{name}"
        );
        let m = igmesh::read(&bytes, LIMITS).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(m.positions.len(), v, "{name} vertices");
        assert_eq!(m.normals.len(), v, "{name} normals");
        assert_eq!(m.tris.len(), t, "{name} triangles");
        assert_eq!(m.quads.len(), q, "{name} quads");
        assert_eq!(m.num_uv_sets, sets, "{name} uv sets");
        assert_eq!(m.uvs.len(), uvs, "{name} uvs");
        assert_eq!(m.material_names.len(), mats, "{name} materials");
        assert_eq!(m.uv_layout, UvLayout::VertexLayer, "{name}");
        m.validate().unwrap();
    }
    // The sizes of the uncompressed files follow from the counts.
    let size = |v: usize, uvs: usize, t: usize, q: Option<usize>, header: usize, layout: bool| {
        header
            + 2 * (4 + 12 * v)
            + layout as usize * 4
            + 4
            + 8 * uvs
            + 4
            + 28 * t
            + q.map_or(0, |q| 4 + 36 * q)
    };
    let len = |n: &str| std::fs::metadata(sample(n)).unwrap().len() as usize;
    assert_eq!(len("tilted_prism"), size(24, 0, 8, Some(0), 32, false));
    assert_eq!(len("cuboid"), size(24, 24, 12, Some(0), 20, true));
}

/// An Indigo scene around `name`: a diffuse model of it seen along its thinnest axis, lit by
/// a uniform background.
fn scene_for(name: &str, dir: &std::path::Path) -> std::path::PathBuf {
    std::fs::copy(sample(name), dir.join(format!("{name}.igmesh"))).unwrap();
    let m = igmesh::read(&std::fs::read(sample(name)).unwrap(), LIMITS).unwrap();
    let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
    for p in &m.positions {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k] as f64);
            hi[k] = hi[k].max(p[k] as f64);
        }
    }
    let ext: Vec<f64> = (0..3).map(|k| hi[k] - lo[k]).collect();
    let c: Vec<f64> = (0..3).map(|k| 0.5 * (hi[k] + lo[k])).collect();
    let axis = (0..3).min_by(|&a, &b| ext[a].total_cmp(&ext[b])).unwrap();
    let size = ext.iter().cloned().fold(0.0, f64::max);
    let mut fwd = [0.0; 3];
    fwd[axis] = 1.0;
    let pos: Vec<f64> = (0..3).map(|k| c[k] - fwd[k] * 2.0 * size).collect();
    let up = if axis == 2 { "0 1 0" } else { "0 0 1" };
    let mats = m.material_names.len().max(1);
    let list: String = (0..mats)
        .map(|_| "<material_uid>1</material_uid>")
        .collect();
    let text = format!(
        "<scene><renderer_settings><width>24</width><height>24</height><metropolis>false</metropolis>\
         <bidirectional>false</bidirectional><max_depth>2</max_depth></renderer_settings>\
         <camera><pos>{} {} {}</pos><forwards>{} {} {}</forwards><up>{up}</up>\
         <sensor_width>0.036</sensor_width><lens_sensor_dist>0.036</lens_sensor_dist></camera>\
         <background><spectrum><uniform><value>1</value></uniform></spectrum></background>\
         <material><uid>1</uid><name>grey</name><diffuse><albedo><constant><uniform><value>0.5</value></uniform></constant></albedo></diffuse></material>\
         <mesh><uid>2</uid><name>{name}</name><external><path>{name}.igmesh</path></external></mesh>\
         <model2><geometry_uid>2</geometry_uid><pos>0 0 0</pos><scale>1</scale><materials>{list}</materials></model2></scene>",
        pos[0], pos[1], pos[2], fwd[0], fwd[1], fwd[2]
    );
    let path = dir.join(format!("{name}.igs"));
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn every_sample_renders_inside_a_scene() {
    for name in SAMPLES.iter().map(|s| s.name) {
        let dir = tempfile::tempdir().unwrap();
        let path = scene_for(name, dir.path());
        let desc = formats::load(&path, &ParseOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        assert!(desc.files.iter().any(|f| f.ends_with(".igmesh")), "{name}");
        let opts = SessionOptions {
            threads: 1,
            seed: 7,
            stream: 0,
        };
        let film = render(&desc, dir.path(), opts, 1);
        let y: Vec<f64> = normalized_xyz(&film).iter().map(|p| p[1]).collect();
        let background = y.iter().cloned().fold(0.0, f64::max);
        assert!(background > 0.0, "{name}: nothing lit");
        // The grey mesh is darker than the uniform background it occludes.
        let covered = y.iter().filter(|&&v| v < 0.9 * background).count();
        assert!(
            covered * 20 >= y.len(),
            "{name}: the mesh covers {covered} of {} pixels",
            y.len()
        );
    }
}
