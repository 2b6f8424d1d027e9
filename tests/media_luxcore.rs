//! Participating media side by side with LuxCore (pyluxcore 2.11), whose homogeneous volumes
//! descend from LuxRender's: a sphere of absorbing and scattering medium behind a null
//! boundary, over a grey floor, lit by a square area light, compared in 32-pixel block means
//! of Y with LuxCore's render of the same scene (`python3 scripts/luxcore_media.py --spp 1024`
//! prints them; the script describes the scene and why the blocks skip the film's last row).
//!
//! The luxfarm side is the path tracer with LuxRender's `multi` volume integrator (multiple
//! scattering), 32 segments and no Russian roulette, as LuxCore's PATHCPU renders it.

mod render_util;

use luxfarm::render::SessionOptions;
use luxfarm::spectrum::{illuminant_y, Rgb};
use render_util::*;
use std::fmt::Write as _;

const RES: u32 = 128;
const BLOCK: u32 = 32;
/// The sphere mesh's segments around and rings from pole to pole (as in the script).
const SEG: usize = 48;
const RINGS: usize = 24;

/// The UV sphere of the script: centre (0, 0, 1), radius 0.8, triangles wound outward.
fn sphere_mesh() -> String {
    let (c, r) = ([0.0f64, 0.0, 1.0], 0.8f64);
    let mut pts = String::new();
    for j in 0..=RINGS {
        let th = std::f64::consts::PI * j as f64 / RINGS as f64;
        for i in 0..SEG {
            let ph = 2.0 * std::f64::consts::PI * i as f64 / SEG as f64;
            let p = [
                c[0] + r * th.sin() * ph.cos(),
                c[1] + r * th.sin() * ph.sin(),
                c[2] + r * th.cos(),
            ];
            let _ = write!(pts, "{} {} {} ", p[0], p[1], p[2]);
        }
    }
    let mut idx = String::new();
    for j in 0..RINGS {
        for i in 0..SEG {
            let (a, b) = (j * SEG + i, j * SEG + (i + 1) % SEG);
            let (c, d) = (a + SEG, b + SEG);
            if j > 0 {
                let _ = write!(idx, "{a} {c} {b} ");
            }
            if j < RINGS - 1 {
                let _ = write!(idx, "{b} {c} {d} ");
            }
        }
    }
    format!("Shape \"trianglemesh\" \"integer indices\" [{idx}] \"point P\" [{pts}]")
}

fn scene(spp: u32) -> String {
    format!(
        r#"
LookAt 0 -5 1.6  0 0 0.9  0 0 1
Camera "perspective" "float fov" [40]
Film "fleximage" "integer xresolution" [{RES}] "integer yresolution" [{RES}]
PixelFilter "box" "float xwidth" [0.5] "float ywidth" [0.5]
Sampler "sobol" "integer pixelsamples" [{spp}]
SurfaceIntegrator "path" "integer maxdepth" [32] "string rrstrategy" ["none"]
VolumeIntegrator "multi"
WorldBegin
MakeNamedVolume "fog" "homogeneous" "color sigma_a" [0.4 0.4 0.4] "color sigma_s" [1.6 1.6 1.6] "color g" [0.3 0.3 0.3]
AttributeBegin
Material "matte" "color Kd" [0.5 0.5 0.5]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point P" [-5 -5 0 5 -5 0 5 5 0 -5 5 0]
AttributeEnd
AttributeBegin
Material "matte" "color Kd" [0 0 0]
AreaLightSource "area" "color L" [8 8 8] "float power" [0]
Shape "trianglemesh" "integer indices" [0 2 1 0 3 2] "point P" [-0.6 -0.6 3.2 0.6 -0.6 3.2 0.6 0.6 3.2 -0.6 0.6 3.2]
AttributeEnd
AttributeBegin
Interior "fog"
Material "null"
{sphere}
AttributeEnd
WorldEnd
"#,
        sphere = sphere_mesh()
    )
}

/// Means of Y over 32-pixel blocks of rows 0..127 (the last block row has 31 rows: LuxCore's
/// film is compared one row down, see the script), divided by the luminance of LuxRender's
/// white illuminant (LuxCore's white radiance is 1).
fn blocks(spp: u32, stream: u64) -> Vec<f64> {
    let dir = tempfile::tempdir().expect("temp dir");
    let desc = parse_text(&scene(spp), &dir.path().join("media.lxs"));
    let opts = SessionOptions {
        threads: 2,
        seed: 11,
        stream,
    };
    let film = render(&desc, dir.path(), opts, 1);
    let white = f64::from(illuminant_y(Rgb::WHITE));
    luxcore_blocks(&film, BLOCK)
        .into_iter()
        .map(|y| y / white)
        .collect()
}

/// LuxCore's block means (1024 spp), rows from the top.
#[rustfmt::skip]
const LUXCORE: [f64; 16] = [
    0.0, 0.0, 0.0, 0.0,
    0.0, 0.10164, 0.10143, 0.0,
    0.060957, 0.056551, 0.05656, 0.060926,
    0.10374, 0.083145, 0.083206, 0.1038,
];

/// The medium's absorption darkens the floor behind and under the sphere, its scattering
/// lights the sphere itself: every lit block within 3 % of LuxCore's, the dark ones dark
/// (measured within 0.5 %; LuxCore's single-scattering default, without `multiscattering`,
/// reads 47 % darker on the sphere's blocks, so the comparison can fail).
#[test]
fn a_homogeneous_sphere_matches_luxcore_block_means() {
    assert_blocks_match_luxcore("media", &blocks(SPP, 0), &LUXCORE);
}

/// Samples per pixel of the test's render.
const SPP: u32 = 16;
