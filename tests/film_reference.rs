//! The reference film LuxRender wrote for the directlighting regression scene: reading it,
//! its header and parameters, tonemapping it to its PNG, and write/read round trips.

use luxfarm::film::{flm, read_flm_file, FilmParams};
use luxfarm::tonemap::{self, Kernel};
use std::path::PathBuf;

mod common;

use common::shared;

fn scene_dir() -> PathBuf {
    shared().join("scenes/testsuite/core_regression_tests/tests/integrators/directlighting/simple")
}

#[test]
fn reference_header_and_counts() {
    let (film, header) = read_flm_file(&scene_dir().join("reference.flm")).unwrap();
    assert_eq!((film.width(), film.height()), (512, 512));
    assert_eq!(film.groups(), ["default"]);
    assert_eq!(film.buffer_types().len(), 1);
    assert_eq!(film.sample_count(0), 34_213_248.0);
    assert!((film.spp() - 130.51).abs() < 0.005);
    let p = FilmParams::from_flm(&header);
    assert_eq!(p.tonemap.kernel, Kernel::Reinhard);
    assert_eq!(p.tonemap.reinhard_prescale, 1.0);
    assert_eq!(p.tonemap.reinhard_postscale, 1.2);
    assert_eq!(p.tonemap.reinhard_burn, 6.0);
    assert_eq!(p.tonemap.gamma, 2.2);
    assert_eq!(header.params.len(), 56);
}

#[test]
fn reference_tonemaps_to_its_png() {
    let (film, header) = read_flm_file(&scene_dir().join("reference.flm")).unwrap();
    let p = FilmParams::from_flm(&header);
    let img = tonemap::tonemap_display(&film, &p.tonemap);
    let png = image::open(scene_dir().join("reference.png"))
        .unwrap()
        .to_rgb8();
    assert_eq!((png.width(), png.height()), (512, 512));
    let mut sum = [0.0f64; 3];
    for (i, px) in png.pixels().enumerate() {
        for c in 0..3 {
            let ours = f64::from(luxfarm::imageio::quantize8(img.rgb[i][c]));
            sum[c] += (ours - f64::from(px[c])).abs();
        }
    }
    let n = 512.0 * 512.0;
    let mad = sum.map(|s| s / n);
    eprintln!("mean absolute difference per channel (0-255): {mad:?}");
    for m in mad {
        assert!(m <= 2.0, "{mad:?}");
    }
}

#[test]
fn write_read_round_trip_is_bit_identical() {
    let (film, header) = read_flm_file(&scene_dir().join("reference.flm")).unwrap();
    let p = FilmParams::from_flm(&header);
    let mut bytes = Vec::new();
    flm::write_flm(&film, &p, &mut bytes).unwrap();
    let (back, header2) = flm::read_flm(&bytes[..]).unwrap();
    assert_eq!(back, film);
    assert_eq!(FilmParams::from_flm(&header2).tonemap, p.tonemap);
    let mut again = Vec::new();
    flm::write_flm(&back, &FilmParams::from_flm(&header2), &mut again).unwrap();
    assert_eq!(again, bytes);
}

#[test]
fn written_header_matches_luxrenders_bytes() {
    use flate2::read::GzDecoder;
    use std::io::Read;
    let path = scene_dir().join("reference.flm");
    let mut raw = Vec::new();
    GzDecoder::new(std::fs::File::open(&path).unwrap())
        .read_to_end(&mut raw)
        .unwrap();
    let (film, header) = read_flm_file(&path).unwrap();
    let mut ours = Vec::new();
    flm::write_flm(&film, &FilmParams::from_flm(&header), &mut ours).unwrap();
    let mut ours_raw = Vec::new();
    GzDecoder::new(&ours[..])
        .read_to_end(&mut ours_raw)
        .unwrap();
    assert_eq!(ours_raw.len(), raw.len());
    assert!(ours_raw == raw, "decompressed FLM differs from LuxRender's");
}

#[test]
fn scene_film_statement_gives_luxrender_params() {
    use luxfarm::lxs::{parse_file, ParseOptions};
    use luxfarm::tonemap::ClampMethod;
    let desc = parse_file(&scene_dir().join("default.lxs"), &ParseOptions::default()).unwrap();
    let film = desc.film.as_ref().unwrap();
    let p = FilmParams::from_entity(Some(film)).unwrap();
    assert_eq!((p.xres, p.yres), (512, 512));
    assert_eq!((p.x_pixel_count, p.y_pixel_count), (512, 512));
    assert_eq!(p.haltspp, Some(127));
    assert_eq!(p.tonemap.kernel, Kernel::Reinhard);
    assert_eq!(p.tonemap.reinhard_postscale, 1.2);
    assert_eq!(p.tonemap.clamp_method, ClampMethod::Lum);
    assert_eq!(p.tonemap.colorspace.white, [0.314275, 0.329411]);
    assert_eq!(p.filename, "default");
    assert!(p.write_resume_flm && p.restart_resume_flm && p.png.enabled && !p.exr.enabled);
    assert!(!p.premultiply_alpha);
    let unused: Vec<_> = film.params.unused().map(|q| q.name.clone()).collect();
    assert!(unused.is_empty(), "unused Film parameters: {unused:?}");
}
