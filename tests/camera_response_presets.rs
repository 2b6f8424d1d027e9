//! LuxRender's built-in camera response presets end to end: a scene whose Film names one
//! renders, and its tonemapped image is the plain image mapped through the preset's curves; a
//! name that is neither a preset nor a file fails the build at the Film statement.

mod render_util;

use luxfarm::film::response::CameraResponse;
use luxfarm::render::setup::Renderable;
use luxfarm::render::SessionOptions;
use luxfarm::tonemap;
use render_util::*;
use std::path::Path;

const PATH: &str = "/tmp/luxfarm-crf-preset-test.lxs";

fn scene(response: &str) -> String {
    format!(
        r#"LookAt 0 -5 1 0 0 1 0 0 1
Camera "perspective" "float fov" [40]
Film "fleximage" "integer xresolution" [12] "integer yresolution" [12] "integer haltspp" [1]
  "string tonemapkernel" ["linear"] "string cameraresponse" ["{response}"]
SurfaceIntegrator "directlighting"
WorldBegin
Material "matte" "color Kd" [0.7 0.4 0.2]
Shape "sphere" "float radius" [1]
LightSource "point" "point from" [0 -3 3] "color L" [20 20 20]
WorldEnd
"#
    )
}

#[test]
fn a_preset_named_by_the_film_maps_the_rendered_image() {
    let text = scene("Ektachrome_64CD");
    let desc = parse_text(&text, Path::new(PATH));
    let built = Renderable::build(&desc, Path::new("/tmp")).expect("scene builds");
    let tm = &built.setup.film_params.tonemap;
    let crf = tm.effects.response.clone().expect("the preset is loaded");
    assert_eq!(crf.name, "Ektachrome_64CD");
    assert_eq!(
        *crf,
        CameraResponse::preset("Ektachrome_64CD").unwrap().unwrap()
    );

    let opts = SessionOptions {
        threads: 2,
        seed: 3,
        stream: 0,
    };
    let film = render(&desc, Path::new("/tmp"), opts, 1);
    let with = tonemap::tonemap(&film, tm);
    let mut plain_params = tm.clone();
    plain_params.effects.response = None;
    let plain = tonemap::tonemap(&film, &plain_params);
    let mut changed = 0;
    for (a, b) in plain.rgb.iter().zip(&with.rgb) {
        assert_eq!(crf.map(*a), *b);
        changed += usize::from(a != b);
    }
    // the sphere is lit: most pixels see something, and the film's curve changes them
    assert!(changed > 12 * 12 / 4, "{changed} pixels changed");
}

#[test]
fn an_unknown_response_fails_at_the_film_statement() {
    let text = scene("Ektachrome64");
    let desc = parse_text(&text, Path::new(PATH));
    let err = match Renderable::build(&desc, Path::new("/tmp")) {
        Ok(_) => panic!("an unknown camera response must not build"),
        Err(e) => e.to_string(),
    };
    assert!(err.contains(":3:"), "{err}");
    assert!(err.contains("neither"), "{err}");
    assert!(err.contains("Ektachrome_64CD"), "{err}");
}

#[test]
fn none_and_empty_mean_no_response() {
    for name in ["", "None"] {
        let desc = parse_text(&scene(name), Path::new(PATH));
        let dir = tempfile::tempdir().unwrap();
        let built = Renderable::build(&desc, dir.path()).expect("scene builds");
        assert!(
            built.setup.film_params.tonemap.effects.response.is_none(),
            "{name:?}"
        );
    }
}

/// The radiances of `scripts/luxcore_crf.py`'s eight emitters (linear RGB).
const LEVELS: [[f32; 3]; 8] = [
    [0.02; 3],
    [0.1; 3],
    [0.3; 3],
    [0.6; 3],
    [1.0; 3],
    [0.5, 0.2, 0.05],
    [0.05, 0.3, 0.6],
    [2.0; 3],
];

/// LuxCore's camera response plugin (pyluxcore 2.11) on those radiances after a linear
/// tonemap of scale 1, as `python3 scripts/luxcore_crf.py NAME...` prints them.
#[rustfmt::skip]
const LUXCORE: [(&str, [f32; 24]); 3] = [
    ("Advantix_100CD", [0.01161, 0.00905, 0.00602, 0.09257, 0.07936, 0.06269, 0.33325, 0.30978,
        0.27465, 0.64701, 0.62680, 0.59799, 1.00000, 1.00000, 1.00000, 0.54846, 0.19239, 0.02331,
        0.03875, 0.30978, 0.59799, 1.00000, 1.00000, 1.00000]),
    ("Agfapan_apx_100CD", [0.00292, 0.00292, 0.00292, 0.08846, 0.08846, 0.08846, 0.37888,
        0.37888, 0.37888, 0.72663, 0.72663, 0.72663, 1.00000, 1.00000, 1.00000, 0.31296, 0.31296,
        0.31296, 0.33489, 0.33489, 0.33489, 1.00000, 1.00000, 1.00000]),
    ("Ektachrome_64CD", [0.00004, 0.00001, 0.00001, 0.02354, 0.01055, 0.00315, 0.47925, 0.37552,
        0.16739, 0.83844, 0.81371, 0.64201, 1.00000, 1.00000, 1.00000, 0.76510, 0.14805, 0.00018,
        0.00130, 0.37552, 0.64201, 1.00000, 1.00000, 1.00000]),
];

/// Colour, monochrome and slide presets map chosen radiances as LuxCore's plugin does (the
/// same measured curves; LuxCore, like LuxRender 1.x, takes the curves' built-in gamma out).
#[test]
fn presets_map_radiances_as_luxcore_does() {
    for (name, want) in LUXCORE {
        let crf = CameraResponse::preset(name).unwrap().expect("a preset");
        for (i, level) in LEVELS.iter().enumerate() {
            let got = crf.map(*level);
            for k in 0..3 {
                let w = want[3 * i + k];
                eprintln!(
                    "{name} {level:?}[{k}]: luxfarm {:.5} LuxCore {w:.5}",
                    got[k]
                );
                assert!(
                    (got[k] - w).abs() <= 1e-3 + 0.01 * w,
                    "{name} {level:?} channel {k}: {} vs LuxCore {w}",
                    got[k]
                );
            }
        }
    }
}
