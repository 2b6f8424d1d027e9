//! The `falsecolors` kernel end to end through the library: read from a Film statement,
//! applied by the shared output stage (`output::write_outputs`, what `luxfarm render`,
//! `luxfarm flm tonemap` and the master's outputs call, and `output::preview_png`, the
//! master's preview), kept in the FLM header, and the same PNG written again from the FLM
//! read back.

use luxfarm::film::{read_flm_file, Film, FilmParams};
use luxfarm::lxs::{Entity, Loc, ParamSet, ParamValue};
use luxfarm::output;
use luxfarm::tonemap::{self, falsecolors, FalseMethod, FalseScale, Kernel};

const W: u32 = 16;
const H: u32 = 4;

/// A Film statement with the falsecolors kernel over Y in [1, 9], in the kernel's own colour
/// space (Adobe RGB) at gamma 1, so the PNG holds the scale's colours as they are.
fn film_params(method: &str, scale: &str) -> FilmParams {
    let mut ps = ParamSet::new();
    let cs = falsecolors::scale_space();
    let s = |v: &str| ParamValue::String(vec![v.into()]);
    let f = |v: &[f32]| ParamValue::Float(v.to_vec());
    ps.add("xresolution", ParamValue::Integer(vec![W as i32]));
    ps.add("yresolution", ParamValue::Integer(vec![H as i32]));
    ps.add("tonemapkernel", s("falsecolors"));
    ps.add("false_method", s(method));
    ps.add("false_colorscale", s(scale));
    ps.add("false_min", f(&[1.0]));
    ps.add("false_max", f(&[9.0]));
    ps.add("gamma", f(&[1.0]));
    ps.add("colorspace_white", f(&cs.white));
    ps.add("colorspace_red", f(&cs.red));
    ps.add("colorspace_green", f(&cs.green));
    ps.add("colorspace_blue", f(&cs.blue));
    ps.add("write_resume_flm", ParamValue::Bool(vec![true]));
    FilmParams::from_entity(Some(&Entity {
        kind: "fleximage".into(),
        params: ps,
        loc: Loc::default(),
    }))
    .unwrap()
}

/// A grey ramp: pixel x of every row has Y = x * 10 / (W - 1) - 0.5 (below 1 to above 9).
fn film() -> Film {
    let mut f = Film::new(W, H, vec!["default".into()]);
    for y in 0..H {
        for x in 0..W {
            let v = x as f32 * 10.0 / (W - 1) as f32 - 0.5;
            f.add_splat(0, x, y, [v.max(0.0); 3], 1.0, 1.0);
        }
    }
    f.add_sample_count(f64::from(W * H));
    f
}

fn png_pixels(path: &std::path::Path) -> Vec<[u8; 3]> {
    let img = image::open(path).unwrap().to_rgb8();
    img.pixels().map(|p| p.0).collect()
}

/// The scale's colour in 8 bits at a luminance, computed by hand from the kernel's functions.
fn expected(method: FalseMethod, scale: FalseScale, y: f32) -> [u8; 3] {
    let v = falsecolors::shape(method, falsecolors::normalise(y, 1.0, 9.0));
    falsecolors::scale_rgb(scale, v).map(|c| (c * 255.0).round() as u8)
}

#[test]
fn png_holds_the_scale_colours_and_survives_the_flm_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    for method in FalseMethod::ALL {
        for scale in FalseScale::ALL {
            let p = film_params(method.name(), scale.name());
            assert_eq!(p.tonemap.kernel, Kernel::FalseColors);
            let f = film();
            let base = dir
                .path()
                .join(format!("{}-{}", method.name(), scale.name()));
            let written = output::write_outputs(&f, &p, &base).unwrap();
            let png = base.with_extension("png");
            assert!(written.contains(&png), "{written:?}");
            let first = png_pixels(&png);
            // every pixel is the scale's colour of its luminance (±1 for the colour space
            // round trip through XYZ)
            for (i, got) in first.iter().enumerate() {
                let x = i as u32 % W;
                let y = (x as f32 * 10.0 / (W - 1) as f32 - 0.5).max(0.0);
                let want = expected(method, scale, y);
                let off = got
                    .iter()
                    .zip(want)
                    .map(|(&g, w)| (i32::from(g) - i32::from(w)).abs())
                    .max();
                assert!(
                    off <= Some(1),
                    "{method:?} {scale:?} pixel {i} (Y {y}): {got:?}, want {want:?}"
                );
            }
            // the master's preview (preview.png, the dashboard's image) shows the same pixels
            let preview = output::preview_png(&f, &p.tonemap, None).unwrap();
            let preview = image::load_from_memory(&preview).unwrap().to_rgb8();
            let preview: Vec<[u8; 3]> = preview.pixels().map(|p| p.0).collect();
            assert_eq!(preview, first, "{method:?} {scale:?}: preview");
            // the FLM keeps the kernel and its parameters; tonemapping it again gives the
            // same PNG, byte for byte
            let (g, header) = read_flm_file(&base.with_extension("flm")).unwrap();
            let mut q = FilmParams::from_flm(&header);
            assert_eq!(q.tonemap.kernel, Kernel::FalseColors);
            assert_eq!(q.tonemap.false_colors, p.tonemap.false_colors);
            q.write_resume_flm = false;
            let again = dir.path().join("again");
            output::write_outputs(&g, &q, &again).unwrap();
            assert_eq!(
                std::fs::read(&png).unwrap(),
                std::fs::read(again.with_extension("png")).unwrap(),
                "{method:?} {scale:?}"
            );
        }
    }
}

#[test]
fn std_scale_ends_and_beyond_in_the_film_colour_space() {
    // hand-computed: below min and at min dark blue (0, 0, 128); at max and above dark red
    // (128, 0, 0); at the middle (Y 5) step 511 of std, (127, 255, 128)
    let p = film_params("linear", "std");
    let mut f = Film::new(5, 1, vec!["default".into()]);
    for (x, y) in [0.2f32, 1.0, 5.0, 9.0, 300.0].into_iter().enumerate() {
        f.add_splat(0, x as u32, 0, [y; 3], 1.0, 1.0);
    }
    let img = tonemap::tonemap_display(&f, &p.tonemap);
    let want = [
        [0, 0, 128],
        [0, 0, 128],
        [127, 255, 128],
        [128, 0, 0],
        [128, 0, 0],
    ];
    for (got, want) in img.rgb.iter().zip(want) {
        let got = got.map(|c| (c * 255.0).round() as i32);
        assert_eq!(got, want);
    }
}

#[test]
fn flm_header_ids_of_the_kernel_and_its_settings() {
    use luxfarm::film::flm_header::id;
    use luxfarm::film::{BufferType, FlmHeader, FlmParam, FlmValue};
    let header = |params: &[(i32, f32)]| FlmHeader {
        width: 2,
        height: 2,
        groups: 1,
        buffer_types: vec![BufferType::PerPixel],
        params: params
            .iter()
            .map(|&(pid, v)| FlmParam {
                id: pid,
                index: 0,
                value: FlmValue::Float(v),
            })
            .collect(),
    };
    // LuxRender's own FLM: kernel 5 and no range (its defaults, 0 and 0)
    let p = FilmParams::from_flm(&header(&[
        (id::TONEMAPKERNEL, 5.0),
        (id::LDR_CLAMP_METHOD, 2.0),
    ]));
    assert_eq!(p.tonemap.kernel, Kernel::FalseColors);
    assert_eq!(p.tonemap.false_colors, Default::default());
    // luxfarm's: method, scale and range by LuxRender's ids 65, 66, 69, 70
    let p = FilmParams::from_flm(&header(&[
        (id::TONEMAPKERNEL, 5.0),
        (id::LDR_CLAMP_METHOD, 2.0),
        (65, 2.0),
        (66, 5.0),
        (69, 3.0),
        (70, 1.0),
    ]));
    let f = p.tonemap.false_colors;
    assert_eq!((f.method, f.scale), (FalseMethod::Log3, FalseScale::Speos));
    assert_eq!((f.min, f.max), (1.0, 3.0));
    // unknown ids fall back as LuxRender's film does: linear, std
    let p = FilmParams::from_flm(&header(&[
        (id::LDR_CLAMP_METHOD, 2.0),
        (65, 7.0),
        (66, 9.0),
    ]));
    let f = p.tonemap.false_colors;
    assert_eq!((f.method, f.scale), (FalseMethod::Linear, FalseScale::Std));
    // a film tonemapped in false colours before and after writing its FLM
    let q = film_params("log", "lmk");
    let f = film();
    let mut bytes = Vec::new();
    luxfarm::film::flm::write_flm(&f, &q, &mut bytes).unwrap();
    let (g, h) = luxfarm::film::flm::read_flm(&bytes[..]).unwrap();
    for (pid, want) in [(65, 1.0), (66, 1.0), (69, 9.0), (70, 1.0)] {
        assert_eq!(h.value(pid, 0), Some(want), "id {pid}");
    }
    let r = FilmParams::from_flm(&h);
    assert_eq!(
        tonemap::tonemap_display(&f, &q.tonemap).rgb,
        tonemap::tonemap_display(&g, &r.tonemap).rgb
    );
}
