//! Analytic hits, clipping, orientation and degenerate parameters.

use super::*;

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
fn degenerate_quadrics_are_errors_and_motion_starts_at_the_first_key() {
    for bad in [
        sphere(vec![("phimax", floats(&[0.0]))], false),
        shape(
            "disk",
            vec![("innerradius", floats(&[2.0]))],
            DMat4::IDENTITY,
            false,
        ),
        shape(
            "cone",
            vec![("height", floats(&[-1.0]))],
            DMat4::IDENTITY,
            false,
        ),
        shape("sphere", vec![], DMat4::ZERO, false),
        shape(
            "heightfield",
            vec![
                ("nu", ints(&[2])),
                ("nv", ints(&[2])),
                ("Pz", floats(&[0.0])),
            ],
            DMat4::IDENTITY,
            false,
        ),
    ] {
        let e = GeometryBuilder::new().add_shape(&bad, 0, &ShapeCtx::default());
        assert!(e.is_err(), "{} should fail", bad.entity.kind);
    }
    let mut moving = sphere(vec![], false);
    moving.object_to_world = Xform {
        keys: vec![
            (0.0, DMat4::IDENTITY),
            (1.0, DMat4::from_translation(DVec3::new(5.0, 0.0, 0.0))),
        ],
    };
    let g = geo(&[moving]);
    let si = hit(&g, [0.0, 0.0, 5.0], [0.0, 0.0, -1.0]).unwrap();
    assert!((si.t - 4.0).abs() < 1e-5);
    // At the shutter's close it is at its last key.
    let mut r = Ray::new(Vec3A::new(5.0, 0.0, 5.0), -Vec3A::Z);
    r.time = 1.0;
    assert!((g.intersect(&r).unwrap().t - 4.0).abs() < 1e-5);
    r.o.x = 0.0;
    assert!(g.intersect(&r).is_none());
}
