//! The unit tests of [`super::loopsubdiv`]: Loop subdivision by level count, displacement
//! by a float texture, microdisplacement, the triangle limit, meshes that cannot be
//! subdivided, and the uv, colour and alpha channels carried through. They build shapes
//! through `Shape::build` as a scene does.

use super::loopsubdiv::{subdivided_count, MAX_TRIANGLES};
use crate::lxs::ParamValue;
use crate::shape::test_util::{floats, ints, points, shape};
use crate::shape::BuildError;
use crate::shape::{Shape, ShapeCtx, TriangleMesh};
use crate::texture::FloatTex;
use glam::DMat4;

fn tetra(extra: Vec<(&str, ParamValue)>) -> crate::lxs::ShapeDesc {
    let mut params = vec![
        (
            "P",
            points(&[
                [1.0, 1.0, 1.0],
                [1.0, -1.0, -1.0],
                [-1.0, 1.0, -1.0],
                [-1.0, -1.0, 1.0],
            ]),
        ),
        ("indices", ints(&[0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2])),
    ];
    params.extend(extra);
    shape("loopsubdiv", params, DMat4::IDENTITY, false)
}

/// A 2×2 plane on [-1,1]² at z = 0 made of four quads.
fn plane(extra: Vec<(&str, ParamValue)>, m: DMat4, reverse: bool) -> crate::lxs::ShapeDesc {
    let mut p = Vec::new();
    for j in 0..3 {
        for i in 0..3 {
            p.push([i as f32 - 1.0, j as f32 - 1.0, 0.0]);
        }
    }
    let q = |i: i32, j: i32| {
        [
            j * 3 + i,
            j * 3 + i + 1,
            (j + 1) * 3 + i + 1,
            (j + 1) * 3 + i,
        ]
    };
    let quads: Vec<i32> = [(0, 0), (1, 0), (0, 1), (1, 1)]
        .iter()
        .flat_map(|&(i, j)| q(i, j))
        .collect();
    let mut params = vec![("P", points(&p)), ("quadindices", ints(&quads))];
    params.extend(extra);
    shape("trianglemesh", params, m, reverse)
}

fn build(desc: &crate::lxs::ShapeDesc, ctx: &ShapeCtx) -> Result<TriangleMesh, BuildError> {
    match Shape::build(desc, &crate::geometry::Transform::IDENTITY, ctx)? {
        Shape::Mesh(m) => Ok(m),
        Shape::Quadric(_) => panic!("a mesh"),
    }
}

fn ctx_with(name: &str, value: f32) -> ShapeCtx {
    let mut ctx = ShapeCtx::default();
    ctx.displacement
        .insert(name.to_string(), FloatTex::constant(value));
    ctx
}

#[test]
fn loopsubdiv_subdivides_by_nlevels_and_defaults_to_none() {
    let m = build(&tetra(vec![("nlevels", ints(&[2]))]), &ShapeCtx::default()).unwrap();
    assert_eq!(m.tris.len(), 64);
    let n = m.n.as_ref().expect("smoothed normals by default");
    for (p, n) in m.p.iter().zip(n) {
        assert!(n.dot(p.normalize()) > 0.9, "outward normal {n} at {p}");
    }
    // LuxRender 1.x builds loopsubdiv with the mesh plugin: nlevels defaults to 0.
    let m = build(&tetra(vec![]), &ShapeCtx::default()).unwrap();
    assert_eq!(m.tris.len(), 4);
    let flat = build(
        &tetra(vec![
            ("nsubdivlevels", ints(&[1])),
            ("dmnormalsmooth", ParamValue::Bool(vec![false])),
        ]),
        &ShapeCtx::default(),
    )
    .unwrap();
    assert_eq!(flat.tris.len(), 16);
    assert!(flat.n.is_none());
}

#[test]
fn a_displaced_plane_moves_its_vertices_by_the_map_times_dmscale() {
    let extra = || {
        vec![
            ("nsubdivlevels", ints(&[2])),
            ("displacementmap", ParamValue::Texture("dm".into())),
            ("dmscale", floats(&[0.2])),
        ]
    };
    let m = build(
        &plane(extra(), DMat4::IDENTITY, false),
        &ctx_with("dm", 0.5),
    )
    .unwrap();
    assert_eq!(m.tris.len(), 8 * 16);
    for p in &m.p {
        assert!((p.z - 0.1).abs() < 1e-6, "{p}");
    }
    for n in m.n.as_ref().unwrap() {
        assert!((n.z - 1.0).abs() < 1e-6, "{n}");
    }
    // dmoffset adds; the displacement is measured after the shape's transform.
    let mut e = extra();
    e.push(("dmoffset", floats(&[0.05])));
    let m2 = DMat4::from_scale(glam::DVec3::new(1.0, 1.0, 3.0));
    let m = build(&plane(e, m2, false), &ctx_with("dm", 0.5)).unwrap();
    for p in &m.p {
        assert!((p.z - 0.15).abs() < 1e-6, "{p}");
    }
    // ReverseOrientation turns the normals, not the displacement.
    let m = build(&plane(extra(), DMat4::IDENTITY, true), &ctx_with("dm", 0.5)).unwrap();
    for (p, n) in m.p.iter().zip(m.n.as_ref().unwrap()) {
        assert!(
            (p.z - 0.1).abs() < 1e-6 && (n.z + 1.0).abs() < 1e-6,
            "{p} {n}"
        );
    }
    for f in &m.face_n {
        assert!((f.z + 1.0).abs() < 1e-6);
    }
}

#[test]
fn an_unknown_displacement_texture_only_warns() {
    let d = plane(
        vec![
            ("nsubdivlevels", ints(&[1])),
            ("displacementmap", ParamValue::String(vec!["nope".into()])),
        ],
        DMat4::IDENTITY,
        false,
    );
    let m = build(&d, &ShapeCtx::default()).unwrap();
    assert_eq!(m.tris.len(), 32);
    assert!(m.p.iter().all(|p| p.z == 0.0));
}

#[test]
fn too_many_levels_is_a_located_error_before_allocating() {
    let e = build(&tetra(vec![("nlevels", ints(&[30]))]), &ShapeCtx::default()).unwrap_err();
    assert_eq!(e.loc.to_string(), "test.lxs:7:3");
    assert!(e.message.contains("would give more than"), "{}", e.message);
    assert_eq!(subdivided_count(4, 30, MAX_TRIANGLES), None);
    assert_eq!(subdivided_count(4, 11, MAX_TRIANGLES), Some(4 << 22));
    assert_eq!(subdivided_count(4, 12, MAX_TRIANGLES), None);
    assert_eq!(subdivided_count(usize::MAX, 0, MAX_TRIANGLES), None);
}

#[test]
fn a_mesh_that_cannot_be_subdivided_is_kept() {
    let d = shape(
        "trianglemesh",
        vec![
            (
                "P",
                points(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]]),
            ),
            ("indices", ints(&[0, 1, 2, 1, 2, 3])),
            ("nsubdivlevels", ints(&[2])),
        ],
        DMat4::IDENTITY,
        false,
    );
    assert_eq!(build(&d, &ShapeCtx::default()).unwrap().tris.len(), 2);
}

#[test]
fn microdisplacement_splits_each_triangle_into_n_by_n_and_without_a_map_does_nothing() {
    let scheme = (
        "subdivscheme",
        ParamValue::String(vec!["microdisplacement".into()]),
    );
    let d = tetra(vec![scheme.clone(), ("nsubdivlevels", ints(&[2]))]);
    assert_eq!(build(&d, &ShapeCtx::default()).unwrap().tris.len(), 4);
    // nsubdivlevels counts segments per edge: 3 gives 9 micro-triangles per triangle of
    // the plane (8), each lifted by the map (1) times dmscale along the +z normal.
    let d = plane(
        vec![
            scheme,
            ("nsubdivlevels", ints(&[3])),
            ("displacementmap", ParamValue::Texture("dm".into())),
            ("dmscale", floats(&[0.25])),
        ],
        DMat4::IDENTITY,
        false,
    );
    let m = build(&d, &ctx_with("dm", 1.0)).unwrap();
    assert_eq!(m.tris.len(), 72);
    assert!(m.p.iter().all(|p| (p.z - 0.25).abs() < 1e-6));
    // Flat shaded: the plane has no normals.
    assert!(m.n.is_none());
    let e = build(
        &plane(
            vec![
                (
                    "subdivscheme",
                    ParamValue::String(vec!["microdisplacement".into()]),
                ),
                ("nsubdivlevels", ints(&[2000])),
                ("displacementmap", ParamValue::Texture("dm".into())),
            ],
            DMat4::IDENTITY,
            false,
        ),
        &ctx_with("dm", 1.0),
    )
    .unwrap_err();
    assert!(e.message.contains("more than"), "{}", e.message);
}

#[test]
fn uv_colours_and_alphas_are_carried_through() {
    let d = plane(
        vec![
            ("nsubdivlevels", ints(&[1])),
            (
                "uv",
                floats(
                    &(0..9)
                        .flat_map(|i| [(i % 3) as f32, (i / 3) as f32])
                        .collect::<Vec<_>>(),
                ),
            ),
            ("C", floats(&[0.5; 27])),
            ("A", floats(&[0.25; 9])),
        ],
        DMat4::IDENTITY,
        false,
    );
    let m = build(&d, &ShapeCtx::default()).unwrap();
    let uv = m.uv.as_ref().unwrap();
    assert_eq!(uv.len(), m.p.len());
    assert!(m.cols.as_ref().unwrap().iter().all(|c| *c == [0.5; 3]));
    assert!(m.alphas.as_ref().unwrap().iter().all(|&a| a == 0.25));
    // uv is affine in the position on this plane (u = x + 1, v = y + 1).
    for (p, t) in m.p.iter().zip(uv) {
        assert!((t.x - (p.x + 1.0)).abs() < 1e-5 && (t.y - (p.y + 1.0)).abs() < 1e-5);
    }
}
