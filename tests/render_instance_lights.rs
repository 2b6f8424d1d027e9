//! Area lights on shapes inside `ObjectBegin` (issue 16): LuxRender 1.x makes every
//! `ObjectInstance` of such an object a light of its own where the instance puts it (its
//! `InstanceAreaLight`, and `MotionAreaLight` for an instance inside `MotionBegin`). So a
//! scene whose lamps are instances renders the very film of the same scene with each lamp
//! written out as a world shape at the instance's place: static, moving, and instanced
//! inside another object's definition.

mod render_util;

use luxfarm::film::Film;
use luxfarm::render::SessionOptions;
use render_util::*;
use std::path::Path;

fn film(text: &str) -> Film {
    let desc = parse_text(text, Path::new("/tmp/luxfarm-instance-lights.lxs"));
    let opts = SessionOptions {
        threads: 2,
        seed: 3,
        stream: 0,
    };
    render(&desc, Path::new("/tmp"), opts, 1)
}

/// A floor and a ball seen from above at an angle, with `lamps` written in the world block
/// after them, and `camera` motion before the Camera statement.
fn scene(camera: &str, lamps: &str) -> String {
    format!(
        r#"LookAt 0 -6 4  0 0 0.5  0 0 1
{camera}
Camera "perspective" "float fov" [40]
Film "fleximage" "integer xresolution" [32] "integer yresolution" [24]
PixelFilter "box" "float xwidth" [0.5] "float ywidth" [0.5]
Sampler "random" "integer pixelsamples" [8]
SurfaceIntegrator "path" "integer maxdepth" [3]
WorldBegin
AttributeBegin
Material "matte" "color Kd" [0.7 0.7 0.7]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point P" [-4 -4 0  4 -4 0  4 4 0  -4 4 0]
Shape "sphere" "float radius" [0.7]
AttributeEnd
{lamps}
WorldEnd
"#
    )
}

/// A downward-facing emitting square of half-size 0.4, in a 0.2-thick frame that does
/// not emit (after the emitter, so both kinds of shape share the object).
const LAMP: &str = r#"AreaLightSource "area" "color L" [6 5 4] "float power" [40] "float efficacy" [17]
Shape "trianglemesh" "integer indices" [0 2 1 0 3 2] "point P" [-0.4 -0.4 0  0.4 -0.4 0  0.4 0.4 0  -0.4 0.4 0]
"#;
const FRAME: &str = r#"Material "matte" "color Kd" [0.2 0.2 0.2]
Shape "disk" "float radius" [0.9] "float innerradius" [0.6] "float height" [0.01]
"#;

/// `placement` (transform statements) and the lamp, written in the world block.
fn world_lamp(placement: &str) -> String {
    format!("AttributeBegin\n{placement}\nAttributeBegin\nTranslate 0 0 0.05\n{LAMP}AttributeEnd\n{FRAME}AttributeEnd\n")
}

/// The lamp defined once as object "lamp".
fn lamp_object() -> String {
    format!("ObjectBegin \"lamp\"\nAttributeBegin\nTranslate 0 0 0.05\n{LAMP}AttributeEnd\n{FRAME}ObjectEnd\n")
}

/// An instance of object `name` under `placement`.
fn instance(name: &str, placement: &str) -> String {
    format!("AttributeBegin\n{placement}\nObjectInstance \"{name}\"\nAttributeEnd\n")
}

/// Mean Y of a film's pixels.
fn mean_y(f: &Film) -> f64 {
    let px = normalized_xyz(f);
    px.iter().map(|p| p[1]).sum::<f64>() / px.len().max(1) as f64
}

/// The films agree to rounding: the lamps are the same world shapes either way, and the
/// frames around them differ only in the last bits (instanced shapes are hit in object
/// space through an f64 transform).
fn assert_same(a: &Film, b: &Film, what: &str) {
    let m = mean_y(a);
    assert!(m > 0.0, "{what}: black image");
    let r = rms(a, b);
    assert!(r < 1e-5 * m, "{what}: rms {r}, mean Y {m}");
}

/// The films differ by more than a per cent of the mean.
fn assert_differ(a: &Film, b: &Film, what: &str) {
    let (r, m) = (rms(a, b), mean_y(a));
    assert!(r > 1e-2 * m, "{what}: rms {r}, mean Y {m}");
}

const LEFT: &str = "Translate -1.2 0.5 2.5";
const RIGHT: &str = "Translate 1.4 -0.2 2.2\nRotate 20 1 0 0";

#[test]
fn instanced_lamps_light_the_scene_as_lamps_written_out() {
    let written = film(&scene("", &(world_lamp(LEFT) + &world_lamp(RIGHT))));
    let instanced = film(&scene(
        "",
        &(lamp_object() + &instance("lamp", LEFT) + &instance("lamp", RIGHT)),
    ));
    assert_same(&written, &instanced, "two static instances");
    // The comparison can fail: one lamp fewer changes the image.
    let one = film(&scene("", &(lamp_object() + &instance("lamp", LEFT))));
    assert_differ(&written, &one, "one lamp fewer");
    // An object defined and never instanced lights nothing.
    let unused = film(&scene("", &lamp_object()));
    assert!(normalized_xyz(&unused).iter().all(|p| p[1] == 0.0));
}

#[test]
fn a_lamp_instanced_inside_another_object_is_placed_by_both_transforms() {
    let outer = "Translate 0.3 0 0.4";
    let pair = format!(
        "{}ObjectBegin \"pair\"\n{}{}ObjectEnd\n",
        lamp_object(),
        instance("lamp", LEFT),
        instance("lamp", RIGHT)
    );
    let instanced = film(&scene("", &(pair + &instance("pair", outer))));
    let written = film(&scene(
        "",
        &(world_lamp(&format!("{outer}\n{LEFT}")) + &world_lamp(&format!("{outer}\n{RIGHT}"))),
    ));
    assert_same(&written, &instanced, "nested instances");
}

#[test]
fn a_lamp_instanced_with_motion_moves_as_a_moving_lamp_written_out() {
    let slide = "MotionBegin [0 1]\nTranslate -1 0.5 2.5\nTranslate 1 0.5 2.5\nMotionEnd";
    let written = film(&scene("", &world_lamp(slide)));
    let instanced = film(&scene("", &(lamp_object() + &instance("lamp", slide))));
    assert_same(&written, &instanced, "moving instance");
    // And it does move: the lamp still at its first key lights differently.
    let first = film(&scene("", &world_lamp("Translate -1 0.5 2.5")));
    assert_differ(&written, &first, "the lamp at its first key");
}
