//! The `falsecolors` kernel through the `luxfarm` binary: a scene whose Film asks for it
//! renders to a PNG (locally, and on a one-worker farm where the master writes it), and
//! `luxfarm flm tonemap` of the FLM written beside it gives the same PNG; a bad `false_*`
//! value is refused naming the scene's file, line and column.

mod cli_common;

use cli_common::{luxfarm, SceneSpec};
use std::path::Path;

/// The tiny scene at 24x16, the Film in false colours (std scale, log, luminance 0.01 to 2)
/// in the kernel's own colour space at gamma 1; `film_extra` ends the Film statement, on the
/// scene's line 9.
fn scene(dir: &Path, film_extra: &str) -> std::path::PathBuf {
    let film = format!(
        r#"Film "fleximage" "integer xresolution" [24] "integer yresolution" [16]
  "string filename" ["frame"] "bool write_resume_flm" ["true"]
  "string tonemapkernel" ["falsecolors"] "string false_method" ["log"]
  "float gamma" [1] "float colorspace_white" [0.3127 0.3290]
  "float colorspace_red" [0.64 0.33] "float colorspace_green" [0.21 0.71]
  "float colorspace_blue" [0.15 0.06]
  {film_extra}"#
    );
    let p = dir.join("scene.lxs");
    std::fs::write(&p, SceneSpec::tiny(&film).text()).unwrap();
    p
}

/// The 8-bit RGB of a PNG (decoded by luxfarm's image reader, values / 255, no gamma).
fn pixels(path: &Path) -> Vec<[i32; 3]> {
    let img = luxfarm::texture::image_io::load(path).unwrap();
    img.texels
        .iter()
        .map(|t| [t[0], t[1], t[2]].map(|v| (v * 255.0).round() as i32))
        .collect()
}

/// Every 8-bit colour of LuxRender's std scale (1024 steps).
fn std_colours() -> Vec<[i32; 3]> {
    (0..1024)
        .map(|s| {
            luxfarm::tonemap::falsecolors::scale_rgb(
                luxfarm::tonemap::FalseScale::Std,
                (s as f32 + 0.5) / 1023.0,
            )
        })
        .map(|c| c.map(|v| (v * 255.0).round() as i32))
        .collect()
}

/// Renders the scene (with `extra` arguments), tonemaps its FLM with `luxfarm flm tonemap`,
/// checks both PNGs are the same bytes and in the std scale's colours; returns the pixels.
fn render_and_tonemap(extra: &[&str]) -> Vec<[i32; 3]> {
    let dir = tempfile::tempdir().unwrap();
    let s = scene(
        dir.path(),
        r#""float false_min" [0.01] "float false_max" [2]"#,
    );
    let mut args = vec![
        "render",
        s.to_str().unwrap(),
        "--haltspp",
        "2",
        "--seed",
        "3",
    ];
    args.extend_from_slice(extra);
    let out = luxfarm(&args);
    assert!(
        out.status.success(),
        "{extra:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rendered = dir.path().join("frame.png");
    let flm = dir.path().join("frame.flm");
    let again = dir.path().join("again.png");
    let out = luxfarm(&[
        "flm",
        "tonemap",
        flm.to_str().unwrap(),
        "-o",
        again.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        std::fs::read(&rendered).unwrap(),
        std::fs::read(&again).unwrap(),
        "{extra:?}: render and flm tonemap differ"
    );
    let a = pixels(&rendered);
    // the image is in the std scale's colours (±1 for the colour space round trip), and
    // more than one of them
    let scale = std_colours();
    for &p in &a {
        assert!(
            scale
                .iter()
                .any(|c| c.iter().zip(p).all(|(c, p)| (c - p).abs() <= 1)),
            "{extra:?}: {p:?} is not a std scale colour"
        );
    }
    let distinct: std::collections::BTreeSet<_> = a.iter().collect();
    assert!(distinct.len() > 3, "{extra:?}: {distinct:?}");
    a
}

#[test]
fn render_and_flm_tonemap_give_the_same_false_colour_png() {
    render_and_tonemap(&[]);
}

/// The master's outputs: a one-worker farm writes the Film's PNG (tonemapped by the master
/// from the merged film) in the same false colours, and its FLM tonemaps to the same PNG.
#[test]
fn a_farm_render_writes_the_same_kind_of_false_colour_png() {
    render_and_tonemap(&["--workers", "1", "--threads", "1"]);
}

#[test]
fn bad_false_colour_values_are_located_errors() {
    for (extra, name) in [
        (r#""string false_colorscale" ["jet"]"#, "false_colorscale"),
        (
            r#""float false_min" [2] "float false_max" [1]"#,
            "false_max",
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let s = scene(dir.path(), extra);
        let out = luxfarm(&["render", s.to_str().unwrap(), "--haltspp", "1"]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{extra}");
        assert!(err.contains("scene.lxs:9:"), "{extra}: {err}");
        assert!(err.contains(name), "{extra}: {err}");
    }
}
