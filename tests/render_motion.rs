//! Motion blur of shapes and object instances, end to end (issue 16, Build 4).
//!
//! Only the relative motion of camera and object is seen: a sphere moving from x = -a to +a
//! under a still camera renders the blur of a still sphere under a camera moving from +a to
//! -a (lit by a distant and a constant infinite light, which do not care where things are).
//! A whole scene, area light included, moving with the camera renders as the still scene (the
//! light is sampled where it is at the sample's time). Two identical keys render as no motion;
//! a moving instance's streak covers exactly the pixels between its end positions, with the
//! brightness the time average predicts; a rotating instance seen at a fixed shutter time
//! renders as the object placed there statically (the motion bound misses nothing). A point
//! light in an object instanced with motion moves with it (LuxRender's MotionLight); a light
//! written directly inside MotionBegin stays at its first key, as in LuxRender.
//!
//! Small films (debug builds), compared on block means of Y against the noise between two
//! streams of the same scene, or pixel by pixel with a stated tolerance.

mod render_util;

use glam::DMat4;
use luxfarm::film::Film;
use luxfarm::geometry::motion::MotionTransform;
use luxfarm::render::SessionOptions;
use render_util::*;
use std::path::Path;

const A: f64 = 1.5;
const R: f64 = 0.6;

fn film(text: &str, stream: u64) -> Film {
    let desc = parse_text(text, Path::new("/tmp/luxfarm-motion.lxs"));
    let opts = SessionOptions {
        threads: 2,
        seed: 5,
        stream,
    };
    render(&desc, Path::new("/tmp"), opts, 1)
}

/// An orthographic view down -z from z = 10 (image right = world +x), `w`×`h` pixels over
/// [-3.2, 3.2] × [-1.6, 1.6], and `camera_motion` before the Camera statement.
fn header(w: u32, h: u32, spp: u32, camera_motion: &str, shutter: (f64, f64)) -> String {
    format!(
        r#"LookAt 0 0 10  0 0 0  0 1 0
{camera_motion}
Camera "orthographic" "float screenwindow" [-3.2 3.2 -1.6 1.6]
  "float shutteropen" [{}] "float shutterclose" [{}]
Film "fleximage" "integer xresolution" [{w}] "integer yresolution" [{h}]
PixelFilter "box" "float xwidth" [0.5] "float ywidth" [0.5]
Sampler "random" "integer pixelsamples" [{spp}]
SurfaceIntegrator "path" "integer maxdepth" [2]
"#,
        shutter.0, shutter.1
    )
}

/// Keys `Translate from 0 0` at time 0 and `Translate to 0 0` at time 1.
fn slide(from: f64, to: f64) -> String {
    format!("MotionBegin [0 1]\nTranslate {from} 0 0\nTranslate {to} 0 0\nMotionEnd")
}

/// The sphere scene: a matte sphere of radius R at the origin under `shape_motion`, a
/// distant light from the camera's side and a dim constant environment.
fn sphere_scene(camera_motion: &str, shape_motion: &str, env: bool) -> String {
    let body = format!(
        "AttributeBegin\n{shape_motion}\nMaterial \"matte\" \"color Kd\" [0.7 0.7 0.7]\n\
         Shape \"sphere\" \"float radius\" [{R}]\nAttributeEnd"
    );
    lit_scene(camera_motion, &body, env)
}

/// `body` in the world of [`sphere_scene`].
fn lit_scene(camera_motion: &str, body: &str, env: bool) -> String {
    let env = if env {
        "LightSource \"infinite\" \"color L\" [0.2 0.2 0.2]"
    } else {
        ""
    };
    format!(
        r#"{}WorldBegin
LightSource "distant" "point from" [0.3 0.5 10] "point to" [0 0 0] "color L" [3 3 3]
{env}
{body}
WorldEnd
"#,
        header(64, 32, 16, camera_motion, (0.0, 1.0))
    )
}

/// Asserts that `other` matches `a` about as well as `a2` (same scene as `a`, another
/// stream) on 4×4 block means of Y.
fn films_within_noise(a: &Film, a2: &Film, other: &Film, what: &str) {
    let means = |f: &Film| block_means(f, 4);
    assert_within_noise(&means(a), &means(a2), &means(other), what);
}

#[test]
fn a_moving_sphere_blurs_as_a_camera_moving_the_other_way() {
    let moving = sphere_scene("", &slide(-A, A), true);
    // The camera is at eye - k for world-to-camera LookAt · Translate(k): keys k = -A then
    // +A put it at +A, then -A.
    let camera = sphere_scene(&slide(-A, A), "", true);
    let still = sphere_scene("", "", true);
    let (m, m2) = (film(&moving, 0), film(&moving, 1));
    films_within_noise(&m, &m2, &film(&camera, 2), "moving camera vs moving sphere");
    // The comparison can fail: the still sphere is far outside the noise.
    let (a, s) = (block_means(&m, 4), block_means(&film(&still, 2), 4));
    assert!(rmse(&a, &s) > 5.0 * rmse(&a, &block_means(&m2, 4)));
}

#[test]
fn two_identical_keys_render_as_no_motion() {
    let keyed = "MotionBegin [0 1]\nTranslate 0.5 0.2 0\nTranslate 0.5 0.2 0\nMotionEnd";
    let a = film(&sphere_scene("", keyed, true), 0);
    let b = film(&sphere_scene("", "Translate 0.5 0.2 0", true), 0);
    assert!(rms(&a, &b) < 1e-9, "rms {}", rms(&a, &b));
    // Same for an instance whose motion block holds one place twice.
    let inst = |placement: &str| {
        let body = format!(
            "ObjectBegin \"ball\"\nMaterial \"matte\" \"color Kd\" [0.7 0.7 0.7]\n\
             Shape \"sphere\" \"float radius\" [{R}]\nObjectEnd\n\
             AttributeBegin\n{placement}\nObjectInstance \"ball\"\nAttributeEnd"
        );
        lit_scene("", &body, false)
    };
    let a = film(&inst(keyed), 0);
    let b = film(&inst("Translate 0.5 0.2 0"), 0);
    assert!(normalized_xyz(&a).iter().any(|p| p[1] > 0.0));
    assert!(rms(&a, &b) < 1e-9, "rms {}", rms(&a, &b));
}

/// Y of the two middle rows, per column.
fn middle_row(f: &Film) -> Vec<f64> {
    let xyz = normalized_xyz(f);
    let (w, h) = (f.width() as usize, f.height() as usize);
    (0..w)
        .map(|x| 0.5 * (xyz[(h / 2 - 1) * w + x][1] + xyz[(h / 2) * w + x][1]))
        .collect()
}

#[test]
fn a_moving_instance_streaks_between_its_end_positions() {
    // An instance sliding from x = -0.5 to x = +2 (asymmetric, so a mirrored or reversed
    // motion would show), no environment: the background is black.
    let (x0, x1) = (-0.5, 2.0);
    let scene = |placement: &str| {
        format!(
            r#"{}WorldBegin
LightSource "distant" "point from" [0 0 10] "point to" [0 0 0] "color L" [3 3 3]
ObjectBegin "ball"
Material "matte" "color Kd" [0.7 0.7 0.7]
Shape "sphere" "float radius" [{R}]
ObjectEnd
AttributeBegin
{placement}
ObjectInstance "ball"
AttributeEnd
WorldEnd
"#,
            header(128, 8, 32, "", (0.0, 1.0))
        )
    };
    let moving = middle_row(&film(&scene(&slide(x0, x1)), 0));
    let still = middle_row(&film(&scene(""), 0));
    let px = 6.4 / 128.0;
    let centre = |i: usize| -3.2 + (i as f64 + 0.5) * px;
    for (i, y) in moving.iter().enumerate() {
        let x = centre(i);
        if x < x0 - R - px || x > x1 + R + px {
            assert_eq!(*y, 0.0, "column {i} (x = {x:.2}) is outside the streak");
        } else if x > x0 - R + 0.5 && x < x1 + R - 0.5 {
            // Covered for at least a fifth of the shutter: some of the 32 samples see it.
            assert!(*y > 0.0, "column {i} (x = {x:.2}) is inside the streak");
        }
    }
    // Where the whole motion passes (x0 + R < x < x1 - R), a point is covered for 2R/(x1-x0)
    // of the shutter; its time-averaged radiance over the sphere's equator (cos-weighted by
    // the frontal light) is π R / (2 (x1 - x0)) of the still sphere's centre.
    let mid = (0..moving.len())
        .filter(|&i| centre(i) > x0 + R + 0.1 && centre(i) < x1 - R - 0.1)
        .map(|i| moving[i])
        .collect::<Vec<_>>();
    assert!(!mid.is_empty());
    let mean = mid.iter().sum::<f64>() / mid.len() as f64;
    let peak = still.iter().cloned().fold(0.0, f64::max);
    let expected = std::f64::consts::PI * R / (2.0 * (x1 - x0)) * peak;
    assert!(
        (mean / expected - 1.0).abs() < 0.08,
        "streak {mean:.4} vs {expected:.4}"
    );
}

#[test]
fn a_rotating_instance_at_a_fixed_time_is_the_instance_placed_there() {
    // A bar reaching from x = 0.4 to 2.8 turning 160° about z over the shutter, seen with a
    // zero-length shutter at several times, against the bar placed by the interpolated
    // matrix (same samples, so the images agree to rounding).
    let keys = [
        (0.0f32, DMat4::from_rotation_z(0.0)),
        (1.0, DMat4::from_rotation_z(160f64.to_radians())),
    ];
    let motion = MotionTransform::from_matrices(&keys).expect("keys");
    let scene = |placement: &str, time: f64| {
        format!(
            r#"{}WorldBegin
LightSource "distant" "point from" [0 0 10] "point to" [0 0 0] "color L" [3 3 3]
ObjectBegin "bar"
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
  "point P" [0.4 -0.2 0  2.8 -0.2 0  2.8 0.2 0  0.4 0.2 0]
ObjectEnd
AttributeBegin
{placement}
ObjectInstance "bar"
AttributeEnd
WorldEnd
"#,
            header(64, 32, 4, "", (time, time))
        )
    };
    let animated = "MotionBegin [0 1]\nRotate 0 0 0 1\nRotate 160 0 0 1\nMotionEnd";
    for time in [0.0, 0.3, 0.55, 0.8, 1.0] {
        let m = DMat4::from(motion.at(time as f32)).to_cols_array();
        let matrix = m.map(|v| format!("{v:.12}")).join(" ");
        let a = film(&scene(animated, time), 0);
        let b = film(&scene(&format!("Transform [{matrix}]"), time), 0);
        let lit = normalized_xyz(&b).iter().filter(|p| p[1] > 0.0).count();
        assert!(lit > 20, "time {time}: the bar is in view ({lit} pixels)");
        let diff = normalized_xyz(&a)
            .iter()
            .zip(normalized_xyz(&b))
            .filter(|(p, q)| (p[1] - q[1]).abs() > 1e-4)
            .count();
        assert!(diff <= 2, "time {time}: {diff} pixels differ");
    }
}

#[test]
fn a_scene_moving_with_its_camera_renders_as_the_still_scene() {
    // A floor, a box lit by a small area light above it: all of it, light included, and the
    // camera slide by (1.5, 0, 0) over the shutter.
    let d = 1.5;
    let scene = |camera: &str, world: &str| {
        format!(
            r#"LookAt 0 -6 4  0 0 0.5  0 0 1
{camera}
Camera "perspective" "float fov" [40]
Film "fleximage" "integer xresolution" [32] "integer yresolution" [24]
PixelFilter "box" "float xwidth" [0.5] "float ywidth" [0.5]
Sampler "random" "integer pixelsamples" [16]
SurfaceIntegrator "path" "integer maxdepth" [2]
WorldBegin
AttributeBegin
{world}
AttributeBegin
Material "matte" "color Kd" [0.7 0.7 0.7]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point P" [-4 -4 0  4 -4 0  4 4 0  -4 4 0]
Shape "sphere" "float radius" [0.7]
AttributeEnd
AttributeBegin
Translate 0.5 0.3 2.5
AreaLightSource "area" "color L" [8 8 8]
Shape "trianglemesh" "integer indices" [0 2 1 0 3 2] "point P" [-0.5 -0.5 0  0.5 -0.5 0  0.5 0.5 0  -0.5 0.5 0]
AttributeEnd
AttributeEnd
WorldEnd
"#
        )
    };
    let still = scene("", "");
    let moving = scene(&slide(0.0, -d), &slide(0.0, d));
    let (a, a2) = (film(&still, 0), film(&still, 1));
    films_within_noise(&a, &a2, &film(&moving, 2), "scene moving with its camera");
    // The comparison can fail: the scene moving alone differs.
    let alone = film(&scene("", &slide(0.0, d)), 2);
    let (ba, ba2) = (block_means(&a, 4), block_means(&a2, 4));
    assert!(rmse(&ba, &block_means(&alone, 4)) > 3.0 * rmse(&ba, &ba2));
}

/// A floor and a ball under `world_motion`, lit by a point light defined in an object and
/// instanced under `light_placement` (LuxRender's way to move a light), seen by a camera under
/// `camera`; `direct` writes the light directly under `light_placement` instead.
fn point_light_scene(
    camera: &str,
    world_motion: &str,
    light_placement: &str,
    direct: bool,
) -> String {
    let lamp = r#"LightSource "point" "point from" [0.5 0.3 2.5] "color L" [8 8 8]"#;
    let light = if direct {
        format!("AttributeBegin\n{light_placement}\n{lamp}\nAttributeEnd")
    } else {
        format!(
            "ObjectBegin \"lamp\"\n{lamp}\nObjectEnd\n\
             AttributeBegin\n{light_placement}\nObjectInstance \"lamp\"\nAttributeEnd"
        )
    };
    format!(
        r#"LookAt 0 -6 4  0 0 0.5  0 0 1
{camera}
Camera "perspective" "float fov" [40]
Film "fleximage" "integer xresolution" [32] "integer yresolution" [24]
PixelFilter "box" "float xwidth" [0.5] "float ywidth" [0.5]
Sampler "random" "integer pixelsamples" [16]
SurfaceIntegrator "path" "integer maxdepth" [2]
WorldBegin
{light}
AttributeBegin
{world_motion}
Material "matte" "color Kd" [0.7 0.7 0.7]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point P" [-4 -4 0  4 -4 0  4 4 0  -4 4 0]
Shape "sphere" "float radius" [0.7]
AttributeEnd
WorldEnd
"#
    )
}

#[test]
fn a_point_light_in_a_moving_instance_moves_with_it() {
    // Floor, ball, light (instanced with motion) and camera all slide by 1.5 over the
    // shutter: the image is the still scene's, with the path tracer and with light subpaths
    // (bidirectional). The light moving alone changes it.
    let d = 1.5;
    for integrator in ["path", "bidirectional"] {
        let with = |s: String| {
            s.replace(
                r#"SurfaceIntegrator "path""#,
                &format!(r#"SurfaceIntegrator "{integrator}""#),
            )
        };
        let still = with(point_light_scene("", "", "", false));
        let moving = with(point_light_scene(
            &slide(0.0, -d),
            &slide(0.0, d),
            &slide(0.0, d),
            false,
        ));
        let (a, a2) = (film(&still, 0), film(&still, 1));
        let what = format!("{integrator}: scene and light moving with the camera");
        films_within_noise(&a, &a2, &film(&moving, 2), &what);
        let alone = film(&with(point_light_scene("", "", &slide(0.0, d), false)), 2);
        let (ba, ba2) = (block_means(&a, 4), block_means(&a2, 4));
        assert!(rmse(&ba, &block_means(&alone, 4)) > 3.0 * rmse(&ba, &ba2));
    }
}

#[test]
fn a_light_written_inside_motion_begin_stays_at_its_first_key() {
    // LuxRender gives a LightSource its static transform (the first key): only instancing
    // moves a light.
    let d = 1.5;
    let keyed = film(&point_light_scene("", "", &slide(0.0, d), true), 0);
    let first = film(&point_light_scene("", "", "", true), 0);
    assert!(normalized_xyz(&first).iter().any(|p| p[1] > 0.0));
    assert!(rms(&keyed, &first) < 1e-9, "rms {}", rms(&keyed, &first));
}

/// A turn about the vertical axis through the origin, from `from` to `to` degrees.
fn turn(from: f64, to: f64) -> String {
    format!("MotionBegin [0 1]\nRotate {from} 0 0 1\nRotate {to} 0 0 1\nMotionEnd")
}

/// The floor and ball of [`point_light_scene`] lit by `light` (a `LightSource` statement)
/// defined in an object and instanced under `placement`, rendered by `integrator`.
fn sky_scene(light: &str, placement: &str, integrator: &str) -> String {
    point_light_scene("", "", placement, false)
        .replace(
            r#"LightSource "point" "point from" [0.5 0.3 2.5] "color L" [8 8 8]"#,
            light,
        )
        .replace(
            r#"SurfaceIntegrator "path""#,
            &format!(r#"SurfaceIntegrator "{integrator}""#),
        )
}

#[test]
fn a_light_at_infinity_in_a_moving_instance_is_turned_by_it() {
    // LuxRender 1.x wraps every instanced light in a MotionLight: a sun, sky or distant light
    // defined in an object instanced with motion is turned by the instance at each ray's
    // time. Keys 70° and 70.001° apart render as the static instance turned by 70° (sampled
    // directions, their densities and the radiance of escaping rays all turned), with the
    // path tracer and with light subpaths; the first key alone (no turn) differs.
    let lights = [
        r#"LightSource "distant" "point from" [1.5 0.6 0.8] "point to" [0 0 0] "color L" [3 3 3]"#,
        r#"LightSource "sunsky" "vector sundir" [0.6 0.2 0.5] "float gain" [0.05]"#,
    ];
    for light in lights {
        for integrator in ["path", "bidirectional"] {
            let what = format!("{light} with {integrator}");
            let still = sky_scene(light, "Rotate 70 0 0 1", integrator);
            let (a, a2) = (film(&still, 0), film(&still, 1));
            let keyed = film(&sky_scene(light, &turn(70.0, 70.001), integrator), 2);
            films_within_noise(&a, &a2, &keyed, &format!("{what}: keys 70° and 70.001°"));
            let unturned = film(&sky_scene(light, "", integrator), 2);
            let (ba, ba2) = (block_means(&a, 4), block_means(&a2, 4));
            let apart = rmse(&ba, &block_means(&unturned, 4));
            assert!(
                apart > 3.0 * rmse(&ba, &ba2),
                "{what}: unturned {apart} noise {}",
                rmse(&ba, &ba2)
            );
        }
    }
}

/// The 4-pixel block means of `light`'s sky scene averaged over 12 static placements, the
/// placement at shutter fraction t (the middle of each twelfth) given by `placement(t)`: what a
/// light moving through those placements over the shutter should render as.
fn mean_of_held(light: &str, placement: impl Fn(f64) -> String) -> Vec<f64> {
    let n = 12;
    let held: Vec<Vec<f64>> = (0..n)
        .map(|k| {
            let at = placement((k as f64 + 0.5) / n as f64);
            block_means(&film(&sky_scene(light, &at, "path"), 2 + k as u64), 4)
        })
        .collect();
    (0..held[0].len())
        .map(|i| held.iter().map(|h| h[i]).sum::<f64>() / n as f64)
        .collect()
}

#[test]
fn a_light_turning_over_the_shutter_averages_its_directions() {
    // A soft distant light (theta 15°) turning from 0° to 60° over the shutter lights the
    // floor and ball as the mean of the light held at 12 angles across that turn.
    let light = r#"LightSource "distant" "point from" [1.5 0.6 0.8] "point to" [0 0 0] "color L" [3 3 3] "float theta" [15]"#;
    let turning = sky_scene(light, &turn(0.0, 60.0), "path");
    let (a, a2) = (film(&turning, 0), film(&turning, 1));
    let mean = mean_of_held(light, |t| format!("Rotate {} 0 0 1", 60.0 * t));
    let (ba, ba2) = (block_means(&a, 4), block_means(&a2, 4));
    assert_within_noise(&ba, &ba2, &mean, "turning light vs the mean of held angles");
    // The light held at its first key alone is far from it.
    let first = block_means(&film(&sky_scene(light, "", "path"), 2), 4);
    assert!(rmse(&ba, &first) > 3.0 * rmse(&ba, &ba2));
}

#[test]
fn an_area_primitive_in_a_moving_instance_moves_with_it() {
    // luxfarm's rectangle light (a shape of its own, not scene geometry) defined in an object
    // instanced with motion: keys 1.2 and 1.2001 apart render as the static instance moved
    // by 1.2, and sliding from 0 to 1.5 over the shutter renders as the mean of the lamp
    // held at 12 places along the way. The lamp at its first key alone differs from both.
    let light = r#"LightSource "rectangle" "point from" [0.5 0.3 2.5] "vector edgeu" [0 0.8 0] "vector edgev" [0.8 0 0] "color L" [4 4 4]"#;
    let still = sky_scene(light, "Translate 1.2 0 0", "path");
    let (a, a2) = (film(&still, 0), film(&still, 1));
    let keyed = film(&sky_scene(light, &slide(1.2, 1.2001), "path"), 2);
    films_within_noise(&a, &a2, &keyed, "rectangle: keys 1.2 and 1.2001");
    let (ba, ba2) = (block_means(&a, 4), block_means(&a2, 4));
    let unmoved = block_means(&film(&sky_scene(light, "", "path"), 2), 4);
    assert!(rmse(&ba, &unmoved) > 3.0 * rmse(&ba, &ba2));

    let sliding = sky_scene(light, &slide(0.0, 1.5), "path");
    let (s, s2) = (film(&sliding, 0), film(&sliding, 1));
    let mean = mean_of_held(light, |t| format!("Translate {} 0 0", 1.5 * t));
    let (bs, bs2) = (block_means(&s, 4), block_means(&s2, 4));
    assert_within_noise(
        &bs,
        &bs2,
        &mean,
        "sliding rectangle vs the mean of held places",
    );
    assert!(rmse(&bs, &unmoved) > 3.0 * rmse(&bs, &bs2));
}

#[test]
fn an_area_primitive_placed_inside_its_object_turns_about_the_instance_origin() {
    // The lamp sits 1 to the side of its object's origin (its own transform inside
    // ObjectBegin) and the instance turns by 40° and 40.001°: it renders as the static
    // instance turned by 40°, the lamp's offset turned with it (instance × light, not
    // light × instance).
    let light = "AttributeBegin\nTranslate 1 0 0\nLightSource \"disc\" \"point from\" [0 0 2.5] \"normal normal\" [0 0 -1] \"float radius\" [0.4] \"color L\" [4 4 4]\nAttributeEnd";
    let still = sky_scene(light, "Rotate 40 0 0 1", "path");
    let (a, a2) = (film(&still, 0), film(&still, 1));
    let keyed = film(&sky_scene(light, &turn(40.0, 40.001), "path"), 2);
    films_within_noise(&a, &a2, &keyed, "disc: keys 40° and 40.001°");
    let unturned = block_means(&film(&sky_scene(light, "", "path"), 2), 4);
    let (ba, ba2) = (block_means(&a, 4), block_means(&a2, 4));
    assert!(rmse(&ba, &unturned) > 3.0 * rmse(&ba, &ba2));
}
