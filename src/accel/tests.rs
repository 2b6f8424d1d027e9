//! Tests of shapes through the accelerator: analytic hits, clipping, orientation, files,
//! instancing, scale robustness and area sampling.

use super::*;
use crate::lxs::{ObjectDesc, ParamValue};
use crate::shape::test_util::{floats, ints, points, quad, shape};
use glam::{DMat4, DVec3};
use std::f32::consts::PI;

fn geo(descs: &[ShapeDesc]) -> Geometry {
    let mut b = GeometryBuilder::new();
    for (i, d) in descs.iter().enumerate() {
        b.add_shape(d, i as u32, &ShapeCtx::default())
            .expect("shape builds");
    }
    b.build()
}

fn close(a: Vec3A, b: Vec3A, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

fn hit(g: &Geometry, o: [f32; 3], d: [f32; 3]) -> Option<SurfaceInteraction> {
    g.intersect(&Ray::new(Vec3A::from_array(o), Vec3A::from_array(d)))
}

fn sphere(params: Vec<(&str, ParamValue)>, reverse: bool) -> ShapeDesc {
    shape("sphere", params, DMat4::IDENTITY, reverse)
}

#[test]
fn sphere_hit_point_normal_uv() {
    let g = geo(&[sphere(vec![("radius", floats(&[2.0]))], false)]);
    let si = hit(&g, [5.0, 0.0, 0.0], [-1.0, 0.0, 0.0]).unwrap();
    assert!((si.t - 3.0).abs() < 1e-5);
    assert!(close(si.it.p, Vec3A::new(2.0, 0.0, 0.0), 1e-5));
    assert!(close(si.it.n, Vec3A::X, 1e-5));
    assert!(
        (si.uv.x - 0.0).abs() < 1e-5 && (si.uv.y - 0.5).abs() < 1e-5,
        "{:?}",
        si.uv
    );
    assert!(close(si.wo, Vec3A::X, 1e-6));
    let si = hit(&g, [0.0, 5.0, 0.0], [0.0, -2.0, 0.0]).unwrap();
    assert!((si.t - 1.5).abs() < 1e-5, "t in the ray's own parameter");
    assert!((si.uv.x - 0.25).abs() < 1e-5);
    // frames are consistent: n ∥ dpdu × dpdv, shading frame orthonormal around n
    assert!(si.dpdu.cross(si.dpdv).normalize().dot(si.it.n) > 0.999);
    assert!(si.shading.n.dot(si.shading.dpdu).abs() < 1e-5);
    assert!(si.it.p_error.max_element() > 0.0);
}

#[test]
fn sphere_clipping_zmax_and_phimax() {
    let g = geo(&[sphere(
        vec![("radius", floats(&[2.0])), ("zmax", floats(&[1.0]))],
        false,
    )]);
    let si = hit(&g, [0.0, 0.0, 5.0], [0.0, 0.0, -1.0]).unwrap();
    assert!(
        (si.t - 7.0).abs() < 1e-4,
        "cap removed: hits the bottom from inside"
    );
    assert!(close(si.it.n, -Vec3A::Z, 1e-5));
    let g = geo(&[sphere(
        vec![("radius", floats(&[2.0])), ("phimax", floats(&[180.0]))],
        false,
    )]);
    let si = hit(&g, [0.0, -5.0, 0.0], [0.0, 1.0, 0.0]).unwrap();
    assert!((si.t - 7.0).abs() < 1e-4, "phi 270° clipped, phi 90° kept");
    assert!(hit(&g, [0.0, -5.0, 0.0], [0.0, -1.0, 0.0]).is_none());
}

#[test]
fn reverse_orientation_and_mirror_flip_normals() {
    let g = geo(&[sphere(vec![], true)]);
    let si = hit(&g, [5.0, 0.0, 0.0], [-1.0, 0.0, 0.0]).unwrap();
    assert!(close(si.it.n, -Vec3A::X, 1e-5));
    // quads: +z normally, -z reversed, -z under a mirror, +z mirrored and reversed
    let mirror = DMat4::from_scale(DVec3::new(1.0, 1.0, -1.0));
    for (m, rev, nz) in [
        (DMat4::IDENTITY, false, 1.0),
        (DMat4::IDENTITY, true, -1.0),
        (mirror, false, -1.0),
        (mirror, true, 1.0),
    ] {
        let g = geo(&[quad(m, rev)]);
        let si = hit(&g, [0.1, 0.2, 3.0], [0.0, 0.0, -1.0]).unwrap();
        assert!(
            (si.it.n.z - nz).abs() < 1e-6,
            "mirror {} reverse {rev}",
            m != DMat4::IDENTITY
        );
    }
    // a mirrored sphere keeps its outward normal
    let g = geo(&[shape("sphere", vec![], mirror, false)]);
    let si = hit(&g, [5.0, 0.0, 0.0], [-1.0, 0.0, 0.0]).unwrap();
    assert!(close(si.it.n, Vec3A::X, 1e-5));
}

#[test]
fn disk_cylinder_cone_paraboloid_hyperboloid() {
    let disk = shape(
        "disk",
        vec![("innerradius", floats(&[0.25]))],
        DMat4::IDENTITY,
        false,
    );
    let g = geo(&[disk]);
    let si = hit(&g, [0.5, 0.0, 1.0], [0.0, 0.0, -1.0]).unwrap();
    assert!((si.t - 1.0).abs() < 1e-6 && close(si.it.n, Vec3A::Z, 1e-6));
    assert!((si.uv.y - (1.0 - 0.5) / 0.75).abs() < 1e-5);
    assert!(
        hit(&g, [0.1, 0.0, 1.0], [0.0, 0.0, -1.0]).is_none(),
        "inner radius"
    );

    let cyl = shape(
        "cylinder",
        vec![("zmax", floats(&[0.4]))],
        DMat4::IDENTITY,
        false,
    );
    let g = geo(&[cyl]);
    let si = hit(&g, [5.0, 0.0, 0.2], [-1.0, 0.0, 0.0]).unwrap();
    assert!((si.t - 4.0).abs() < 1e-5 && close(si.it.n, Vec3A::X, 1e-5));
    assert!((si.uv.y - 1.2 / 1.4).abs() < 1e-5);
    assert!(
        hit(&g, [5.0, 0.0, 0.5], [-1.0, 0.0, 0.0]).is_none(),
        "zmax clips"
    );

    let g = geo(&[shape("cone", vec![], DMat4::IDENTITY, false)]);
    let si = hit(&g, [5.0, 0.0, 0.5], [-1.0, 0.0, 0.0]).unwrap();
    assert!((si.t - 4.5).abs() < 1e-5);
    let s = std::f32::consts::FRAC_1_SQRT_2;
    assert!(close(si.it.n, Vec3A::new(s, 0.0, s), 1e-5), "{:?}", si.it.n);

    let g = geo(&[shape("paraboloid", vec![], DMat4::IDENTITY, false)]);
    let si = hit(&g, [5.0, 0.0, 0.25], [-1.0, 0.0, 0.0]).unwrap();
    assert!((si.t - 4.5).abs() < 1e-5);
    assert!(
        close(si.it.n, Vec3A::new(s, 0.0, -s), 1e-5),
        "{:?}",
        si.it.n
    );

    let hyp = shape(
        "hyperboloid",
        vec![
            ("p1", points(&[[1.0, 0.0, 0.0]])),
            ("p2", points(&[[1.0, 0.0, 1.0]])),
        ],
        DMat4::IDENTITY,
        false,
    );
    let g = geo(&[hyp]);
    let si = hit(&g, [5.0, 0.0, 0.5], [-1.0, 0.0, 0.0]).unwrap();
    assert!((si.t - 4.0).abs() < 1e-5 && close(si.it.n, Vec3A::X, 1e-5));
    assert!((si.uv.y - 0.5).abs() < 1e-5);
    // a twisted hyperboloid: hit points satisfy the swept-line equation
    let hyp = shape(
        "hyperboloid",
        vec![
            ("p1", points(&[[1.0, -1.0, -1.0]])),
            ("p2", points(&[[1.0, 1.0, 1.0]])),
        ],
        DMat4::IDENTITY,
        false,
    );
    let g = geo(&[hyp]);
    let si = hit(&g, [5.0, 0.1, 0.3], [-1.0, 0.0, 0.0]).unwrap();
    let p = si.it.p;
    let expected_r2 = 1.0 + p.z * p.z; // the line (1, z, z) swept: r² = 1 + z²
    assert!((p.x * p.x + p.y * p.y - expected_r2).abs() < 1e-4);
}

#[test]
fn mesh_uv_normals_and_shading() {
    let mut d = quad(DMat4::IDENTITY, false);
    d.entity
        .params
        .add("uv", floats(&[0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0]));
    let g = geo(&[d]);
    let si = hit(&g, [0.5, -0.5, 2.0], [0.0, 0.0, -1.0]).unwrap();
    assert!((si.uv - Vec2::new(0.75, 0.25)).abs().max_element() < 1e-5);
    assert!(close(si.dpdu, Vec3A::new(2.0, 0.0, 0.0), 1e-5));
    assert!(close(si.dpdv, Vec3A::new(0.0, 2.0, 0.0), 1e-5));
    // vertex normals (tilted) with ReverseOrientation: shading normal negated, n follows it
    let mut d = quad(DMat4::IDENTITY, true);
    d.entity
        .params
        .add("N", ParamValue::Normal(vec![[0.0, 0.6, 0.8]; 4]));
    let g = geo(&[d]);
    let si = hit(&g, [0.5, -0.5, 2.0], [0.0, 0.0, -1.0]).unwrap();
    assert!(close(si.shading.n, Vec3A::new(0.0, -0.6, -0.8), 1e-5));
    assert!(close(si.it.n, -Vec3A::Z, 1e-6));
    // no uv: frame still consistent
    let g = geo(&[quad(DMat4::IDENTITY, false)]);
    let si = hit(&g, [0.5, -0.5, 2.0], [0.0, 0.0, -1.0]).unwrap();
    assert!(si.dpdu.cross(si.dpdv).normalize().dot(si.it.n).abs() > 0.999);
}

#[test]
fn mesh_quads_and_bad_indices() {
    let d = shape(
        "mesh",
        vec![
            ("quadindices", ints(&[0, 1, 2, 3])),
            (
                "P",
                points(&[
                    [0.0, 0.0, 0.0],
                    [1.0, 0.0, 0.0],
                    [1.0, 1.0, 0.0],
                    [0.0, 1.0, 0.0],
                ]),
            ),
        ],
        DMat4::IDENTITY,
        false,
    );
    let g = geo(&[d]);
    assert!(hit(&g, [0.9, 0.1, 1.0], [0.0, 0.0, -1.0]).is_some());
    assert!(hit(&g, [0.1, 0.9, 1.0], [0.0, 0.0, -1.0]).is_some());
    assert!((g.area(ShapeId(0)) - 1.0).abs() < 1e-6);
    let bad = shape(
        "trianglemesh",
        vec![("indices", ints(&[0, 1, 5])), ("P", points(&[[0.0; 3]; 3]))],
        DMat4::IDENTITY,
        false,
    );
    let err = GeometryBuilder::new()
        .add_shape(&bad, 0, &ShapeCtx::default())
        .unwrap_err();
    assert!(err.to_string().starts_with("test.lxs:7:3:"), "{err}");
    let unknown = shape("teapot", vec![], DMat4::IDENTITY, false);
    assert!(GeometryBuilder::new()
        .add_shape(&unknown, 0, &ShapeCtx::default())
        .is_err());
}

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
                base_dir: dir.clone(),
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
                base_dir: dir.clone(),
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
                base_dir: dir.clone(),
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
fn instances_hit_at_their_places() {
    let obj = ObjectDesc {
        name: "ball".into(),
        shapes: vec![
            sphere(vec![("radius", floats(&[0.5]))], false),
            quad(DMat4::from_translation(DVec3::new(0.0, 0.0, -2.0)), false),
        ],
        loc: Default::default(),
    };
    let mut b = GeometryBuilder::new();
    let id = b.add_object(&obj, &[10, 11], &ShapeCtx::default()).unwrap();
    b.add_instance(
        id,
        &Xform::fixed(DMat4::from_translation(DVec3::new(-3.0, 0.0, 0.0))),
    );
    b.add_instance(
        id,
        &Xform::fixed(
            DMat4::from_translation(DVec3::new(3.0, 0.0, 0.0))
                * DMat4::from_scale(DVec3::splat(2.0)),
        ),
    );
    b.add_shape(
        &quad(DMat4::from_translation(DVec3::new(0.0, 0.0, -10.0)), false),
        20,
        &ShapeCtx::default(),
    )
    .unwrap();
    let g = b.build();
    let si = hit(&g, [-3.0, 0.0, 5.0], [0.0, 0.0, -1.0]).unwrap();
    assert!((si.t - 4.5).abs() < 1e-5 && si.prim == 10);
    assert!(close(si.it.n, Vec3A::Z, 1e-5));
    let si = hit(&g, [3.0, 0.0, 5.0], [0.0, 0.0, -1.0]).unwrap();
    assert!(
        (si.t - 4.0).abs() < 1e-5 && si.prim == 10,
        "scaled instance: radius 1"
    );
    let si = hit(&g, [3.0 + 1.5, 0.0, 5.0], [0.0, 0.0, -1.0]).unwrap();
    assert!(
        (si.t - 9.0).abs() < 1e-5 && si.prim == 11,
        "its quad at z = -4"
    );
    let si = hit(&g, [0.0, 0.0, 5.0], [0.0, 0.0, -1.0]).unwrap();
    assert!(si.prim == 20 && (si.t - 15.0).abs() < 1e-4);
    assert!(g.intersect_p(&Ray::new(Vec3A::new(3.0, 0.0, 5.0), -Vec3A::Z)));
    assert!(!g.intersect_p(&Ray {
        o: Vec3A::new(3.0, 0.0, 5.0),
        d: -Vec3A::Z,
        t_max: 3.5,
        time: 0.0
    }));
    let (lo, hi) = g.bounds();
    assert!(lo.x <= -3.5 && hi.x >= 5.0);
}

/// Two parallel quads `gap` apart (lower facing up, upper facing down) and a sphere, scaled.
fn scaled_scene(scale: f64, instanced: bool) -> Geometry {
    let s = DMat4::from_scale(DVec3::splat(scale));
    let gap = 1e-3;
    let descs = vec![
        quad(
            s * DMat4::from_translation(DVec3::new(0.3, 0.1, 0.7)),
            false,
        ),
        quad(
            s * DMat4::from_translation(DVec3::new(0.3, 0.1, 0.7 + gap))
                * DMat4::from_scale(DVec3::new(1.0, 1.0, -1.0)),
            false,
        ),
        shape(
            "sphere",
            vec![("radius", floats(&[0.4]))],
            s * DMat4::from_translation(DVec3::new(3.0, 0.2, 0.5)),
            false,
        ),
    ];
    if !instanced {
        return geo(&descs);
    }
    let mut b = GeometryBuilder::new();
    let obj = ObjectDesc {
        name: "o".into(),
        shapes: descs,
        loc: Default::default(),
    };
    let id = b
        .add_object(&obj, &[0, 1, 2], &ShapeCtx::default())
        .unwrap();
    b.add_instance(id, &Xform::fixed(DMat4::from_rotation_z(0.3)));
    b.build()
}

#[test]
fn no_acne_and_no_leaks_at_any_scale() {
    for scale in [1e-4, 1.0, 1e5] {
        for instanced in [false, true] {
            let g = scaled_scene(scale, instanced);
            let mut rng = bench::Rng::new(1);
            let sf = scale as f32;
            let (mut leaks, mut acne, mut tested) = (0, 0, 0);
            for i in 0..2000 {
                // aim at the lower quad from above, between the planes' edges
                let target = Vec3A::new(
                    0.3 + rng.f32() * 1.6 - 0.8,
                    0.1 + rng.f32() * 1.6 - 0.8,
                    0.7,
                ) * sf;
                let target = if instanced {
                    Vec3A::new(
                        target.x * 0.3f32.cos() - target.y * 0.3f32.sin(),
                        target.x * 0.3f32.sin() + target.y * 0.3f32.cos(),
                        target.z,
                    )
                } else {
                    target
                };
                let from_below = i % 2 == 0;
                let o = target + Vec3A::new(0.0, 0.0, if from_below { -1.0 } else { 1.0 }) * sf;
                let Some(si) = g.intersect(&Ray::new(o, target - o)) else {
                    continue;
                };
                tested += 1;
                let first = si.prim;
                // reflection-like: leave on the side the ray came from
                let mut d = rng.direction();
                if d.dot(si.it.n) * si.wo.dot(si.it.n) < 0.0 {
                    d = -d;
                }
                if g.intersect(&si.it.spawn_ray(d))
                    .is_some_and(|h| h.prim == first)
                {
                    acne += 1;
                }
                // transmission-like from below: through the lower quad, the upper one is
                // `gap` away and must be hit
                if from_below {
                    let up = si.it.spawn_ray(Vec3A::new(0.01, 0.02, 1.0).normalize());
                    match g.intersect(&up) {
                        Some(h) if h.prim == first => acne += 1,
                        Some(h) if h.prim == 1 => {}
                        _ => leaks += 1,
                    }
                }
            }
            assert!(tested > 1000, "scale {scale}");
            assert_eq!(acne, 0, "scale {scale} instanced {instanced}: self-hits");
            assert_eq!(leaks, 0, "scale {scale} instanced {instanced}: leaks");
        }
    }
}

#[test]
fn rays_between_close_surfaces_hit_the_other_one() {
    for scale in [1e-4, 1.0, 1e5] {
        for instanced in [false, true] {
            let g = scaled_scene(scale, instanced);
            let sf = scale as f32;
            let mut rng = bench::Rng::new(2);
            let rot = |v: Vec3A| {
                if instanced {
                    Vec3A::new(
                        v.x * 0.3f32.cos() - v.y * 0.3f32.sin(),
                        v.x * 0.3f32.sin() + v.y * 0.3f32.cos(),
                        v.z,
                    )
                } else {
                    v
                }
            };
            for _ in 0..500 {
                let x = Vec3A::new(0.3 + rng.f32() - 0.5, 0.1 + rng.f32() - 0.5, 0.0);
                // from below the lower quad straight up: hits it, then from it hits the upper one
                let o = rot(Vec3A::new(x.x, x.y, 0.0) * sf);
                let target = rot(Vec3A::new(x.x, x.y, 0.7) * sf);
                let si = g.intersect(&Ray::new(o, target - o)).expect("lower quad");
                assert_eq!(si.prim, 0);
                let mut d = rng.direction();
                d.z = d.z.abs().max(0.3);
                let d = rot(d.normalize());
                let next = g.intersect(&si.it.spawn_ray(d));
                assert!(next.is_none() || next.unwrap().prim == 1, "scale {scale}");
                let lower = si.it;
                // from above the upper quad: hits its back... then down it must reach the lower
                let top = rot(Vec3A::new(x.x, x.y, 2.0) * sf);
                let s2 = g
                    .intersect(&Ray::new(top, target - top))
                    .expect("upper quad");
                assert_eq!(s2.prim, 1);
                // the segment between points on the two quads is unobstructed
                let upper = s2.it;
                assert!(
                    !g.intersect_p(&lower.spawn_ray_to(&upper)),
                    "scale {scale} instanced {instanced}"
                );
                assert!(!g.intersect_p(&upper.spawn_ray_to(&lower)), "scale {scale}");
            }
            // sphere: leaving outward never re-hits it; going inward hits the far side
            let c = rot(Vec3A::new(3.0, 0.2, 0.5) * sf);
            for _ in 0..500 {
                let dir = rng.direction();
                let o = c + dir * 0.9 * sf;
                let si = g.intersect(&Ray::new(o, c - o)).expect("sphere");
                assert_eq!(si.prim, 2);
                let mut d = rng.direction();
                if d.dot(si.it.n) < 0.0 {
                    d = -d;
                }
                assert!(g.intersect(&si.it.spawn_ray(d)).is_none_or(|h| h.prim != 2));
                let inside = g.intersect(&si.it.spawn_ray(-d)).expect("far side");
                assert!((inside.it.p - si.it.p).length() > 1e-3 * sf * 0.4 * d.dot(si.it.n).abs());
            }
        }
    }
}

fn mean_and_inverse_pdf(g: &Geometry, id: ShapeId, n: usize) -> (Vec3A, f64, Vec<Interaction>) {
    let mut rng = bench::Rng::new(5);
    let (mut sum, mut inv) = (Vec3A::ZERO, 0.0f64);
    let mut pts = Vec::new();
    for _ in 0..n {
        let (it, pdf) = g.sample(id, Vec2::new(rng.f32(), rng.f32()), rng.f32());
        assert!(pdf > 0.0 && pdf.is_finite());
        sum += it.p;
        inv += 1.0 / pdf as f64;
        pts.push(it);
    }
    (sum / n as f32, inv / n as f64, pts)
}

#[test]
fn area_sampling_is_uniform_and_pdf_integrates_to_one() {
    let hemi = sphere(
        vec![("radius", floats(&[2.0])), ("zmin", floats(&[0.0]))],
        false,
    );
    let g = geo(&[hemi]);
    assert!((g.area(ShapeId(0)) - 2.0 * PI * 4.0).abs() < 1e-3);
    let (mean, inv, pts) = mean_and_inverse_pdf(&g, ShapeId(0), 40_000);
    assert!(
        (mean.z - 1.0).abs() < 0.02,
        "Archimedes: centroid at r/2, got {}",
        mean.z
    );
    assert!((inv / g.area(ShapeId(0)) as f64 - 1.0).abs() < 1e-4);
    for it in &pts[..100] {
        assert!((it.p.length() - 2.0).abs() < 1e-5 && it.n.dot(it.p) > 0.0);
    }
    // every shape: E[1/pdf] equals the area (pdf integrates to 1 over the surface)
    let non_uniform = DMat4::from_scale(DVec3::new(2.0, 1.0, 0.5));
    let descs = [
        shape(
            "disk",
            vec![
                ("innerradius", floats(&[0.5])),
                ("phimax", floats(&[270.0])),
            ],
            DMat4::IDENTITY,
            false,
        ),
        shape(
            "cylinder",
            vec![],
            DMat4::from_scale(DVec3::splat(3.0)),
            false,
        ),
        shape(
            "cone",
            vec![("height", floats(&[2.0]))],
            DMat4::IDENTITY,
            false,
        ),
        shape(
            "paraboloid",
            vec![("zmin", floats(&[0.2]))],
            DMat4::IDENTITY,
            false,
        ),
        shape(
            "hyperboloid",
            vec![
                ("p1", points(&[[1.0, -1.0, -1.0]])),
                ("p2", points(&[[1.0, 1.0, 1.0]])),
            ],
            DMat4::IDENTITY,
            false,
        ),
        shape("sphere", vec![], non_uniform, false),
        quad(DMat4::from_scale(DVec3::new(1.0, 3.0, 1.0)), false),
    ];
    let g = geo(&descs);
    for (i, d) in descs.iter().enumerate() {
        let id = ShapeId(i as u32);
        let (_, inv, _) = mean_and_inverse_pdf(&g, id, 20_000);
        let a = g.area(id) as f64;
        assert!(
            (inv / a - 1.0).abs() < 0.02,
            "{}: E[1/pdf] {inv} vs area {a}",
            d.entity.kind
        );
    }
    // analytic areas
    let cone_area = PI * 1.0 * (1.0f32 + 4.0).sqrt();
    assert!((g.area(ShapeId(2)) - cone_area).abs() < 1e-4);
    let parab = PI / 6.0 * (5.0f32.powf(1.5) - 1.8f32.powf(1.5)); // z = r², r from sqrt(.2) to 1
    assert!(
        (g.area(ShapeId(3)) - parab).abs() < 1e-3,
        "{} vs {parab}",
        g.area(ShapeId(3))
    );
    assert!((g.area(ShapeId(6)) - 12.0).abs() < 1e-5);
    // paraboloid samples are uniform by area: mean z matches the area-weighted mean
    let (mean, _, _) = mean_and_inverse_pdf(&g, ShapeId(3), 40_000);
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for k in 0..100_000 {
        let z = 0.2 + 0.8 * (k as f64 + 0.5) / 100_000.0;
        let w = (z + 0.25).sqrt(); // dA/dz ∝ sqrt(r² + r'²/4) with r² = z
        num += z * w;
        den += w;
    }
    assert!(
        (mean.z as f64 - num / den).abs() < 0.01,
        "{} vs {}",
        mean.z,
        num / den
    );
}
