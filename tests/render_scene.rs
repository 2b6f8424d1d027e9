//! Scene building: unused parameters are reported with their file:line:column, unreferenced
//! materials are not built, and unsupported lights fail with a located error.

mod render_util;

use luxfarm::render::setup::Renderable;
use render_util::*;
use std::path::Path;

const SCENE: &str = r#"LookAt 0 -5 1 0 0 1 0 0 1
Camera "perspective" "float fov" [40]
Film "fleximage" "integer xresolution" [16] "integer yresolution" [16] "integer haltspp" [1]
SurfaceIntegrator "path" "integer maxdepth" [3]
WorldBegin
MakeNamedMaterial "used" "string type" ["matte"] "color Kd" [0.5 0.5 0.5]
MakeNamedMaterial "never" "string type" ["nosuchmaterial"]
NamedMaterial "used"
Shape "sphere" "float radius" [1]
LightSource "point" "point from" [0 -3 3] "color L" [10 10 10] "float bogus" [1]
WorldEnd
"#;

#[test]
fn unused_parameters_are_reported_with_location() {
    let path = Path::new("/tmp/luxfarm-render-scene-test.lxs");
    let desc = parse_text(SCENE, path);
    // The unknown material type is never referenced, so it is never built.
    let scene = Renderable::build(&desc, Path::new("/tmp")).expect("scene builds");
    let w: Vec<String> = scene.warnings.iter().map(|d| d.to_string()).collect();
    let bogus = w
        .iter()
        .find(|m| m.contains("bogus"))
        .expect("bogus reported");
    assert!(bogus.contains(":10:"), "{bogus}");
    assert_eq!(scene.world.lights().len(), 1);
}

#[test]
fn unsupported_light_is_a_located_error() {
    let text = SCENE.replace("LightSource \"point\"", "LightSource \"sunsky9\"");
    let desc = parse_text(&text, Path::new("/tmp/luxfarm-render-scene-test.lxs"));
    let err = match Renderable::build(&desc, Path::new("/tmp")) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("sunsky9 must be refused"),
    };
    assert!(err.contains("sunsky9") && err.contains(":10:"), "{err}");
}
