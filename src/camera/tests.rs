//! Unit tests of the cameras: projection, orientation, lens, clipping, crop, autofocus.

use super::*;
use crate::lxs::{CameraDesc, Entity, Loc, ParamSet, ParamValue, Xform};
use glam::{DMat4, DVec3, DVec4, Vec3};

/// LuxRender's `LookAt` (right = dir x up): the world-to-camera matrix.
fn look_at(eye: [f64; 3], target: [f64; 3], up: [f64; 3]) -> DMat4 {
    let (eye, target, up) = (DVec3::from(eye), DVec3::from(target), DVec3::from(up));
    let dir = (target - eye).normalize();
    let right = dir.cross(up).normalize();
    let new_up = right.cross(dir);
    let cam_to_world = DMat4::from_cols(
        right.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        DVec4::new(eye.x, eye.y, eye.z, 1.0),
    );
    cam_to_world.inverse()
}

fn desc(kind: &str, params: &[(&str, ParamValue)], w2c: DMat4) -> CameraDesc {
    let mut ps = ParamSet::new();
    for (n, v) in params {
        ps.add(n, v.clone());
    }
    CameraDesc {
        entity: Entity {
            kind: kind.to_string(),
            params: ps,
            loc: Loc {
                file: "cam.lxs".into(),
                line: 2,
                col: 1,
            },
        },
        world_to_camera: Xform::fixed(w2c),
        exterior: None,
    }
}

fn f(v: f32) -> ParamValue {
    ParamValue::Float(vec![v])
}

fn camera(kind: &str, params: &[(&str, ParamValue)], w2c: DMat4, xres: u32, yres: u32) -> Camera {
    Camera::build(
        &desc(kind, params, w2c),
        &FilmGeometry::new(xres, yres),
        &mut Vec::new(),
    )
    .expect("valid camera")
}

fn ray_at(cam: &Camera, x: f32, y: f32) -> Ray {
    let s = CameraSample {
        p_film: Vec2::new(x, y),
        p_lens: Vec2::splat(0.5),
        time: 0.0,
    };
    let (r, w) = cam.generate_ray(&s).expect("ray");
    assert_eq!(w, 1.0);
    assert!((r.d.length() - 1.0).abs() < 1e-5);
    r
}

fn angle_deg(a: Vec3A, b: Vec3A) -> f32 {
    a.normalize()
        .dot(b.normalize())
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}

#[test]
fn fov_spans_the_shorter_axis() {
    let t = 30f32.to_radians().tan();
    // Landscape: fov is vertical.
    let cam = camera(
        "perspective",
        &[("fov", f(60.0))],
        DMat4::IDENTITY,
        200,
        100,
    );
    assert!((angle_deg(ray_at(&cam, 100.0, 0.0).d, Vec3A::Z) - 30.0).abs() < 1e-3);
    let wide = (2.0 * t).atan().to_degrees();
    assert!((angle_deg(ray_at(&cam, 0.0, 50.0).d, Vec3A::Z) - wide).abs() < 1e-3);
    let corner = (5f32.sqrt() * t).atan().to_degrees();
    for (x, y) in [(0.0, 0.0), (200.0, 0.0), (0.0, 100.0), (200.0, 100.0)] {
        assert!((angle_deg(ray_at(&cam, x, y).d, Vec3A::Z) - corner).abs() < 1e-3);
    }
    // Portrait: fov is horizontal.
    let cam = camera(
        "perspective",
        &[("fov", f(60.0))],
        DMat4::IDENTITY,
        100,
        200,
    );
    assert!((angle_deg(ray_at(&cam, 0.0, 100.0).d, Vec3A::Z) - 30.0).abs() < 1e-3);
    assert!((angle_deg(ray_at(&cam, 50.0, 0.0).d, Vec3A::Z) - wide).abs() < 1e-3);
    // The default fov is 90 degrees.
    let cam = camera("perspective", &[], DMat4::IDENTITY, 64, 64);
    assert!((angle_deg(ray_at(&cam, 64.0, 32.0).d, Vec3A::Z) - 45.0).abs() < 1e-3);
}

#[test]
fn image_is_not_mirrored() {
    // Camera at y = -10 looking at the origin, z up: world +x is to the camera's right.
    let w2c = look_at([0.0, -10.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
    for kind in ["perspective", "orthographic"] {
        let cam = camera(kind, &[], w2c, 100, 80);
        let centre = ray_at(&cam, 50.0, 40.0);
        assert!(centre.d.y > 0.99, "{kind} looks along +y");
        let right = ray_at(&cam, 90.0, 40.0);
        let left = ray_at(&cam, 10.0, 40.0);
        let top = ray_at(&cam, 50.0, 5.0);
        let bottom = ray_at(&cam, 50.0, 75.0);
        let x = |r: &Ray| r.at(10.0).x;
        let z = |r: &Ray| r.at(10.0).z;
        assert!(
            x(&right) > 0.5 && x(&left) < -0.5,
            "{kind}: right of image is world +x"
        );
        assert!(
            z(&top) > 0.5 && z(&bottom) < -0.5,
            "{kind}: top of image is world up"
        );
    }
}

#[test]
fn screenwindow_maps_the_raster() {
    let sw = ParamValue::Float(vec![0.0, 1.0, 0.0, 1.0]);
    let cam = camera(
        "perspective",
        &[("screenwindow", sw.clone())],
        DMat4::IDENTITY,
        50,
        50,
    );
    // Raster (0, 0) is screen (xmin, ymax) = (0, 1); raster (xres, yres) is (1, 0).
    let r = ray_at(&cam, 0.0, 0.0);
    assert!((r.d - Vec3A::new(0.0, 1.0, 1.0).normalize()).length() < 1e-5);
    let r = ray_at(&cam, 50.0, 50.0);
    assert!((r.d - Vec3A::new(1.0, 0.0, 1.0).normalize()).length() < 1e-5);
    let ortho = camera(
        "orthographic",
        &[("screenwindow", sw)],
        DMat4::IDENTITY,
        50,
        50,
    );
    let r = ray_at(&ortho, 25.0, 12.5);
    assert!((r.o - Vec3A::new(0.5, 0.75, 1e-3)).length() < 1e-5);
    // frameaspectratio overrides the film's.
    let cam = camera(
        "orthographic",
        &[("frameaspectratio", f(2.0))],
        DMat4::IDENTITY,
        50,
        50,
    );
    assert!((ray_at(&cam, 0.0, 0.0).o.x + 2.0).abs() < 1e-5);
}

#[test]
fn cropwindow_selects_pixels_but_not_rays() {
    let mut geo = FilmGeometry::new(100, 80);
    assert_eq!(geo.pixel_bounds(), [0, 100, 0, 80]);
    geo.crop = [0.25, 0.75, 0.5, 0.1];
    assert_eq!(geo.pixel_bounds(), [25, 75, 8, 40]);
    geo.crop = [0.5, 0.5, 0.0, 1.0];
    assert_eq!(geo.pixel_bounds(), [50, 51, 0, 80]);
    let d = desc("perspective", &[("fov", f(40.0))], DMat4::IDENTITY);
    let full = Camera::build(&d, &FilmGeometry::new(100, 80), &mut Vec::new()).unwrap();
    let cropped = Camera::build(&d, &geo, &mut Vec::new()).unwrap();
    assert_eq!(ray_at(&full, 60.0, 30.0), ray_at(&cropped, 60.0, 30.0));
}

#[test]
fn clipping_planes() {
    let cam = camera(
        "perspective",
        &[("hither", f(0.5)), ("yon", f(20.0))],
        DMat4::IDENTITY,
        40,
        40,
    );
    for (x, y) in [(20.0, 20.0), (0.0, 0.0), (33.0, 7.0)] {
        let r = ray_at(&cam, x, y);
        assert!((r.o.z - 0.5).abs() < 1e-5);
        assert!((r.at(r.t_max).z - 20.0).abs() < 1e-3);
    }
    // hither has a floor of 1e-4, as in LuxRender.
    let cam = camera("perspective", &[("hither", f(0.0))], DMat4::IDENTITY, 4, 4);
    assert!((cam.hither - 1e-4).abs() < 1e-9);
}

#[test]
fn thin_lens_rays_converge_on_the_focal_plane() {
    let w2c = look_at([1.0, 2.0, 3.0], [4.0, -2.0, 1.0], [0.0, 0.0, 1.0]);
    let c2w = w2c.inverse();
    let params = [
        ("lensradius", f(0.3)),
        ("focaldistance", f(6.0)),
        ("fov", f(50.0)),
    ];
    for blades in [0, 6] {
        let mut ps = params.to_vec();
        ps.push(("blades", ParamValue::Integer(vec![blades])));
        let cam = camera("perspective", &ps, w2c, 64, 48);
        let mut focus = Vec::new();
        let mut origins = Vec::new();
        for i in 0..16 {
            let s = CameraSample {
                p_film: Vec2::new(40.3, 10.7),
                p_lens: Vec2::new((i % 4) as f32 / 4.0 + 0.1, (i / 4) as f32 / 4.0 + 0.1),
                time: 0.0,
            };
            let (r, _) = cam.generate_ray(&s).unwrap();
            // Point where the ray crosses camera-space z = 6.
            let o = w2c.transform_point3(DVec3::new(r.o.x as f64, r.o.y as f64, r.o.z as f64));
            let d = w2c.transform_vector3(DVec3::new(r.d.x as f64, r.d.y as f64, r.d.z as f64));
            let p = o + d * ((6.0 - o.z) / d.z);
            focus.push(c2w.transform_point3(p));
            origins.push(o);
        }
        for p in &focus {
            assert!(
                (*p - focus[0]).length() < 1e-4,
                "blades {blades}: {p} vs {}",
                focus[0]
            );
        }
        let spread = origins
            .iter()
            .map(|o| (*o - origins[0]).length())
            .fold(0.0, f64::max);
        assert!(spread > 0.1 && spread <= 0.6 + 1e-6, "lens spread {spread}");
    }
}

#[test]
fn lens_with_default_focal_distance_gives_finite_rays() {
    // A lens radius without focaldistance (default 1e30) appears in exported scenes.
    for kind in ["perspective", "orthographic"] {
        let cam = camera(kind, &[("lensradius", f(0.01))], DMat4::IDENTITY, 32, 32);
        for (x, y) in [(0.0, 0.0), (16.0, 16.0), (31.9, 3.0)] {
            let s = CameraSample {
                p_film: Vec2::new(x, y),
                p_lens: Vec2::new(0.9, 0.2),
                time: 0.0,
            };
            let (r, _) = cam.generate_ray(&s).expect("finite ray");
            assert!(r.o.is_finite() && r.d.is_finite(), "{kind}");
            assert!((r.d.length() - 1.0).abs() < 1e-5);
        }
    }
}

#[test]
fn orthographic_rays_are_parallel() {
    let cam = camera("orthographic", &[], DMat4::IDENTITY, 100, 100);
    let r = ray_at(&cam, 0.0, 0.0);
    assert!((r.o - Vec3A::new(-1.0, 1.0, 1e-3)).length() < 1e-5);
    assert!((r.d - Vec3A::Z).length() < 1e-6);
    let r = ray_at(&cam, 50.0, 50.0);
    assert!((r.o - Vec3A::new(0.0, 0.0, 1e-3)).length() < 1e-5);
    let lens = camera(
        "orthographic",
        &[("lensradius", f(0.2)), ("focaldistance", f(3.0))],
        DMat4::IDENTITY,
        100,
        100,
    );
    let mut hits = Vec::new();
    for u in [0.1, 0.5, 0.9] {
        let s = CameraSample {
            p_film: Vec2::new(75.0, 25.0),
            p_lens: Vec2::new(u, 1.0 - u * 0.7),
            time: 0.0,
        };
        let (r, _) = lens.generate_ray(&s).unwrap();
        hits.push(r.at((3.0 - r.o.z) / r.d.z));
    }
    for h in &hits {
        assert!((*h - Vec3A::new(0.5, 0.5, 3.0)).length() < 1e-4, "{h}");
    }
}

#[test]
fn environment_latlong_mapping() {
    let cam = camera("environment", &[], DMat4::IDENTITY, 200, 100);
    let dir = |x: f32, y: f32| ray_at(&cam, x, y).d;
    assert!(
        (dir(100.0, 50.0) - Vec3A::Z).length() < 1e-5,
        "centre looks forward"
    );
    assert!(
        (dir(50.0, 50.0) - Vec3A::NEG_X).length() < 1e-5,
        "quarter width looks left"
    );
    assert!(
        (dir(150.0, 50.0) - Vec3A::X).length() < 1e-5,
        "three quarters look right"
    );
    assert!(
        (dir(0.0, 50.0) - Vec3A::NEG_Z).length() < 1e-5,
        "edges look back"
    );
    assert!(
        (dir(37.0, 0.0) - Vec3A::Y).length() < 1e-5,
        "top row looks up"
    );
    assert!(
        (dir(37.0, 100.0) - Vec3A::NEG_Y).length() < 1e-5,
        "bottom row looks down"
    );
    // Placed with LookAt: the centre looks at the target, the top at world up.
    let w2c = look_at([0.0, 0.0, 1.0], [5.0, 0.0, 1.0], [0.0, 0.0, 1.0]);
    let cam = camera("environment", &[], w2c, 200, 100);
    let r = ray_at(&cam, 100.0, 50.0);
    assert!((r.d - Vec3A::X).length() < 1e-5);
    assert!((r.o - Vec3A::new(1e-3, 0.0, 1.0)).length() < 1e-5);
    assert!((ray_at(&cam, 3.0, 0.0).d - Vec3A::Z).length() < 1e-5);
    // Right of the panorama centre is the camera's right (world -y when looking along +x).
    assert!((ray_at(&cam, 150.0, 50.0).d - Vec3A::NEG_Y).length() < 1e-5);
}

#[test]
fn autofocus_traces_the_centre_ray() {
    let w2c = look_at([0.0, -10.0, 2.0], [0.0, 0.0, 2.0], [0.0, 0.0, 1.0]);
    let params = [
        ("autofocus", ParamValue::Bool(vec![true])),
        ("lensradius", f(0.1)),
    ];
    let mut cam = camera("perspective", &params, w2c, 64, 64);
    assert!(cam.needs_autofocus());
    assert_eq!(cam.focal_distance(), Some(1e30));
    // A wall at world y = 3, i.e. 13 units in front of the camera.
    let wall = |r: &Ray| (r.d.y > 0.0).then(|| (3.0 - r.o.y) / r.d.y);
    let fd = cam.autofocus(wall).unwrap();
    assert!((fd - 13.0).abs() < 1e-3, "{fd}");
    // Nothing hit: focal distance kept.
    let mut cam2 = camera("orthographic", &params, w2c, 64, 64);
    assert_eq!(cam2.autofocus(|_| None), Some(1e30));
    assert!((cam2.autofocus(wall).unwrap() - 13.0).abs() < 1e-3);
    // Without the parameter autofocus does nothing.
    let mut plain = camera("perspective", &[], w2c, 64, 64);
    assert!(!plain.needs_autofocus());
    assert_eq!(plain.autofocus(wall), Some(1e30));
}

/// A fixed camera transforms its rays in f32: they match the f64 transform (which moving
/// cameras use) within a few ulps of the origin's coordinates and 1e-6 in direction, at
/// every scene scale, for all three camera kinds.
#[test]
fn fixed_camera_rays_in_f32_match_the_f64_transform() {
    for scale in [1e-4, 1.0, 1e5] {
        let w2c = look_at(
            [3.0 * scale, -4.0 * scale, 2.0 * scale],
            [0.5 * scale, 0.2 * scale, 0.1 * scale],
            [0.0, 0.0, 1.0],
        );
        let lens = [("lensradius", f(0.01)), ("focaldistance", f(2.0))];
        for (kind, params) in [
            ("perspective", &lens[..]),
            ("orthographic", &[][..]),
            ("environment", &[][..]),
        ] {
            let fast = camera(kind, params, w2c, 64, 48);
            assert!(fast.fixed.is_some());
            let exact = Camera {
                fixed: None,
                ..fast.clone()
            };
            for (x, y) in [(0.0, 0.0), (31.5, 20.25), (63.9, 47.9), (10.0, 40.0)] {
                let (a, b) = (ray_at(&fast, x, y), ray_at(&exact, x, y));
                let ulp = b.o.abs().max_element().max(f32::MIN_POSITIVE) * f32::EPSILON;
                assert!(
                    (a.o - b.o).abs().max_element() <= 4.0 * ulp,
                    "{kind} {scale}: {a:?} {b:?}"
                );
                assert!(
                    (a.d - b.d).abs().max_element() <= 1e-6,
                    "{kind} {scale}: {a:?} {b:?}"
                );
                assert!(
                    (a.t_max - b.t_max).abs() <= 1e-5 * b.t_max,
                    "{kind} {scale}"
                );
            }
        }
    }
}

#[test]
fn animated_camera_moves_with_time() {
    let a = look_at([0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
    let b = look_at([2.0, 0.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
    let mut d = desc("perspective", &[], DMat4::IDENTITY);
    d.world_to_camera = Xform {
        keys: vec![(0.0, a), (1.0, b)],
    };
    let cam = Camera::build(&d, &FilmGeometry::new(10, 10), &mut Vec::new()).unwrap();
    let at = |t: f32| {
        let s = CameraSample {
            p_film: Vec2::new(5.0, 5.0),
            p_lens: Vec2::ZERO,
            time: t,
        };
        cam.generate_ray(&s).unwrap().0
    };
    assert!(at(0.0).o.x.abs() < 1e-4);
    assert!((at(0.5).o.x - 1.0).abs() < 1e-4);
    assert!((at(1.0).o.x - 2.0).abs() < 1e-4);
    assert_eq!(at(0.25).time, 0.25);
}

#[test]
fn bad_cameras_are_errors_with_locations() {
    let g = FilmGeometry::new(10, 10);
    let e = Camera::build(&desc("fisheye", &[], DMat4::IDENTITY), &g, &mut Vec::new()).unwrap_err();
    assert!(
        e.to_string().starts_with("cam.lxs:2:1: unknown camera"),
        "{e}"
    );
    assert!(Camera::build(
        &desc("perspective", &[("fov", f(0.0))], DMat4::IDENTITY),
        &g,
        &mut Vec::new()
    )
    .is_err());
    assert!(Camera::build(
        &desc("perspective", &[("fov", f(180.0))], DMat4::IDENTITY),
        &g,
        &mut Vec::new()
    )
    .is_err());
    assert!(Camera::build(&desc("perspective", &[], DMat4::ZERO), &g, &mut Vec::new()).is_err());
    assert!(Camera::build(
        &desc(
            "perspective",
            &[],
            DMat4::from_diagonal(DVec4::splat(f64::NAN))
        ),
        &g,
        &mut Vec::new()
    )
    .is_err());
    assert!(Camera::build(
        &desc("perspective", &[], DMat4::IDENTITY),
        &FilmGeometry::new(0, 10),
        &mut Vec::new()
    )
    .is_err());
    assert!(Camera::build(
        &desc("perspective", &[("lensradius", f(-1.0))], DMat4::IDENTITY),
        &g,
        &mut Vec::new()
    )
    .is_err());
    // Old exporters' "focaldistance" [0] without a lens is accepted; with a lens, the lens is
    // disabled rather than producing NaN rays.
    let old = camera(
        "perspective",
        &[("focaldistance", f(0.0))],
        DMat4::IDENTITY,
        10,
        10,
    );
    assert_eq!(old.focal_distance(), Some(1e30));
    let lens = camera(
        "perspective",
        &[("focaldistance", f(0.0)), ("lensradius", f(0.5))],
        DMat4::IDENTITY,
        10,
        10,
    );
    assert!(matches!(&lens.model, CameraModel::Perspective(p) if p.lens_radius == 0.0));
    let cam = camera("perspective", &[], DMat4::IDENTITY, 10, 10);
    let s = CameraSample {
        p_film: Vec2::new(f32::NAN, 1.0),
        p_lens: Vec2::ZERO,
        time: 0.0,
    };
    assert!(cam.generate_ray(&s).is_none());
}

#[test]
fn parameters_are_consumed() {
    let d = desc(
        "perspective",
        &[
            ("fov", f(35.0)),
            ("hither", f(0.01)),
            ("yon", f(100.0)),
            ("lensradius", f(0.01)),
            ("focaldistance", f(3.0)),
            ("shutteropen", f(0.0)),
            ("shutterclose", f(1.0)),
            (
                "screenwindow",
                ParamValue::Float(vec![-1.0, 1.0, -0.75, 0.75]),
            ),
            ("frameaspectratio", f(1.333)),
            ("autofocus", ParamValue::Bool(vec![false])),
        ],
        DMat4::IDENTITY,
    );
    Camera::build(&d, &FilmGeometry::new(40, 30), &mut Vec::new()).unwrap();
    let unused: Vec<_> = d.entity.params.unused().map(|p| p.name.clone()).collect();
    assert!(unused.is_empty(), "{unused:?}");
    let _ = Vec3::ZERO;
}

/// The shared test data directory (`../shared` from the repository root).
fn shared_dir() -> std::path::PathBuf {
    let local = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared"));
    if local.is_dir() {
        local.to_path_buf()
    } else {
        std::path::PathBuf::from("/work/shared")
    }
}

#[test]
fn orientation_matches_the_luxcore_reference_render() {
    // cornell-mesh.lxs: `LookAt 0 -3.9 1  0 0 1  0 0 1`, fov 39.3, 256x256; the red wall is
    // at x = -1, the green one at x = +1. LuxCore rendered it to luxcore-ref-2048.exr.
    let path = shared_dir().join("scenes/cornell/luxcore-ref-2048.exr");
    use exr::prelude::*;
    let image = read_first_rgba_layer_from_file(
        &path,
        |res, _| vec![vec![[0f32; 3]; res.width()]; res.height()],
        |px: &mut Vec<Vec<[f32; 3]>>, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            px[pos.y()][pos.x()] = [r, g, b]
        },
    )
    .unwrap_or_else(|e| panic!("reading {}: {e}", path.display()));
    let px = image.layer_data.channel_data.pixels;
    let (h, w) = (px.len(), px[0].len());
    assert_eq!((w, h), (256, 256));
    // Mean red-minus-green over a band of columns, middle rows.
    let band = |x0: usize, x1: usize| {
        let mut s = 0.0f64;
        for row in &px[h / 3..2 * h / 3] {
            for p in &row[x0..x1] {
                s += (p[0] - p[1]) as f64;
            }
        }
        s / ((x1 - x0) * (h / 3)) as f64
    };
    let (left, right) = (band(2, 30), band(w - 30, w - 2));
    assert!(
        left > 0.05 && right < -0.02,
        "reference: left {left}, right {right}"
    );
    // Our camera: the same pixels look at the same walls.
    let w2c = look_at([0.0, -3.9, 1.0], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0]);
    let cam = camera("perspective", &[("fov", f(39.3))], w2c, 256, 256);
    let wall_x = |x: f32| {
        let r = ray_at(&cam, x, 128.0);
        r.at((1.0 - r.o.y) / r.d.y).x // where the ray meets the back wall plane y = 1
    };
    assert!(
        wall_x(16.0) < -1.0,
        "left columns see the red wall (x < -1 at the back)"
    );
    assert!(wall_x(240.0) > 1.0, "right columns see the green wall");
}
