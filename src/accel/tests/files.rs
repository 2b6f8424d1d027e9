//! Shapes read from files (PLY, STL) and the heightfield.

use super::*;

#[test]
fn heightfield_is_a_mesh_over_the_unit_square() {
    let d = shape(
        "heightfield",
        vec![
            ("nu", ints(&[2])),
            ("nv", ints(&[3])),
            ("Pz", floats(&[0.0, 0.0, 0.5, 0.5, 1.0, 1.0])),
        ],
        DMat4::IDENTITY,
        false,
    );
    let g = geo(&[d]);
    let si = hit(&g, [0.3, 0.25, 5.0], [0.0, 0.0, -1.0]).unwrap();
    assert!((si.it.p.z - 0.25).abs() < 1e-5);
    assert!((si.uv - Vec2::new(0.3, 0.25)).abs().max_element() < 1e-5);
}

fn temp_dir(tag: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("luxfarm-geom-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A PLY with a quad [0,1]² at z = 0 (normals +z, uv = xy) and one triangle above it.
fn ply_bytes(format: &str) -> Vec<u8> {
    let verts: [[f32; 8]; 7] = [
        [0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0],
        [1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        [0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0],
        [5.0, 5.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0],
        [6.0, 5.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0],
        [5.0, 6.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0],
    ];
    let faces: [&[i32]; 2] = [&[0, 1, 2, 3], &[4, 5, 6]];
    let mut out = format!(
        "ply\nformat {format} 1.0\ncomment test\nelement vertex 7\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
    )
    .into_bytes();
    let be = format == "binary_big_endian";
    for v in verts {
        for x in v {
            match format {
                "ascii" => out.extend(format!("{x} ").bytes()),
                _ if be => out.extend(x.to_be_bytes()),
                _ => out.extend(x.to_le_bytes()),
            }
        }
        if format == "ascii" {
            out.push(b'\n');
        }
    }
    for f in faces {
        if format == "ascii" {
            out.extend(
                format!(
                    "{} {}\n",
                    f.len(),
                    f.iter()
                        .map(|i| i.to_string())
                        .collect::<Vec<_>>()
                        .join(" ")
                )
                .bytes(),
            );
        } else {
            out.push(f.len() as u8);
            for &i in f {
                out.extend(if be { i.to_be_bytes() } else { i.to_le_bytes() });
            }
        }
    }
    out
}

#[test]
fn plymesh_ascii_and_binary() {
    let dir = temp_dir("ply");
    for format in ["ascii", "binary_little_endian", "binary_big_endian"] {
        let name = format!("{format}.ply");
        std::fs::write(dir.join(&name), ply_bytes(format)).unwrap();
        let d = shape(
            "plymesh",
            vec![("filename", ParamValue::String(vec![name.clone()]))],
            DMat4::from_translation(DVec3::new(0.0, 0.0, 2.0)),
            false,
        );
        let mut b = GeometryBuilder::new();
        b.add_shape(
            &d,
            3,
            &ShapeCtx {
                files: dir.clone().into(),
                ..ShapeCtx::default()
            },
        )
        .unwrap_or_else(|e| panic!("{format}: {e}"));
        let g = b.build();
        let si = hit(&g, [0.25, 0.75, 5.0], [0.0, 0.0, -1.0]).expect(format);
        assert!((si.t - 3.0).abs() < 1e-5, "{format}");
        assert!(
            (si.uv - Vec2::new(0.25, 0.75)).abs().max_element() < 1e-5,
            "{format}"
        );
        assert!(close(si.shading.n, Vec3A::Z, 1e-6) && si.prim == 3);
        assert!(
            hit(&g, [5.2, 5.2, 5.0], [0.0, 0.0, -1.0]).is_some(),
            "{format} triangle"
        );
    }
    std::fs::write(
        dir.join("bad.ply"),
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1 2",
    )
    .unwrap();
    let d = shape(
        "plymesh",
        vec![("filename", ParamValue::String(vec!["bad.ply".into()]))],
        DMat4::IDENTITY,
        false,
    );
    let err = GeometryBuilder::new()
        .add_shape(
            &d,
            0,
            &ShapeCtx {
                files: dir.clone().into(),
                ..ShapeCtx::default()
            },
        )
        .unwrap_err();
    assert!(err.to_string().contains("test.lxs:7:3"), "{err}");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn stlmesh_ascii_and_binary() {
    let dir = temp_dir("stl");
    let tri = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let mut ascii = String::from("solid t\nfacet normal 0 0 1\nouter loop\n");
    for v in tri {
        ascii += &format!("vertex {} {} {}\n", v[0], v[1], v[2]);
    }
    ascii += "endloop\nendfacet\nendsolid t\n";
    std::fs::write(dir.join("a.stl"), ascii).unwrap();
    let mut bin = vec![0u8; 80];
    bin.extend(1u32.to_le_bytes());
    bin.extend([0.0f32, 0.0, 1.0].iter().flat_map(|x| x.to_le_bytes()));
    bin.extend(tri.iter().flatten().flat_map(|x| x.to_le_bytes()));
    bin.extend([0u8, 0]);
    std::fs::write(dir.join("b.stl"), bin).unwrap();
    for name in ["a.stl", "b.stl"] {
        let d = shape(
            "stlmesh",
            vec![("filename", ParamValue::String(vec![name.into()]))],
            DMat4::IDENTITY,
            false,
        );
        let mut b = GeometryBuilder::new();
        b.add_shape(
            &d,
            0,
            &ShapeCtx {
                files: dir.clone().into(),
                ..ShapeCtx::default()
            },
        )
        .unwrap();
        let g = b.build();
        let si = hit(&g, [0.2, 0.2, 1.0], [0.0, 0.0, -1.0]).expect(name);
        assert!(close(si.it.n, Vec3A::Z, 1e-6));
        assert!(hit(&g, [0.8, 0.8, 1.0], [0.0, 0.0, -1.0]).is_none());
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn plymesh_without_normals_gets_smoothed_vertex_normals() {
    let data = crate::shape::plymesh::parse(
        b"ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 3 1\n",
    )
    .unwrap();
    assert!(data.n.is_none() && data.uv.is_none());
    let n = crate::shape::plymesh::smooth_normals(&data);
    let s = std::f32::consts::FRAC_1_SQRT_2;
    assert!((Vec3A::from_array(n[0]) - Vec3A::new(0.0, s, s)).length() < 1e-6);
    assert!((Vec3A::from_array(n[2]) - Vec3A::Z).length() < 1e-6);
}
