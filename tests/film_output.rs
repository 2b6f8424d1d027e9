//! Image and FLM outputs as the Film parameters ask for them, and resuming from a resume FLM.

use luxfarm::film::{flm, read_flm_file, Channels, Film, FilmParams};
use luxfarm::output;
use std::path::{Path, PathBuf};

mod common;

use common::shared;

fn reference() -> PathBuf {
    shared().join(
        "scenes/testsuite/core_regression_tests/tests/integrators/directlighting/simple/reference.flm",
    )
}

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("luxfarm-out-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn mad_against_reference_png(png: &Path) -> [f64; 3] {
    let ours = image::open(png).unwrap().to_rgb8();
    let theirs = image::open(reference().with_extension("png"))
        .unwrap()
        .to_rgb8();
    let mut sum = [0.0f64; 3];
    for (a, b) in ours.pixels().zip(theirs.pixels()) {
        for c in 0..3 {
            sum[c] += (f64::from(a[c]) - f64::from(b[c])).abs();
        }
    }
    sum.map(|s| s / f64::from(ours.width() * ours.height()))
}

#[test]
fn png_output_reproduces_luxrenders_png() {
    let dir = tmpdir("png");
    let (film, header) = read_flm_file(&reference()).unwrap();
    let p = FilmParams::from_flm(&header);
    let written = output::write_outputs(&film, &p, &dir.join("x")).unwrap();
    assert_eq!(written, vec![dir.join("x.png")]);
    let mad = mad_against_reference_png(&dir.join("x.png"));
    assert!(mad.iter().all(|&m| m <= 2.0), "{mad:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn every_format_and_channel_set() {
    let dir = tmpdir("all");
    let (film, header) = read_flm_file(&reference()).unwrap();
    let mut p = FilmParams::from_flm(&header);
    p.tga.enabled = true;
    p.exr.enabled = true;
    p.write_resume_flm = true;
    for (ch, bit16, half) in [
        (Channels::Y, false, true),
        (Channels::Ya, true, false),
        (Channels::Rgb, true, true),
        (Channels::Rgba, false, false),
    ] {
        p.png.channels = ch;
        p.png_16bit = bit16;
        p.tga.channels = if ch == Channels::Ya { Channels::Y } else { ch };
        p.exr.channels = ch;
        p.exr_options.halftype = half;
        p.exr_options.applyimaging = !half;
        let base = dir.join(format!("{ch:?}"));
        let written = output::write_outputs(&film, &p, &base).unwrap();
        assert_eq!(written.len(), 4, "{written:?}");
        let png = image::open(base.with_extension("png")).unwrap();
        assert_eq!((png.width(), png.height()), (512, 512));
        assert_eq!(
            png.color().channel_count() as usize,
            if ch == Channels::Y {
                1
            } else if ch == Channels::Ya {
                2
            } else if ch == Channels::Rgb {
                3
            } else {
                4
            }
        );
        assert_eq!(
            png.color().bytes_per_pixel() as usize / png.color().channel_count() as usize,
            if bit16 { 2 } else { 1 }
        );
        let tga = image::open(base.with_extension("tga")).unwrap();
        assert_eq!(tga.width(), 512);
        let exr = exr::prelude::read_all_data_from_file(base.with_extension("exr")).unwrap();
        let layer = &exr.layer_data[0];
        let names: Vec<String> = layer
            .channel_data
            .list
            .iter()
            .map(|c| c.name.to_string())
            .collect();
        assert_eq!(
            names.len(),
            match ch {
                Channels::Y => 1,
                Channels::Ya => 2,
                Channels::Rgb => 3,
                Channels::Rgba => 4,
            },
            "{names:?}"
        );
        let (back, _) = read_flm_file(&base.with_extension("flm")).unwrap();
        assert_eq!(back, film);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn exr_with_z_buffer() {
    let dir = tmpdir("z");
    let mut film = Film::new(4, 3, vec![]);
    film.add_splat(0, 1, 1, [1.0, 1.0, 1.0], 1.0, 1.0);
    let mut p = FilmParams::with_resolution(4, 3);
    p.png.enabled = false;
    p.exr.enabled = true;
    p.exr.zbuf = true;
    let z: Vec<f32> = (0..12).map(|i| i as f32).collect();
    output::write_outputs_with_z(&film, &p, &dir.join("z"), Some(&z)).unwrap();
    let exr = exr::prelude::read_all_data_from_file(dir.join("z.exr")).unwrap();
    let names: Vec<String> = exr.layer_data[0]
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    assert!(names.contains(&"Z".to_string()), "{names:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn resume_and_restart() {
    let dir = tmpdir("resume");
    let base = dir.join("scene");
    let mut film = Film::new(3, 2, vec![]);
    film.add_splat(0, 0, 0, [1.0, 1.0, 1.0], 1.0, 1.0);
    film.add_sample_count(6.0);
    let mut p = FilmParams::with_resolution(3, 2);
    p.write_resume_flm = true;
    flm::write_flm_file(&base.with_extension("flm"), &film, &p).unwrap();

    let mut resumed = Film::new(3, 2, vec![]);
    let from = output::resume(&mut resumed, &p, &base).unwrap();
    assert_eq!(from, Some(base.with_extension("flm")));
    assert_eq!(resumed, film);

    p.restart_resume_flm = true;
    let mut fresh = Film::new(3, 2, vec![]);
    assert_eq!(output::resume(&mut fresh, &p, &base).unwrap(), None);
    assert_eq!(fresh.sample_count(0), 0.0);
    assert!(dir.join("scene.flm1").exists() && !base.with_extension("flm").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
