//! The depth (Z) buffer: rendered when the Film asks for `write_exr_ZBuf`, holding the
//! distance from the camera to the first hit, and written as the EXR's Z channel with
//! LuxRender 1.x's normalisations (Min/Max: nearest 1, farthest 0; "Camera Start/End clip":
//! the raw depths). PNG and TGA get no Z, as in LuxRender.

mod render_util;

use luxfarm::output;
use luxfarm::render::{Session, SessionOptions};
use render_util::*;
use std::path::Path;

/// A camera at the origin looking along +y at a wall (the plane y = 5), 16x16 pixels.
fn scene(extra_film: &str) -> String {
    format!(
        r#"LookAt 0 0 0 0 1 0 0 0 1
Camera "perspective" "float fov" [40]
Film "fleximage" "integer xresolution" [16] "integer yresolution" [16] {extra_film}
PixelFilter "box" "float xwidth" [0.5] "float ywidth" [0.5]
Sampler "random" "integer pixelsamples" [4]
SurfaceIntegrator "directlighting"
WorldBegin
LightSource "point" "point from" [0 1 0] "color L" [1 1 1]
Material "matte"
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
    "point P" [-100 5 -100 100 5 -100 100 5 100 -100 5 100]
WorldEnd
"#
    )
}

fn session(text: &str) -> Session {
    let path = Path::new("/tmp/luxfarm-zbuffer-test.lxs");
    let desc = parse_text(text, path);
    let mut s = Session::new(&desc, Path::new("/tmp"), SessionOptions::default()).unwrap();
    assert!(s.render_pass().complete);
    s
}

#[test]
fn depths_of_a_wall_at_a_known_distance() {
    let s = session(&scene(
        r#""bool write_exr" ["true"] "bool write_exr_ZBuf" ["true"]"#,
    ));
    let z = s.zbuffer().expect("a Z buffer is kept").raw();
    // pixel (8, 8): its centre is 0.5 px off the axis, 1/cos = 1.0005
    let centre = z[8 * 16 + 8];
    assert!((centre - 5.0).abs() < 0.01, "{centre}");
    // pixel (0, 0): centre at ndc -0.9375 on both axes, tan = 0.9375 * tan(20°) = 0.34122,
    // distance = 5 * sqrt(1 + 2 * 0.34122²) = 5.5517
    let corner = z[0];
    assert!((corner - 5.5517).abs() < 0.02, "{corner}");
    // "None" is the EXR default: the raw depths are written
    assert_eq!(s.exr_depths().unwrap(), z);
}

#[test]
fn exr_gets_a_z_channel_and_normalisation_applies() {
    let s = session(&scene(
        r#""bool write_exr" ["true"] "bool write_exr_ZBuf" ["true"]
           "string write_exr_zbuf_normalizationtype" ["Min/Max"] "bool write_png" ["false"]"#,
    ));
    let d = s.exr_depths().unwrap();
    let (lo, hi) = d
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), &v| (a.min(v), b.max(v)));
    assert!(lo.abs() < 1e-6 && (hi - 1.0).abs() < 1e-6, "{lo} {hi}");
    // LuxRender's direction: the wall's nearest pixels (the centre) are 1, the corners 0.
    let raw = s.zbuffer().unwrap().raw();
    let nearest = (0..raw.len())
        .min_by(|&a, &b| raw[a].total_cmp(&raw[b]))
        .unwrap();
    let farthest = (0..raw.len())
        .max_by(|&a, &b| raw[a].total_cmp(&raw[b]))
        .unwrap();
    assert!([7 * 16 + 7, 7 * 16 + 8, 8 * 16 + 7, 8 * 16 + 8].contains(&nearest));
    assert_eq!((d[nearest], d[farthest]), (1.0, 0.0));
    let centre = (raw[8 * 16 + 8], d[8 * 16 + 8]);
    let (near, far) = (raw[nearest], raw[farthest]);
    assert!((centre.1 - (far - centre.0) / (far - near)).abs() < 1e-5);
    let dir = std::env::temp_dir().join(format!("luxfarm-zbuf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let base = dir.join("wall");
    let written = output::write_outputs_with_z(s.film(), s.film_params(), &base, Some(&d)).unwrap();
    let exr_path = written
        .iter()
        .find(|p| p.extension().is_some_and(|e| e == "exr"))
        .unwrap();
    let img = exr::prelude::read_all_flat_layers_from_file(exr_path).unwrap();
    let names: Vec<String> = img.layer_data[0]
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    assert!(names.iter().any(|n| n == "Z"), "{names:?}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn camera_start_end_clip_writes_the_depths_as_luxrender_does() {
    let s = session(&scene(
        r#""bool write_exr" ["true"] "bool write_exr_ZBuf" ["true"]
           "string write_exr_zbuf_normalizationtype" ["Camera Start/End clip"]"#,
    ));
    assert_eq!(s.exr_depths().unwrap(), s.zbuffer().unwrap().raw());
}

#[test]
fn no_z_buffer_unless_asked() {
    let s = session(&scene(""));
    assert!(s.zbuffer().is_none());
    // PNG and TGA carry no Z channel: asking them for one renders no depth buffer.
    let s = session(&scene(
        r#""bool write_png_ZBuf" ["true"] "bool write_tga" ["true"] "bool write_tga_ZBuf" ["true"]"#,
    ));
    assert!(s.zbuffer().is_none());
    // One located warning each, at the parameter (line 3 of the scene).
    let said: Vec<String> = s.warnings().iter().map(|w| w.to_string()).collect();
    for name in ["write_png_ZBuf", "write_tga_ZBuf"] {
        let hits: Vec<_> = said.iter().filter(|m| m.contains(name)).collect();
        assert_eq!(hits.len(), 1, "{said:?}");
        assert!(hits[0].contains(":3:"), "{}", hits[0]);
    }
}

/// A farm worker's session renders no depth (its film deltas carry none): after
/// `skip_depth` passes still complete and no Z buffer is kept.
#[test]
fn take_film_takes_the_depth_sums_since_the_last_take() {
    // A farm worker's delta carries the depths added since its last delta.
    let path = Path::new("/tmp/luxfarm-zbuffer-take.lxs");
    let text = scene(r#""bool write_exr" ["true"] "bool write_exr_ZBuf" ["true"]"#);
    let desc = parse_text(&text, path);
    let mut s = Session::new(&desc, Path::new("/tmp"), SessionOptions::default()).unwrap();
    assert!(s.render_pass().complete);
    let first = s.take_film();
    let z = first.depth().expect("the delta carries depth");
    // 4 samples per pixel, box filter of one pixel: 4 depths per pixel.
    assert!(
        z.weights().iter().all(|&w| w == 4.0),
        "{:?}",
        &z.weights()[..4]
    );
    assert!((z.raw()[8 * 16 + 8] - 5.0).abs() < 0.01);
    assert!(s.zbuffer().unwrap().weights().iter().all(|&w| w == 0.0));
    assert!(s.render_pass().complete);
    let mut both = first.clone();
    both.merge(&s.take_film()).unwrap();
    assert!(both.depth().unwrap().weights().iter().all(|&w| w == 8.0));
    // Without a Z output, no depth travels.
    let plain = parse_text(&scene(""), path);
    let mut s = Session::new(&plain, Path::new("/tmp"), SessionOptions::default()).unwrap();
    assert!(s.render_pass().complete);
    assert!(s.take_film().depth().is_none());
}

#[test]
fn depths_across_an_edge_are_plain_means_of_the_covering_samples() {
    // LuxRender adds each sample's depth with weight 1 to every pixel of its filter footprint,
    // so a pixel's depth is a plain mean: across the edge between a near wall (the left half,
    // planes at distance 3) and the far wall (5), every pixel stays between the two, even
    // under mitchell's negative lobes, which would push a filter-weighted mean outside.
    let text = scene(r#""bool write_exr" ["true"] "bool write_exr_ZBuf" ["true"]"#)
        .replace(
            r#"PixelFilter "box" "float xwidth" [0.5] "float ywidth" [0.5]"#,
            r#"PixelFilter "mitchell" "float xwidth" [2] "float ywidth" [2]"#,
        )
        .replace(
            r#"Sampler "random" "integer pixelsamples" [4]"#,
            r#"Sampler "random" "integer pixelsamples" [64]"#,
        )
        .replace(
            "WorldEnd",
            "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n    \
             \"point P\" [-100 3 -100 0 3 -100 0 3 100 -100 3 100]\nWorldEnd",
        );
    let s = session(&text);
    let z = s.zbuffer().expect("a Z buffer is kept").raw();
    // The wall's depths along the middle row: from 3 (near, left) to about 5.5 (far, right).
    let row: Vec<f32> = (0..16).map(|x| z[8 * 16 + x]).collect();
    assert!(row[0] < 3.4 && row[15] > 5.0, "{row:?}");
    // No depth on the row lies outside [3, 5.6] (the far wall's farthest is 5 / cos 20°).
    for (x, d) in row.iter().enumerate() {
        assert!(*d >= 3.0 - 1e-3 && *d <= 5.6, "pixel {x}: {d} ({row:?})");
    }
}
