//! Instancing, scale robustness (no acne, no leaks) and BVH configurations.

use super::*;

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
            let mut rng = fixtures::Rng::new(1);
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
            let mut rng = fixtures::Rng::new(2);
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

fn build_with(shapes: &[ShapeDesc], opts: bvh::BvhOptions) -> Geometry {
    let mut b = GeometryBuilder::with_options(opts);
    for (i, s) in shapes.iter().enumerate() {
        b.add_shape(s, i as u32, &ShapeCtx::default()).unwrap();
    }
    b.build()
}

/// What a closest hit found: primitive, distance, point and uv.
fn found(si: SurfaceInteraction) -> (u32, f32, Vec3A, glam::Vec2) {
    (si.prim, si.t, si.it.p, si.uv)
}

#[test]
fn every_bvh_configuration_finds_the_same_hits() {
    // The Cornell meshes and 30 small analytic spheres (quadrics share leaves and packets
    // with triangles).
    let mut shapes = fixtures::cornell_like();
    let mut rng = fixtures::Rng::new(77);
    for _ in 0..30 {
        let c = rng.in_box(Vec3A::new(-0.9, -0.9, 0.1), Vec3A::new(0.9, 0.9, 1.9));
        let at = DMat4::from_translation(DVec3::new(c.x as f64, c.y as f64, c.z as f64));
        let r = 0.02 + 0.06 * rng.f32();
        shapes.push(shape("sphere", vec![("radius", floats(&[r]))], at, false));
    }
    let build = |opts| build_with(&shapes, opts);
    let reference = build(bvh::BvhOptions::default());
    let (closest, any) = fixtures::incoherent_rays(&reference, 3000, 11);
    let expect: Vec<_> = closest
        .iter()
        .map(|r| reference.intersect(r).map(found))
        .collect();
    assert!(expect.iter().filter(|h| h.is_some()).count() > 2000);
    let sphere_hits = expect.iter().flatten().filter(|h| h.0 >= 6).count();
    assert!(sphere_hits > 20, "{sphere_hits} sphere hits");
    let expect_any: Vec<bool> = any.iter().map(|r| reference.intersect_p(r)).collect();
    for opts in bvh::BvhOptions::candidates() {
        let g = build(opts);
        for (r, e) in closest.iter().zip(&expect) {
            assert_eq!(g.intersect(r).map(found), *e, "{opts}");
        }
        for (r, e) in any.iter().zip(&expect_any) {
            assert_eq!(g.intersect_p(r), *e, "{opts}");
        }
    }
    // closest hits agree with any-hit queries along the same segment
    for (r, e) in closest.iter().zip(&expect) {
        if let Some((_, t, _, _)) = e {
            let seg = Ray {
                t_max: t * 1.01,
                ..*r
            };
            assert!(reference.intersect_p(&seg));
            let short = Ray {
                t_max: t * 0.99,
                ..*r
            };
            assert!(!reference.intersect_p(&short));
        }
    }
}

/// Clusters of quad, sphere, quad close together share leaves: packets mixing triangles and
/// a quadric, with the sphere in front of or behind a triangle of its packet. Every 8-wide
/// configuration finds what the binary BVH with single-primitive leaves finds.
#[test]
fn packets_mixing_triangles_and_quadrics_find_the_closest() {
    let mut shapes = Vec::new();
    let mut centres = Vec::new();
    for i in 0..40 {
        let c = DVec3::new((i % 8) as f64 * 3.0, (i / 8) as f64 * 3.0, 0.0);
        centres.push(Vec3A::new(c.x as f32, c.y as f32, 0.0));
        let dz = if i % 2 == 0 { 0.1 } else { -0.35 };
        let small = DMat4::from_scale(DVec3::splat(0.3));
        let quad_at = |z: f64| DMat4::from_translation(c + DVec3::new(0.0, 0.0, z)) * small;
        shapes.push(quad(quad_at(dz), false));
        let ball = vec![("radius", floats(&[0.3]))];
        shapes.push(shape("sphere", ball, DMat4::from_translation(c), false));
        shapes.push(quad(quad_at(-dz), false));
    }
    let single = bvh::BvhOptions {
        layout: bvh::BvhLayout::Bvh2,
        quality: bvh::BuildQuality::Medium,
        max_prims_per_leaf: 1,
    };
    let reference = build_with(&shapes, single);
    let mut rng = fixtures::Rng::new(4);
    let rays: Vec<Ray> = (0..6000)
        .map(|k| {
            let c = centres[k % centres.len()];
            let side = if k % 3 == 0 { -3.0 } else { 3.0 };
            let o = c + rng.in_box(Vec3A::splat(-0.4), Vec3A::splat(0.4)) + Vec3A::Z * side;
            let d = (c + rng.in_box(Vec3A::splat(-0.3), Vec3A::splat(0.3)) - o).normalize();
            Ray::new(o, d)
        })
        .collect();
    let expect: Vec<_> = rays
        .iter()
        .map(|r| reference.intersect(r).map(found))
        .collect();
    let sphere_hits = expect.iter().flatten().filter(|h| h.0 % 3 == 1).count();
    assert!(sphere_hits > 500, "{sphere_hits} sphere hits");
    for leaf in [3, 4, 8] {
        let opts = bvh::BvhOptions {
            layout: bvh::BvhLayout::Bvh8,
            quality: bvh::BuildQuality::Medium,
            max_prims_per_leaf: leaf,
        };
        let g = build_with(&shapes, opts);
        let (_, mixed) = g.world.packet_counts();
        assert!(mixed > 0, "{opts}: no packet mixes triangles and quadrics");
        for (r, e) in rays.iter().zip(&expect) {
            assert_eq!(g.intersect(r).map(found), *e, "{opts}");
            assert_eq!(g.intersect_p(r), e.is_some(), "{opts}");
        }
    }
}

/// A mesh hit is described from the BVH packet's copy of the triangle's vertices
/// (`Blas::hit_geometry`); the description must be the mesh's own, bit for bit, on a mesh with
/// vertex normals and uvs and triangles of every orientation.
#[test]
fn mesh_hits_are_described_as_the_mesh_describes_them() {
    use crate::accel::blas::Blas;
    use crate::accel::bvh::BvhOptions;
    use crate::shape::mesh::TriangleMesh;
    use crate::shape::{triangle, Shape};
    use fixtures::Rng;

    let mut rng = Rng::new(11);
    let nv = 600;
    let p: Vec<Vec3A> = (0..nv)
        .map(|_| rng.in_box(Vec3A::splat(-1.0), Vec3A::splat(1.0)))
        .collect();
    let tris: Vec<[u32; 3]> = (0..nv as u32 / 3)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    let face_n = tris
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|k| p[k as usize]);
            (a - c).cross(b - c).normalize()
        })
        .collect();
    let mesh = TriangleMesh {
        n: Some((0..nv).map(|_| rng.direction()).collect()),
        uv: Some((0..nv).map(|_| Vec2::new(rng.f32(), rng.f32())).collect()),
        cols: None,
        alphas: None,
        p,
        tris,
        face_n,
        flip: false,
    };
    let blas = Blas::build(
        vec![Shape::Mesh(mesh.clone())],
        vec![7],
        BvhOptions::default(),
    );
    let mut hits = 0;
    for _ in 0..2000 {
        let o = rng.in_box(Vec3A::splat(-2.0), Vec3A::splat(2.0));
        let d = rng.direction();
        let Some(h) = blas.closest(o, d, f32::INFINITY) else {
            continue;
        };
        let (g, prim) = blas.hit_geometry(h, o, d, f32::INFINITY).unwrap();
        assert_eq!(prim, 7);
        // The triangle hit: the one the scalar test finds at the same distance.
        let i = (0..mesh.tris.len())
            .find(|&i| {
                triangle::intersect(&mesh.vertices(i), o, d, f32::INFINITY)
                    .is_some_and(|t| t.t == h.t)
            })
            .expect("the hit triangle");
        let m = mesh.geometry(i, h.b.to_array());
        assert_eq!(
            (g.p, g.p_error, g.n, g.ns, g.uv, g.dpdu, g.dpdv, g.hit.face),
            (m.p, m.p_error, m.n, m.ns, m.uv, m.dpdu, m.dpdv, m.hit.face),
            "triangle {i}"
        );
        hits += 1;
    }
    assert!(hits > 300, "{hits} hits");
}
