//! The lights of issue 17 in one small scene of our own, rendered end to end through the
//! scene's confined files, with the path tracer and with bidirectional path tracing (which
//! starts light subpaths on each of them): a `sunsky2`, a `point` light with an IES profile
//! (flipped to face down), a `goniometric` light with a lat-long map and a `projection` light
//! throwing a two-colour slide on the floor. Every film is finite, without rejected samples,
//! and lit; no light is refused or left without emission sampling.

mod render_util;

use luxfarm::render::{Session, SessionOptions};
use render_util::*;

const IES: &str = "IESNA:LM-63-2002\n[TEST] downlight\nTILT=NONE\n1 1000 1 3 1 1 2 0.1 0.1 0\n\
1.0 1.0 20\n0 45 90\n0\n800 500 0\n";

fn scene(integrator: &str) -> String {
    format!(
        r#"
LookAt 0 -5 3  0 0 0.3  0 0 1
Camera "perspective" "float fov" [60]
Film "fleximage" "integer xresolution" [32] "integer yresolution" [24]
PixelFilter "box"
Sampler "random" "integer pixelsamples" [4]
SurfaceIntegrator "{integrator}"
WorldBegin
AttributeBegin
LightSource "sunsky2" "vector sundir" [0.3 0.2 0.9] "float turbidity" [3] "float gain" [0.0002]
AttributeEnd
AttributeBegin
Translate -1 0 2
LightSource "point" "string iesname" ["lamp.ies"] "bool flipz" ["true"] "float gain" [0.01]
AttributeEnd
AttributeBegin
Translate 1 1 1.5
LightSource "goniometric" "string mapname" ["gonio.png"] "float gain" [0.5]
AttributeEnd
AttributeBegin
Translate 1 -1 2
Rotate 180 1 0 0
LightSource "projection" "string mapname" ["slide.png"] "float fov" [40] "float gain" [2]
AttributeEnd
Material "matte" "color Kd" [0.6 0.6 0.6]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point P" [-4 -4 0 4 -4 0 4 4 0 -4 4 0]
WorldEnd
"#
    )
}

fn write_files(dir: &std::path::Path) {
    std::fs::write(dir.join("lamp.ies"), IES).unwrap();
    let slide = image::RgbImage::from_fn(4, 2, |x, _| {
        if x < 2 {
            image::Rgb([255, 40, 40])
        } else {
            image::Rgb([40, 40, 255])
        }
    });
    slide.save(dir.join("slide.png")).unwrap();
    let gonio = image::RgbImage::from_fn(8, 4, |_, y| image::Rgb([200, 200, (60 * y) as u8]));
    gonio.save(dir.join("gonio.png")).unwrap();
}

#[test]
fn photometric_lights_render_with_path_and_bidirectional() {
    let dir = tempfile::tempdir().unwrap();
    write_files(dir.path());
    for integrator in ["path", "bidirectional"] {
        let path = dir.path().join("lights.lxs");
        let desc = parse_text(&scene(integrator), &path);
        let opts = SessionOptions {
            threads: 2,
            seed: 3,
            stream: 0,
        };
        let mut s = Session::new(&desc, dir.path(), opts).expect("scene builds");
        let lights = s.renderable().world.lights().len();
        assert_eq!(lights, 5, "sun, sky2, point, goniometric, projection");
        let warnings: Vec<String> = s.warnings().iter().map(|w| w.to_string()).collect();
        assert!(
            !warnings.iter().any(|w| w.contains("bidirectional")),
            "{integrator}: {warnings:?}"
        );
        let stats = s.render_pass();
        assert!(stats.complete);
        assert_eq!(stats.rejected, 0, "{integrator}: NaN/Inf/negative samples");
        let film = s.take_film();
        let xyz = normalized_xyz(&film);
        assert!(xyz.iter().flatten().all(|v| v.is_finite() && *v >= 0.0));
        let lit = xyz.iter().filter(|p| p[1] > 0.0).count();
        assert!(lit > xyz.len() * 9 / 10, "{integrator}: {lit} lit pixels");
    }
}
