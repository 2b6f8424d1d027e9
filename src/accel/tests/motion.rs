//! Moving world shapes and instances: hits at the ray's time, agreement with the static
//! path, the motion bound (no missed hits while rotating) and area sampling that follows the
//! shape.

use super::*;
use crate::geometry::motion::MotionTransform;
use glam::{DAffine3, DQuat};

fn keyed(a: DMat4, b: DMat4) -> Xform {
    Xform {
        keys: vec![(0.0, a), (1.0, b)],
    }
}

fn timed(o: [f32; 3], d: [f32; 3], time: f32) -> Ray {
    Ray {
        o: Vec3A::from_array(o),
        d: Vec3A::from_array(d),
        t_max: f32::INFINITY,
        time,
    }
}

fn ball_object() -> ObjectDesc {
    ObjectDesc {
        name: "ball".into(),
        shapes: vec![
            sphere(vec![("radius", floats(&[0.5]))], false),
            quad(DMat4::from_translation(DVec3::new(2.0, 0.0, 0.0)), false),
        ],
        loc: Default::default(),
    }
}

#[test]
fn a_moving_sphere_is_hit_where_it_is_at_the_ray_time() {
    let mut b = GeometryBuilder::new();
    let m = keyed(
        DMat4::from_translation(DVec3::new(-2.0, 0.0, 0.0)),
        DMat4::from_translation(DVec3::new(2.0, 0.0, 0.0)),
    );
    let mut s = sphere(vec![("radius", floats(&[0.5]))], false);
    s.object_to_world = m;
    b.add_shape(&s, 3, &ShapeCtx::default()).unwrap();
    let g = b.build();
    for i in 0..=20 {
        let time = i as f32 / 20.0;
        let x = -2.0 + 4.0 * time;
        let si = g
            .intersect(&timed([x, 0.0, 5.0], [0.0, 0.0, -1.0], time))
            .expect("hit at the sphere's place");
        assert!((si.t - 4.5).abs() < 1e-5 && si.prim == 3, "t {}", si.t);
        assert!(close(si.it.n, Vec3A::Z, 1e-5) && si.it.time == time);
        assert!(close(si.it.p, Vec3A::new(x, 0.0, 0.5), 1e-5));
        assert!(g.intersect_p(&timed([x, 0.0, 5.0], [0.0, 0.0, -1.0], time)));
        // Where the sphere was at the other end of the shutter: nothing now (unless there).
        let other = -x;
        if (other - x).abs() > 1.5 {
            assert!(g
                .intersect(&timed([other, 0.0, 5.0], [0.0, 0.0, -1.0], time))
                .is_none());
            assert!(!g.intersect_p(&timed([other, 0.0, 5.0], [0.0, 0.0, -1.0], time)));
        }
    }
    // Before the first key and after the last, the end keys hold.
    assert!(g
        .intersect(&timed([-2.0, 0.0, 5.0], [0.0, 0.0, -1.0], -1.0))
        .is_some());
    assert!(g
        .intersect(&timed([2.0, 0.0, 5.0], [0.0, 0.0, -1.0], 3.0))
        .is_some());
    let (lo, hi) = g.bounds();
    assert!(lo.x <= -2.5 && hi.x >= 2.5 && lo.y <= -0.5 && hi.y >= 0.5);
}

/// The moving path with a motion that does not move gives what the static path gives.
#[test]
fn constant_motion_matches_the_static_instance() {
    let place = DMat4::from_scale_rotation_translation(
        DVec3::new(1.5, 1.5, 1.5),
        DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.7),
        DVec3::new(0.3, -0.2, 0.1),
    );
    let build = |moving: bool| {
        let mut b = GeometryBuilder::new();
        let id = b
            .add_object(&ball_object(), &[1, 2], &ShapeCtx::default())
            .unwrap();
        if moving {
            let a = DAffine3::from_mat4(place);
            b.moving.push(MovingInstance {
                object: id.0,
                motion: MotionTransform::new(&[(0.0, a), (1.0, a)]).unwrap(),
            });
        } else {
            b.add_instance(id, &Xform::fixed(place));
        }
        b.build()
    };
    let (fixed, moving) = (build(false), build(true));
    let mut rng = fixtures::Rng::new(5);
    let mut hits = 0;
    for _ in 0..2000 {
        let o = [rng.f32() * 8.0 - 4.0, rng.f32() * 8.0 - 4.0, 6.0];
        let target = [rng.f32() * 6.0 - 2.0, rng.f32() * 4.0 - 2.0, 0.0];
        let d = [target[0] - o[0], target[1] - o[1], target[2] - o[2]];
        let r = timed(o, d, rng.f32());
        let (a, b) = (fixed.intersect(&r), moving.intersect(&r));
        assert_eq!(a.is_some(), b.is_some(), "{r:?}");
        assert_eq!(fixed.intersect_p(&r), moving.intersect_p(&r));
        if let (Some(a), Some(b)) = (a, b) {
            hits += 1;
            assert_eq!(a.prim, b.prim);
            assert!(
                (a.t - b.t).abs() <= 1e-5 * a.t.max(1.0),
                "{} vs {}",
                a.t,
                b.t
            );
            assert!(close(a.it.n, b.it.n, 1e-5) && close(a.it.p, b.it.p, 1e-4));
        }
    }
    assert!(hits > 300, "{hits} hits");
}

/// A rotating instance is hit exactly where the same object placed statically at the ray's
/// time is hit: the motion bound misses nothing, half a turn and more.
#[test]
fn a_rotating_instance_misses_nothing() {
    let motion = Xform {
        keys: vec![
            (0.0, DMat4::from_translation(DVec3::new(0.0, 1.0, 0.0))),
            (
                0.5,
                DMat4::from_rotation_translation(
                    DQuat::from_rotation_z(2.5),
                    DVec3::new(1.0, 0.0, 0.0),
                ),
            ),
            (1.0, DMat4::from_rotation_z(-2.0)),
        ],
    };
    let mut b = GeometryBuilder::new();
    let id = b
        .add_object(&ball_object(), &[1, 2], &ShapeCtx::default())
        .unwrap();
    b.add_instance(id, &motion);
    let g = b.build();
    let m = MotionTransform::from_matrices(&motion.keys).unwrap();
    let mut rng = fixtures::Rng::new(9);
    let mut hits = 0;
    for i in 0..3000 {
        let time = (i % 60) as f32 / 59.0;
        let mut sb = GeometryBuilder::new();
        let sid = sb
            .add_object(&ball_object(), &[1, 2], &ShapeCtx::default())
            .unwrap();
        sb.add_instance(sid, &Xform::fixed(DMat4::from(m.at(time))));
        let fixed = sb.build();
        let o = [rng.f32() * 8.0 - 4.0, rng.f32() * 8.0 - 4.0, 3.0];
        let target = [rng.f32() * 8.0 - 4.0, rng.f32() * 8.0 - 4.0, -1.0];
        let d = [target[0] - o[0], target[1] - o[1], target[2] - o[2]];
        let r = timed(o, d, time);
        let (a, b) = (fixed.intersect(&r), g.intersect(&r));
        assert_eq!(a.is_some(), b.is_some(), "time {time}: {r:?}");
        assert_eq!(fixed.intersect_p(&r), g.intersect_p(&r));
        if let (Some(a), Some(b)) = (a, b) {
            hits += 1;
            assert_eq!(a.prim, b.prim);
            assert!((a.t - b.t).abs() <= 1e-4 * a.t.max(1.0));
        }
    }
    assert!(hits > 200, "{hits} hits");
}

#[test]
fn a_moving_emitter_is_sampled_where_it_is() {
    let mut b = GeometryBuilder::new();
    // A quad of area 4 turning about x and sliding along y: rigid, so its area holds.
    let mut q = quad(DMat4::IDENTITY, false);
    q.object_to_world = keyed(
        DMat4::IDENTITY,
        DMat4::from_rotation_translation(DQuat::from_rotation_x(1.0), DVec3::new(0.0, 3.0, 0.0)),
    );
    let id = b.add_shape(&q, 0, &ShapeCtx::default()).unwrap();
    let mut g = b.build();
    assert!((g.prepare_sampling(id) - 4.0).abs() < 1e-5);
    assert!((g.area(id) - 4.0).abs() < 1e-5);
    let m = MotionTransform::from_matrices(&q.object_to_world.keys).unwrap();
    let mut rng = fixtures::Rng::new(4);
    for _ in 0..200 {
        let time = rng.f32();
        let (it, _, pdf) = g.sample(id, Vec2::new(rng.f32(), rng.f32()), rng.f32(), time);
        assert!((pdf - 0.25).abs() < 1e-6 && it.time == time);
        // Back in the quad's own space the point is on the quad and the normal is +z.
        let a = m.at(time);
        let local = a.inverse().transform_point3(to_f64(it.p));
        assert!(local.z.abs() < 1e-5 && local.x.abs() <= 1.0 + 1e-5 && local.y.abs() <= 1.0 + 1e-5);
        let n = a.transform_vector3(DVec3::Z);
        assert!((to_f64(it.n) - n).length() < 1e-5);
    }
}
