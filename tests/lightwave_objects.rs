//! LightWave objects end to end: every sample .lwo (LWO2 and LWOB) loads through a scene of
//! our own with the triangle count its polygons give (a k-gon is k - 2 triangles, counted
//! from the files by hand), consistent uv and normal arrays, outward normals and windings
//! after the change of handedness, image textures on uv maps, custom normals from a NORM
//! vertex map, warnings where LightWave's result cannot be reproduced, and clear errors for
//! object forms that are not read (LWO3, modo's LXOB, not IFF at all).

mod lightwave_util;

use glam::DVec3;
use lightwave_util::*;
use luxfarm::lxs::{LxsErrorKind, ParseOptions, SceneDescription, ShapeDesc};
use std::path::Path;

/// Every trianglemesh of the scene, placed or inside an object.
fn meshes(d: &SceneDescription) -> Vec<&ShapeDesc> {
    d.shapes
        .iter()
        .chain(d.objects.iter().flat_map(|o| o.shapes.iter()))
        .filter(|s| s.entity.kind == "trianglemesh")
        .collect()
}

/// A scene of layer `layer` of `object`, a distant light and a camera.
fn probe_scene(object: &str, layer: u32) -> String {
    format!(
        "LWSC\n3\n\nLoadObjectLayer {layer} {object}\nAddLight\nLightType 0\n{}",
        camera_block().replace(" 30000000", "")
    )
}

/// Loads layer `layer` of the sample `rel` (copied with `extra` files from its directory)
/// through [`probe_scene`].
fn load_sample(rel: &str, layer: u32, extra: &[&str]) -> SceneDescription {
    let dir = tempfile::tempdir().unwrap();
    let src = samples().join("LWO").join(rel);
    let name = src.file_name().unwrap().to_string_lossy().into_owned();
    std::fs::copy(&src, dir.path().join(&name)).unwrap();
    for e in extra {
        std::fs::copy(src.parent().unwrap().join(e), dir.path().join(e)).unwrap();
    }
    let scene = dir.path().join("probe.lws");
    std::fs::write(&scene, probe_scene(&name, layer)).unwrap();
    load_at(&scene, Some(0))
}

fn v(a: [f32; 3]) -> DVec3 {
    DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64)
}

/// Checks one mesh's arrays against each other; returns its triangle count.
fn check_mesh(s: &ShapeDesc, what: &str) -> usize {
    let p = &s.entity.params;
    let pts = p.points("P").expect("P");
    let idx = p.ints("indices").expect("indices");
    assert_eq!(idx.len() % 3, 0, "{what}");
    assert!(
        idx.iter().all(|&i| i >= 0 && (i as usize) < pts.len()),
        "{what}: index out of range"
    );
    assert!(pts.iter().flatten().all(|c| c.is_finite()), "{what}");
    if let Some(uv) = p.floats("uv") {
        assert_eq!(uv.len(), 2 * pts.len(), "{what}: one uv per point");
        assert!(uv.iter().all(|c| c.is_finite()), "{what}");
    }
    if let Some(n) = p.normals("N") {
        assert_eq!(n.len(), pts.len(), "{what}: one normal per point");
        for x in n {
            assert!((v(*x).length() - 1.0).abs() < 1e-3, "{what}: unit normals");
        }
    }
    idx.len() / 3
}

fn has(s: &ShapeDesc, name: &str) -> bool {
    s.entity.params.contains(name)
}

/// (sample, scene layer, files beside it, triangles, shapes, uv, normals).
type Case = (
    &'static str,
    u32,
    &'static [&'static str],
    usize,
    usize,
    bool,
    bool,
);

#[test]
fn every_sample_object_loads_with_its_triangle_count() {
    let cases: &[Case] = &[
        // 240 quads and 48 triangles: 240 x 2 + 48 = 528; smooth, so normals
        (
            "LWO2/ModoExport_vertNormals.lwo",
            1,
            &[],
            528,
            1,
            false,
            true,
        ),
        // 24 subpatch quads rendered as their cage
        ("LWO2/Subdivision.lwo", 1, &[], 48, 1, false, false),
        // 6 quads; its image is not there, so no texture and no uv
        ("LWO2/box_2uv_1unused.lwo", 1, &[], 12, 1, false, false),
        ("LWO2/boxuv.lwo", 1, &["boxuv.png"], 12, 1, true, false),
        // one 66-gon (a hole bridged into its outline): 64 triangles
        ("LWO2/concave_polygon.lwo", 1, &[], 64, 1, false, true),
        // LAYR 1 is scene layer 2, ...; LAYR 4 (scene layer 5) is the sphere
        ("LWO2/hierarchy.lwo", 2, &[], 12, 1, false, true),
        ("LWO2/hierarchy.lwo", 3, &[], 12, 1, false, false),
        ("LWO2/hierarchy.lwo", 4, &[], 12, 1, false, true),
        // its surface has no smoothing angle: faceted, no normals
        ("LWO2/hierarchy.lwo", 5, &[], 528, 1, false, false),
        // one non-planar 18-gon
        ("LWO2/nonplanar_polygon.lwo", 1, &[], 16, 1, false, false),
        (
            "LWO2/sphere_with_mat_gloss_10pc.lwo",
            1,
            &[],
            528,
            1,
            false,
            true,
        ),
        // 246 quads and 48 triangles
        ("LWO2/transparency.lwo", 1, &[], 540, 1, false, true),
        // 16 quads, one surface each
        ("LWO2/uvtest.lwo", 1, &["uvtest.png"], 32, 16, true, false),
        (
            "LWO2/MappingModes/earth_cylindrical_y.lwo",
            1,
            &[],
            528,
            1,
            false,
            false,
        ),
        (
            "LWO2/MappingModes/earth_planar_z.lwo",
            1,
            &[],
            528,
            1,
            false,
            false,
        ),
        (
            "LWO2/MappingModes/earth_spherical_y.lwo",
            1,
            &[],
            528,
            1,
            false,
            false,
        ),
        (
            "LWO2/MappingModes/earth_uv_cylindrical_y.lwo",
            1,
            &[],
            528,
            1,
            false,
            false,
        ),
        ("LWOB/ConcavePolygon.lwo", 1, &[], 64, 1, false, true),
        (
            "LWOB/sphere_with_mat_gloss_10pc.lwo",
            1,
            &[],
            528,
            1,
            false,
            true,
        ),
    ];
    for &(rel, layer, extra, tris, shapes, uv, n) in cases {
        let what = format!("{rel} layer {layer}");
        let d = load_sample(rel, layer, extra);
        let ms = meshes(&d);
        assert_eq!(ms.len(), shapes, "{what}");
        let total: usize = ms.iter().map(|s| check_mesh(s, &what)).sum();
        assert_eq!(total, tris, "{what}: triangles");
        assert!(ms.iter().all(|s| has(s, "uv") == uv), "{what}: uv");
        assert!(ms.iter().all(|s| has(s, "N") == n), "{what}: normals");
    }
}

#[test]
fn spheres_face_outwards_after_the_change_of_handedness() {
    for rel in [
        "LWO2/sphere_with_mat_gloss_10pc.lwo",
        "LWOB/sphere_with_mat_gloss_10pc.lwo",
        "LWO2/ModoExport_vertNormals.lwo",
    ] {
        let d = load_sample(rel, 1, &[]);
        let s = meshes(&d)[0];
        let m = s.object_to_world.start();
        let pts: Vec<DVec3> = s
            .entity
            .params
            .points("P")
            .unwrap()
            .iter()
            .map(|&p| v(p))
            .collect();
        let centre = pts.iter().sum::<DVec3>() / pts.len() as f64;
        let ns = s.entity.params.normals("N").unwrap();
        for (p, n) in pts.iter().zip(ns) {
            assert!(
                (*p - centre).normalize().dot(v(*n)) > 0.8,
                "{rel}: normal at {p}"
            );
        }
        let idx = s.entity.params.ints("indices").unwrap();
        for t in idx.chunks(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| pts[i as usize]);
            let geometric = (b - a).cross(c - a);
            let mid = (a + b + c) / 3.0 - centre;
            assert!(
                geometric.dot(mid) > 0.0,
                "{rel}: triangle {t:?} winds inwards"
            );
        }
        // the sphere is placed without mirroring
        assert!(m.determinant() > 0.0, "{rel}");
    }
}

#[test]
fn image_blocks_become_textures_on_the_uv_map() {
    let d = load_sample("LWO2/boxuv.lwo", 1, &["boxuv.png"]);
    let tex: Vec<_> = d
        .textures
        .iter()
        .filter(|t| t.entity.kind == "imagemap")
        .collect();
    assert_eq!(tex.len(), 1, "{:?}", d.textures);
    let file = tex[0].entity.params.string("filename").unwrap();
    assert!(file.ends_with("boxuv.png"), "{file}");
    let uv = meshes(&d)[0].entity.params.floats("uv").unwrap();
    assert!(uv.iter().all(|c| (-1e-4..=1.0001).contains(c)), "{uv:?}");
    // the 16 surfaces of uvtest share one image and use different parts of it
    let d = load_sample("LWO2/uvtest.lwo", 1, &["uvtest.png"]);
    let firsts: Vec<(i64, i64)> = meshes(&d)
        .iter()
        .map(|s| {
            let uv = s.entity.params.floats("uv").unwrap();
            ((uv[0] * 1000.0) as i64, (uv[1] * 1000.0) as i64)
        })
        .collect();
    let mut distinct = firsts.clone();
    distinct.sort();
    distinct.dedup();
    assert!(distinct.len() > 1, "{firsts:?}");
}

#[test]
fn cages_and_layer_numbers_are_warned_about() {
    let d = load_sample("LWO2/Subdivision.lwo", 1, &[]);
    assert!(
        d.warnings
            .iter()
            .any(|w| w.message.contains("cage") && w.loc.file.contains("Subdivision.lwo")),
        "{:?}",
        d.warnings
    );
    // hierarchy.lwo numbers its layers 1-4 (no LAYR 0): scene layer 1 falls back to the
    // file's first layer, with a warning
    let d = load_sample("LWO2/hierarchy.lwo", 1, &[]);
    assert!(
        d.warnings
            .iter()
            .any(|w| w.message.contains("no layer number 1")),
        "{:?}",
        d.warnings
    );
}

/// A VMAP chunk of type `kind`, dimension `dim`, named `name`, values per point.
fn vmap(kind: &[u8; 4], name: &str, values: &[(u16, Vec<f32>)]) -> Vec<u8> {
    let mut b = kind.to_vec();
    let dim = values.first().map_or(0, |v| v.1.len()) as u16;
    b.extend(dim.to_be_bytes());
    b.extend(s0(name));
    for (i, vals) in values {
        b.extend(i.to_be_bytes());
        for x in vals {
            b.extend(f4(*x));
        }
    }
    chunk(b"VMAP", &b)
}

/// A square facing -Z (LightWave) whose NORM map "custom" leans towards +X and -Z; its
/// surface names the map when `named`.
fn leaning_square(named: bool) -> Vec<u8> {
    let lean = [0.6f32, 0.0, -0.8];
    let values: Vec<(u16, Vec<f32>)> = (0..4).map(|i| (i, lean.to_vec())).collect();
    lwo2_with(
        [0.0; 3],
        &[
            [-0.5, -0.5, 0.0],
            [-0.5, 0.5, 0.0],
            [0.5, 0.5, 0.0],
            [0.5, -0.5, 0.0],
        ],
        &[(&[0, 1, 2, 3], 0)],
        &[("Square", [0.8; 3], 1.0, 0.0)],
        &[vmap(b"NORM", "custom", &values)],
        &if named {
            sub(b"NORM", &s0("custom"))
        } else {
            Vec::new()
        },
    )
}

#[test]
fn the_surfaces_norm_vertex_map_gives_the_normals() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("n.lws");
    std::fs::write(&scene, probe_scene("n.lwo", 1)).unwrap();
    std::fs::write(dir.path().join("n.lwo"), leaning_square(true)).unwrap();
    let d = load_at(&scene, Some(0));
    let ns = meshes(&d)[0]
        .entity
        .params
        .normals("N")
        .expect("custom normals")
        .to_vec();
    assert_eq!(ns.len(), 4);
    // LightWave (x, y, z) is luxfarm (x, z, y)
    for n in ns {
        assert!((v(n) - DVec3::new(0.6, -0.8, 0.0)).length() < 1e-5, "{n:?}");
    }
    // A map the surface does not name is not used (LightWave picks the map per surface):
    // the flat square is faceted.
    std::fs::write(dir.path().join("n.lwo"), leaning_square(false)).unwrap();
    let d = load_at(&scene, Some(0));
    assert!(!meshes(&d)[0].entity.params.contains("N"));
}

fn load_err(dir: &Path, bytes: &[u8]) -> luxfarm::lxs::LxsError {
    std::fs::write(dir.join("x.lwo"), bytes).unwrap();
    let scene = dir.join("x.lws");
    std::fs::write(&scene, probe_scene("x.lwo", 1)).unwrap();
    luxfarm::formats::load(&scene, &ParseOptions::default()).unwrap_err()
}

#[test]
fn other_object_forms_fail_clearly() {
    let dir = tempfile::tempdir().unwrap();
    for (form, needle) in [(b"LWO3", "LWO3"), (b"LXOB", "modo")] {
        let e = load_err(dir.path(), &chunk(b"FORM", &[&form[..], &[0; 8]].concat()));
        assert_eq!(e.kind, LxsErrorKind::Unsupported, "{e}");
        let s = e.to_string();
        assert!(
            s.contains(needle) && s.contains("x.lwo") && s.contains("x.lws:4:1"),
            "{s}"
        );
    }
    let e = load_err(dir.path(), b"o 1 2 3\nv 0 0 0\n");
    assert!(e.to_string().contains("not a LightWave object"), "{e}");
}
