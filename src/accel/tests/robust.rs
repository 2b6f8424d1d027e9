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

#[test]
fn every_bvh_configuration_finds_the_same_hits() {
    let shapes = bench::cornell_like();
    let build = |opts| {
        let mut b = GeometryBuilder::with_options(opts);
        for (i, s) in shapes.iter().enumerate() {
            b.add_shape(s, i as u32, &ShapeCtx::default()).unwrap();
        }
        b.build()
    };
    let reference = build(bvh::BvhOptions::default());
    let (closest, any) = bench::incoherent_rays(&reference, 3000, 11);
    let expect: Vec<_> = closest
        .iter()
        .map(|r| reference.intersect(r).map(|s| (s.prim, s.t)))
        .collect();
    assert!(expect.iter().filter(|h| h.is_some()).count() > 2000);
    let expect_any: Vec<bool> = any.iter().map(|r| reference.intersect_p(r)).collect();
    for opts in bench::candidate_options() {
        let g = build(opts);
        for (r, e) in closest.iter().zip(&expect) {
            assert_eq!(g.intersect(r).map(|s| (s.prim, s.t)), *e, "{opts}");
        }
        for (r, e) in any.iter().zip(&expect_any) {
            assert_eq!(g.intersect_p(r), *e, "{opts}");
        }
    }
    // closest hits agree with any-hit queries along the same segment
    for (r, e) in closest.iter().zip(&expect) {
        if let Some((_, t)) = e {
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
