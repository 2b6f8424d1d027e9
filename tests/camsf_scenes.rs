//! Cameras, samplers and pixel filters built from every real scene in ../shared/scenes, and
//! the cornell camera checked against LuxCore's reference render.

use glam::Vec2;
use luxfarm::camera::{Camera, CameraSample, FilmGeometry};
use luxfarm::filter::Filter;
use luxfarm::lxs::{self, ParseOptions, SceneDescription};
use luxfarm::sampler::Sampler;

mod common;

use common::{all_scenes, shared};

/// The film geometry a scene asks for (LuxRender defaults 800x600, no crop).
fn film_geometry(desc: &SceneDescription) -> FilmGeometry {
    let film = desc.film.as_ref();
    let int = |name: &str, default: i32| {
        film.and_then(|f| f.params.int(name))
            .unwrap_or(default)
            .max(1) as u32
    };
    let mut g = FilmGeometry::new(int("xresolution", 800), int("yresolution", 600));
    if let Some([a, b, c, d]) = film.and_then(|f| f.params.floats("cropwindow")) {
        g.crop = [*a, *b, *c, *d];
    }
    g
}

#[test]
fn every_scene_builds_its_camera_sampler_and_filter() {
    let scenes = all_scenes(&shared().join("scenes"));
    let mut built = 0;
    for path in &scenes {
        // Scenes that do not parse are the parser's tests' business.
        let Ok(desc) = lxs::parse_file(path, &ParseOptions::default()) else {
            continue;
        };
        let Some(cam_desc) = desc.camera.as_ref() else {
            continue;
        };
        let geo = film_geometry(&desc);
        let cam = Camera::build(cam_desc, &geo, &mut Vec::new())
            .unwrap_or_else(|e| panic!("{}: camera: {e}", path.display()));
        let sampler = Sampler::build(desc.sampler.as_ref(), &mut Vec::new())
            .unwrap_or_else(|e| panic!("{}: sampler: {e}", path.display()));
        let filter = Filter::build(desc.pixel_filter.as_ref(), &mut Vec::new())
            .unwrap_or_else(|e| panic!("{}: filter: {e}", path.display()));
        assert!(sampler.pixel_samples() >= 1);
        let [x0, x1, y0, y1] = geo.pixel_bounds();
        for (px, py) in [(x0, y0), (x1 - 1, y1 - 1), ((x0 + x1) / 2, (y0 + y1) / 2)] {
            let mut st = sampler.start(1, 0, px, py, 0);
            let cs = st.camera_sample();
            let (ray, w) = cam
                .generate_ray(&cs)
                .unwrap_or_else(|| panic!("{}: no ray at {px},{py}", path.display()));
            assert!(ray.o.is_finite() && ray.d.is_finite() && w == 1.0);
            assert!((ray.d.length() - 1.0).abs() < 1e-4);
            let mut sum = 0.0;
            filter.splat(cs.p_film, |_, _, wt| sum += wt);
            assert!(
                (sum - 1.0).abs() < 1e-4,
                "{}: splat sum {sum}",
                path.display()
            );
        }
        built += 1;
    }
    assert!(built >= 10, "only {built} scenes built");
}

#[test]
fn parsed_cornell_camera_sees_red_on_the_left() {
    let path = shared().join("scenes/cornell/cornell-mesh.lxs");
    let desc = lxs::parse_file(&path, &ParseOptions::default()).expect("cornell parses");
    let geo = film_geometry(&desc);
    assert_eq!((geo.xres, geo.yres), (256, 256));
    let cam = Camera::build(desc.camera.as_ref().expect("camera"), &geo, &mut Vec::new())
        .expect("camera");
    // Where the ray through the middle of a column meets the back wall plane y = 1.
    let wall_x = |x: f32| {
        let s = CameraSample {
            p_film: Vec2::new(x, 128.0),
            p_lens: Vec2::splat(0.5),
            time: 0.0,
        };
        let (r, _) = cam.generate_ray(&s).expect("ray");
        r.at((1.0 - r.o.y) / r.d.y).x
    };
    // The red wall is at x = -1 and LuxCore's reference shows it on the left.
    assert!(wall_x(16.0) < -1.0);
    assert!(wall_x(240.0) > 1.0);
    assert!(wall_x(128.0).abs() < 0.01);
    // The cornell scene asks for a box filter and 1 random sample per pixel.
    let f = Filter::build(desc.pixel_filter.as_ref(), &mut Vec::new()).unwrap();
    assert_eq!(f.radius(), Vec2::splat(0.5));
    let s = Sampler::build(desc.sampler.as_ref(), &mut Vec::new()).unwrap();
    assert_eq!(s.pixel_samples(), 1);
}
