//! The Film's image effects end to end: read from a Film statement, applied by the shared
//! tonemapping stage (what `luxfarm render`, `flm tonemap`, the master's outputs and previews
//! all call), written to an FLM and applied again identically after reading it back.

mod render_util;

use luxfarm::film::{flm, Film, FilmParams};
use luxfarm::lxs::ParamValue;
use luxfarm::tonemap;
use render_util::linear_film_params;

fn film_params(extra: &[(&str, ParamValue)]) -> FilmParams {
    linear_film_params(32, 24, extra)
}

/// A dim uniform film with one bright pixel.
fn film() -> Film {
    let mut f = Film::new(32, 24, vec!["default".into()]);
    for y in 0..24 {
        for x in 0..32 {
            let v = if (x, y) == (16, 12) { 50.0 } else { 0.1 };
            f.add_splat(0, x, y, [v, v, v], 1.0, 1.0);
        }
    }
    f.add_sample_count(32.0 * 24.0);
    f
}

fn all_effects() -> FilmParams {
    film_params(&[
        ("bloom_enabled", ParamValue::Bool(vec![true])),
        ("bloom_radius", ParamValue::Float(vec![0.2])),
        ("glare_enabled", ParamValue::Bool(vec![true])),
        ("glare_amount", ParamValue::Float(vec![0.1])),
        ("vignetting_enabled", ParamValue::Bool(vec![true])),
        ("abberation_enabled", ParamValue::Bool(vec![true])),
        ("abberation_amount", ParamValue::Float(vec![0.05])),
    ])
}

#[test]
fn effects_change_the_image_and_default_is_unchanged() {
    let f = film();
    let plain = tonemap::tonemap(&f, &film_params(&[]).tonemap);
    let fx = tonemap::tonemap(&f, &all_effects().tonemap);
    // bloom spreads the bright pixel: its neighbour brightens, itself dims
    let (c, n) = (12 * 32 + 16, 12 * 32 + 18);
    assert!(
        fx.rgb[n][1] > plain.rgb[n][1] * 1.5,
        "{:?} {:?}",
        fx.rgb[n],
        plain.rgb[n]
    );
    assert!(fx.rgb[c][1] < plain.rgb[c][1]);
    // vignetting darkens the corner relative to the plain image
    assert!(fx.rgb[0][1] < plain.rgb[0][1]);
    assert!(fx.rgb.iter().flatten().all(|v| v.is_finite()));
}

#[test]
fn vignetting_alone_matches_the_hand_computed_factor() {
    let f = film();
    let plain = tonemap::tonemap(&f, &film_params(&[]).tonemap);
    let p = film_params(&[("vignetting_enabled", ParamValue::Bool(vec![true]))]);
    let v = tonemap::tonemap(&f, &p.tonemap);
    // pixel (0, 12) of 32x24: r = 0.5, factor = 0.71 * (1 - 0.4) + 0.29 = 0.716
    let i = 12 * 32;
    for k in 0..3 {
        assert!((v.rgb[i][k] - 0.716 * plain.rgb[i][k]).abs() < 1e-5 * plain.rgb[i][k].max(1.0));
    }
}

#[test]
fn flm_round_trip_keeps_and_applies_the_effects() {
    let f = film();
    let p = all_effects();
    let mut bytes = Vec::new();
    flm::write_flm(&f, &p, &mut bytes).unwrap();
    let (g, header) = flm::read_flm(&bytes[..]).unwrap();
    let q = FilmParams::from_flm(&header);
    assert_eq!(q.tonemap.effects, p.tonemap.effects);
    let a = tonemap::tonemap_display(&f, &p.tonemap);
    let b = tonemap::tonemap_display(&g, &q.tonemap);
    assert_eq!(a.rgb, b.rgb);
}

#[test]
fn camera_response_file_applies_after_the_colour_space() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/imaging");
    let files = luxfarm::fileio::SceneFiles::confined(&dir, &dir).unwrap();
    let f = film();
    let plain = tonemap::tonemap(&f, &film_params(&[]).tonemap);
    let mut p = film_params(&[(
        "cameraresponse",
        ParamValue::String(vec!["halfblue.crf".into()]),
    )]);
    p.tonemap.effects.load_response(&files).unwrap();
    let crf = p.tonemap.effects.response.clone().unwrap();
    let with = tonemap::tonemap(&f, &p.tonemap);
    for (a, b) in plain.rgb.iter().zip(&with.rgb) {
        assert_eq!(crf.map(*a), *b);
    }
    // the curves are linear but for blue, whose gain below 0.5 is halved (before the
    // estimated built-in gamma is taken out): blue falls relative to green.
    let i = 3;
    assert!(with.rgb[i][2] / with.rgb[i][1] < plain.rgb[i][2] / plain.rgb[i][1]);
    // a missing file is an error
    let mut q = film_params(&[(
        "cameraresponse",
        ParamValue::String(vec!["nope.crf".into()]),
    )]);
    assert!(q.tonemap.effects.load_response(&files).is_err());
    // a file outside the scene's directory is refused, even through a symbolic link
    let outside = tempfile::tempdir().unwrap();
    std::fs::copy(dir.join("halfblue.crf"), outside.path().join("x.crf")).unwrap();
    let scene = tempfile::tempdir().unwrap();
    std::os::unix::fs::symlink(outside.path().join("x.crf"), scene.path().join("link.crf"))
        .unwrap();
    let confined = luxfarm::fileio::SceneFiles::confined(scene.path(), scene.path()).unwrap();
    let mut r = film_params(&[(
        "cameraresponse",
        ParamValue::String(vec!["link.crf".into()]),
    )]);
    let e = r.tonemap.effects.load_response(&confined).unwrap_err();
    assert!(e.contains("link.crf"), "{e}");
}
