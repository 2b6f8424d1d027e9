//! Photometric lights side by side with LuxCore (pyluxcore 2.11): an IES point light and a
//! projection light over a grey floor, compared in 32-pixel block means of Y with LuxCore's
//! renders of the same scenes (`python3 scripts/luxcore_photometric.py --spp 256` prints
//! them; the script says how the LuxCore scenes carry the two lights' documented differences
//! in normalisation and framing, and why the blocks skip the film's last row).
//!
//! Both scenes look straight down from 3 m at a grey (0.5) matte floor, 128×128 pixels, one
//! box-filtered pixel, direct light only. A point light's direct light has no noise beyond
//! where in each pixel a sample lands, so 16 low-discrepancy samples per pixel suffice (they
//! cover the slide's edges evenly).

mod render_util;

use luxfarm::render::SessionOptions;
use luxfarm::spectrum::{illuminant_y, Rgb};
use render_util::*;
use std::path::Path;

const RES: u32 = 128;
const BLOCK: u32 = 32;

/// Type C, a full turn of horizontal angles: brightest toward +x (H = 0), dimmest toward −x.
const IES: &str = "IESNA:LM-63-2002\n[TEST] asymmetric downlight\nTILT=NONE\n\
1 1000 1 5 5 1 2 0.1 0.1 0\n1.0 1.0 20\n0 30 60 90 180\n0 90 180 270 360\n\
900 700 300 50 0\n600 500 250 40 0\n300 250 120 20 0\n600 500 250 40 0\n900 700 300 50 0\n";

fn scene(light: &str) -> String {
    format!(
        r#"
LookAt 0 0 3  0 0 0  0 1 0
Camera "perspective" "float fov" [90]
Film "fleximage" "integer xresolution" [{RES}] "integer yresolution" [{RES}]
PixelFilter "box" "float xwidth" [0.5] "float ywidth" [0.5]
Sampler "lowdiscrepancy" "integer pixelsamples" [16]
SurfaceIntegrator "directlighting" "integer maxdepth" [1]
WorldBegin
AttributeBegin
{light}
AttributeEnd
Material "matte" "color Kd" [0.5 0.5 0.5]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point P" [-100 -100 0 100 -100 0 100 100 0 -100 100 0]
WorldEnd
"#
    )
}

/// The projected slide (as in the script): 64×32, quadrants 1, 2 (top) and 3, 4 (bottom),
/// each ramped from 0.5 at the left edge to 1 at the right.
fn slide(x: usize, y: usize) -> f32 {
    let (w, h) = (64, 32);
    let quadrant = match (y < h / 2, x < w / 2) {
        (true, true) => 1.0,
        (true, false) => 2.0,
        (false, true) => 3.0,
        (false, false) => 4.0,
    };
    quadrant * (0.5 + 0.5 * x as f32 / (w - 1) as f32)
}

/// Means of Y over 32-pixel blocks of rows 0..127 (the last block row has 31 rows: LuxCore's
/// film is compared one row down, see the script).
fn blocks(text: &str, dir: &Path) -> Vec<f64> {
    let desc = parse_text(text, &dir.join("scene.lxs"));
    let opts = SessionOptions {
        threads: 2,
        seed: 5,
        stream: 0,
    };
    let film = render(&desc, dir, opts, 1);
    luxcore_blocks(&film, BLOCK)
}

/// LuxCore's block means (256 spp) of the IES scene, rows from the top.
#[rustfmt::skip]
const LUXCORE_IES: [f64; 16] = [
    0.27484, 1.1579, 1.8984, 0.726,
    0.48224, 6.4137, 21.829, 2.4894,
    0.44946, 4.8087, 13.231, 1.9474,
    0.21861, 0.71886, 1.0649, 0.50565,
];

/// LuxCore's block means (256 spp) of the projection scene, rows from the top.
#[rustfmt::skip]
const LUXCORE_PROJECTION: [f64; 16] = [
    0.0, 0.0, 0.0, 0.0,
    0.0027223, 0.11601, 0.20789, 0.071553,
    0.00095121, 0.033665, 0.085515, 0.030253,
    0.0, 0.0, 0.0, 0.0,
];

/// An asymmetric IES profile (flipped to face down) with power normalisation: where the
/// floor is lit, by how much, and which way the profile's horizontal angles turn.
#[test]
fn an_ies_point_light_matches_luxcore_block_means() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(dir.path().join("lamp.ies"), IES).unwrap();
    let light = "Translate 0.3 0.2 1\nLightSource \"point\" \"string iesname\" [\"lamp.ies\"] \
                 \"bool flipz\" [\"true\"] \"float power\" [100] \"float efficacy\" [10]";
    let ours = blocks(&scene(light), dir.path());
    assert_blocks_match_luxcore("ies", &ours, &LUXCORE_IES);
}

/// A projected slide: its orientation on the floor, its even spread (LuxRender's
/// 1/(A cos³θ)) and its edges. LuxRender's light colours are illuminant spectra whose Y for
/// white `L` is `illuminant_y(white)`; LuxCore's white is 1, so ours are divided by that.
#[test]
fn a_projection_light_matches_luxcore_block_means() {
    let dir = tempfile::tempdir().expect("temp dir");
    exr::prelude::write_rgb_file(dir.path().join("slide.exr"), 64, 32, |x, y| {
        let v = slide(x, y);
        (v, v, v)
    })
    .expect("slide written");
    let light = "Translate 0.2 0.1 1.5\nRotate 180 1 0 0\nLightSource \"projection\" \
                 \"string mapname\" [\"slide.exr\"] \"float fov\" [60]";
    let white = f64::from(illuminant_y(Rgb::WHITE));
    let ours: Vec<f64> = blocks(&scene(light), dir.path())
        .iter()
        .map(|v| v / white)
        .collect();
    assert_blocks_match_luxcore("projection", &ours, &LUXCORE_PROJECTION);
}
