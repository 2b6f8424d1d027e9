//! Hand-computed values of the blending, procedural, hit-point and image-derivative textures
//! (a few points each), their defaults, and the bump derivatives that have closed forms.

use super::super::*;
use super::{add_tex, color_of, f, float_of, s, si_at, temp_dir, tex_ref};
use crate::lxs::{ParamValue, SceneDescription, TextureType};
use glam::{Vec2, Vec3A};

fn floats(v: &[f32]) -> ParamValue {
    ParamValue::Float(v.to_vec())
}

fn color(r: f32, g: f32, b: f32) -> ParamValue {
    ParamValue::Color(vec![[r, g, b]])
}

fn int(v: i32) -> ParamValue {
    ParamValue::Integer(vec![v])
}

fn close(a: f32, b: f32) -> bool {
    (a - b).abs() < 1e-5
}

#[test]
fn band_bilerp_multimix() {
    let mut d = SceneDescription::default();
    add_tex(
        &mut d,
        "band",
        TextureType::Float,
        "band",
        vec![
            ("offsets", floats(&[0.0, 0.5, 1.0])),
            ("tex1", f(0.2)),
            ("tex2", f(0.6)),
            ("tex3", f(1.0)),
            ("amount", f(0.25)),
        ],
    );
    add_tex(
        &mut d,
        "cband",
        TextureType::Color,
        "band",
        vec![
            ("offsets", floats(&[0.2, 0.8])),
            ("tex1", color(1.0, 0.0, 0.0)),
            ("tex2", color(0.0, 0.0, 1.0)),
            ("amount", f(0.95)),
        ],
    );
    add_tex(
        &mut d,
        "bil",
        TextureType::Float,
        "bilerp",
        vec![
            ("v00", f(0.1)),
            ("v01", f(0.3)),
            ("v10", f(0.5)),
            ("v11", f(0.9)),
            ("uscale", f(2.0)),
        ],
    );
    add_tex(
        &mut d,
        "mm",
        TextureType::Float,
        "multimix",
        vec![
            ("weights", floats(&[0.5, 0.25])),
            ("tex1", f(0.4)),
            ("tex2", f(0.8)),
        ],
    );
    let mut set = TextureSet::new(&d, TextureCtx::default());
    let si = si_at(0.375, 0.25, Vec3A::ZERO);
    // amount 0.25 is halfway between offsets 0 and 0.5: 0.4.
    assert!(close(float_of(&mut set, "band").eval(&si), 0.4));
    // Above the last offset: the last input.
    assert_eq!(
        color_of(&mut set, "cband").eval(&si),
        Rgb::new(0.0, 0.0, 1.0)
    );
    // s = frac(2 · 0.375) = 0.75, t = 0.25:
    // 0.25·0.75·0.1 + 0.25·0.25·0.3 + 0.75·0.75·0.5 + 0.75·0.25·0.9 = 0.4875.
    let bil = float_of(&mut set, "bil");
    assert!(close(bil.eval(&si), 0.4875), "{}", bil.eval(&si));
    // d/du = uscale · ((v10 − v00) + t·(v00 + v11 − v01 − v10)) = 2·(0.4 + 0.25·0.2) = 0.9.
    let d = bil.duv(&si, 0.001);
    assert!(
        close(d.x, 0.9) && close(d.y, (0.3 - 0.1) + 0.75 * 0.2),
        "{d:?}"
    );
    assert!(close(float_of(&mut set, "mm").eval(&si), 0.4));
    assert!(set.warnings.is_empty(), "{:?}", set.warnings);
}

#[test]
fn band_without_offsets_is_a_located_error() {
    let mut d = SceneDescription::default();
    add_tex(&mut d, "b", TextureType::Float, "band", vec![]);
    let mut set = TextureSet::new(&d, TextureCtx::default());
    let mut ps = ParamSet::new();
    ps.add("x", tex_ref("b"));
    let e = set.float_param(&ps, "x", 0.0).unwrap_err();
    assert!(e.to_string().contains("offsets"), "{e}");
}

#[test]
fn brick_bonds_bricks_and_mortar() {
    let mut d = SceneDescription::default();
    add_tex(
        &mut d,
        "b",
        TextureType::Float,
        "brick",
        vec![("brickbond", s("stacked"))],
    );
    add_tex(
        &mut d,
        "mod",
        TextureType::Float,
        "brick",
        vec![
            ("brickbond", s("running")),
            ("brickmodtex", tex_ref("ramp")),
        ],
    );
    // A 3D checker along x evaluated at the brick's index: alternates from brick to brick.
    add_tex(
        &mut d,
        "ramp",
        TextureType::Float,
        "checkerboard",
        vec![("dimension", int(3)), ("tex1", f(1.0)), ("tex2", f(0.5))],
    );
    let mut set = TextureSet::new(&d, TextureCtx::default());
    let b = float_of(&mut set, "b");
    // (0.15, 0.05, 0.05) + 0.011, over (0.3, 0.15, 0.1): (0.537, 0.407, 0.61), inside the
    // first brick (mortar fractions 0.033, 0.067, 0.1).
    assert_eq!(b.eval(&si_at(0.0, 0.0, Vec3A::new(0.15, 0.05, 0.05))), 1.0);
    // z = −0.006: (0.005/0.1) = 0.05 of the row, in the bed joint: mortar 0.2.
    assert!(close(
        b.eval(&si_at(0.0, 0.0, Vec3A::new(0.15, 0.05, -0.006))),
        0.2
    ));
    // x = 0.29: 0.301/0.3 → 0.0033 into the next brick, in the head joint.
    assert!(close(
        b.eval(&si_at(0.0, 0.0, Vec3A::new(0.29, 0.05, 0.05))),
        0.2
    ));
    // Running bond with a modulation texture: bricks 0 and 1 of the row differ.
    let m = float_of(&mut set, "mod");
    let v0 = m.eval(&si_at(0.0, 0.0, Vec3A::new(0.15, 0.1, 0.05)));
    let v1 = m.eval(&si_at(0.0, 0.0, Vec3A::new(0.45, 0.1, 0.05)));
    assert!((v0 - v1).abs() == 0.5, "{v0} {v1}");
    assert!(set.warnings.is_empty(), "{:?}", set.warnings);
}

#[test]
fn every_brick_bond_draws_bricks_and_mortar() {
    for bond in [
        "stacked",
        "running",
        "flemish",
        "english",
        "herringbone",
        "basket",
        "chain link",
    ] {
        let mut d = SceneDescription::default();
        add_tex(
            &mut d,
            "b",
            TextureType::Float,
            "brick",
            vec![("brickbond", s(bond)), ("mortarsize", f(0.02))],
        );
        let mut set = TextureSet::new(&d, TextureCtx::default());
        let b = float_of(&mut set, "b");
        let (mut brick, mut mortar) = (0, 0);
        for i in 0..400 {
            let p = Vec3A::new(i as f32 * 0.0137, (i * 7 % 400) as f32 * 0.0051, 0.02);
            let v = b.eval(&si_at(0.0, 0.0, p));
            if v == 1.0 {
                brick += 1;
            } else if close(v, 0.2) {
                mortar += 1;
            }
        }
        assert!(
            brick > mortar && mortar > 0,
            "{bond}: {brick} bricks, {mortar} mortar"
        );
        assert!(set.warnings.is_empty(), "{bond}: {:?}", set.warnings);
    }
}

#[test]
fn noise_textures_follow_the_noise_functions() {
    let mut d = SceneDescription::default();
    add_tex(
        &mut d,
        "fbm",
        TextureType::Float,
        "fbm",
        vec![("octaves", int(2)), ("roughness", f(0.25))],
    );
    add_tex(
        &mut d,
        "wr",
        TextureType::Float,
        "wrinkled",
        vec![("octaves", int(1))],
    );
    add_tex(&mut d, "wind", TextureType::Float, "windy", vec![]);
    add_tex(&mut d, "marble", TextureType::Color, "marble", vec![]);
    let mut set = TextureSet::new(&d, TextureCtx::default());
    let p = Vec3A::new(0.31, 1.27, -0.4);
    let si = si_at(0.0, 0.0, p);
    let n = noise::noise_p;
    let expect = n(p) + 0.25 * n(1.99 * p);
    assert!(close(float_of(&mut set, "fbm").eval(&si), expect));
    assert!(close(float_of(&mut set, "wr").eval(&si), n(p).abs()));
    let w = noise::fbm(0.1 * p, 0.5, 3).abs() * noise::fbm(p, 0.5, 6);
    assert!(close(float_of(&mut set, "wind").eval(&si), w));
    // At the origin every octave of noise is 0: sin(0) puts t at 0.5, the start of the
    // spline's fourth segment, LuxRender's grey 0.5, times 1.5.
    let m = color_of(&mut set, "marble").eval(&si_at(0.0, 0.0, Vec3A::ZERO));
    assert!(
        close(m.r, 0.75) && close(m.g, 0.75) && close(m.b, 0.75),
        "{m:?}"
    );
    // Bump derivatives of procedural textures: finite differences over delta along dpdu.
    let fbm = float_of(&mut set, "fbm");
    let d = fbm.duv(&si, 0.001);
    let mut moved = si;
    moved.it.p += Vec3A::X * 0.001;
    let fd = (fbm.eval(&moved) - fbm.eval(&si)) / 0.001;
    assert!(close(d.x, fd), "{d:?} {fd}");
}

#[test]
fn dots_show_the_outside_parameter_in_the_dots_as_luxrender_does() {
    let mut d = SceneDescription::default();
    add_tex(
        &mut d,
        "dots",
        TextureType::Float,
        "dots",
        vec![
            ("inside", f(0.9)),
            ("outside", f(0.1)),
            ("uscale", f(4.0)),
            ("vscale", f(4.0)),
        ],
    );
    let mut set = TextureSet::new(&d, TextureCtx::default());
    let t = float_of(&mut set, "dots");
    let (mut dot, mut rest) = (0, 0);
    for i in 0..64 {
        for j in 0..64 {
            let (u, v) = ((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 64.0);
            let inside = dots::in_dot(4.0 * u, 4.0 * v);
            let val = t.eval(&si_at(u, v, Vec3A::ZERO));
            assert_eq!(val, if inside { 0.1 } else { 0.9 });
            if inside {
                dot += 1;
            } else {
                rest += 1;
            }
        }
    }
    assert!(dot > 0 && rest > dot, "{dot} {rest}");
}

#[test]
fn uvmask_harlequin_hitpoints_colordepth() {
    let mut d = SceneDescription::default();
    add_tex(
        &mut d,
        "mask",
        TextureType::Float,
        "uvmask",
        vec![
            ("innertex", f(0.7)),
            ("outertex", f(0.2)),
            ("udelta", f(0.5)),
        ],
    );
    add_tex(&mut d, "harl", TextureType::Color, "harlequin", vec![]);
    add_tex(&mut d, "hc", TextureType::Color, "hitpointcolor", vec![]);
    add_tex(&mut d, "ha", TextureType::Float, "hitpointalpha", vec![]);
    add_tex(&mut d, "hg", TextureType::Float, "hitpointgrey", vec![]);
    add_tex(
        &mut d,
        "hg1",
        TextureType::Float,
        "hitpointgrey",
        vec![("channel", int(1))],
    );
    add_tex(
        &mut d,
        "cd",
        TextureType::Color,
        "colordepth",
        vec![("Kt", color(0.5, 1.0, 0.0)), ("depth", f(2.0))],
    );
    let mut set = TextureSet::new(&d, TextureCtx::default());
    let mask = float_of(&mut set, "mask");
    // s = u + 0.5: inside for u < 0.5.
    assert!(close(mask.eval(&si_at(0.25, 0.5, Vec3A::ZERO)), 0.7));
    assert!(close(mask.eval(&si_at(0.75, 0.5, Vec3A::ZERO)), 0.2));
    let mut si = si_at(0.0, 0.0, Vec3A::ZERO);
    si.hit.color = [0.2, 0.4, 0.6];
    si.hit.alpha = 0.3;
    assert_eq!(color_of(&mut set, "hc").eval(&si), Rgb::new(0.2, 0.4, 0.6));
    assert_eq!(float_of(&mut set, "ha").eval(&si), 0.3);
    let y = 0.212_671 * 0.2 + 0.715_160 * 0.4 + 0.072_169 * 0.6;
    assert!(close(float_of(&mut set, "hg").eval(&si), y));
    assert_eq!(float_of(&mut set, "hg1").eval(&si), 0.4);
    // Without vertex data: white and alpha 1.
    assert_eq!(
        color_of(&mut set, "hc").eval(&si_at(0.0, 0.0, Vec3A::ZERO)),
        Rgb::WHITE
    );
    // Palette entry 0: radical inverses of 1 in bases 2, 3, 5.
    let h = harlequin::HarlequinTex::new();
    assert_eq!(h.palette[0], Rgb::new(0.5, 1.0 / 3.0, 0.2));
    // Entry 1 (n = 4): 0.001₂ = 0.125, 0.11₃ = 4/9, 0.4₅ = 0.8.
    assert!(close(h.palette[1].r, 0.125) && close(h.palette[1].g, 4.0 / 9.0));
    let harl = color_of(&mut set, "harl");
    let a = harl.eval(&si);
    let mut other = si;
    let mut differs = false;
    for face in 1..8 {
        other.hit.face = face;
        differs |= harl.eval(&other) != a;
    }
    assert!(differs, "faces get different colours");
    // −ln(0.5)/2 = 0.34657; −ln(1)/2 = 0; −ln(1e-9)/2 = 10.36.
    let c = color_of(&mut set, "cd").eval(&si);
    assert!(close(c.r, 0.346_573_6) && c.g == 0.0 && (c.b - 10.361_633).abs() < 1e-3);
}

#[test]
fn checkerboard_aa_modes_are_luxrender_s_point_sampling() {
    let mut d = SceneDescription::default();
    for (name, mode) in [("a", "closedform"), ("b", "supersample"), ("c", "none")] {
        add_tex(
            &mut d,
            name,
            TextureType::Float,
            "checkerboard",
            vec![("aamode", s(mode)), ("uscale", f(2.0))],
        );
    }
    let mut set = TextureSet::new(&d, TextureCtx::default());
    for name in ["a", "b", "c"] {
        let t = float_of(&mut set, name);
        assert_eq!(t.eval(&si_at(0.25, 0.1, Vec3A::ZERO)), 1.0);
        assert_eq!(t.eval(&si_at(0.75, 0.1, Vec3A::ZERO)), 0.0);
    }
    assert!(set.warnings.is_empty(), "{:?}", set.warnings);
    // Derivative at a cell edge: a step of (tex2 − tex1)/delta times ds/du.
    let t = float_of(&mut set, "a");
    let d = t.duv(&si_at(0.5, 0.1, Vec3A::ZERO), 0.001);
    assert!(d.x.abs() > 100.0, "{d:?}");
    assert_eq!(t.duv(&si_at(0.25, 0.1, Vec3A::ZERO), 0.001), Vec2::ZERO);
}

#[test]
fn unused_texture_parameters_are_located_warnings() {
    let mut d = SceneDescription::default();
    add_tex(
        &mut d,
        "t",
        TextureType::Float,
        "fbm",
        vec![("octaves", int(2)), ("roughnes", f(0.2))],
    );
    let mut set = TextureSet::new(&d, TextureCtx::default());
    float_of(&mut set, "t");
    assert_eq!(set.warnings.len(), 1, "{:?}", set.warnings);
    assert!(set.warnings[0].message.contains("roughnes"));
}

/// A one-texel PNG of the given colour.
fn pixel_png(dir: &std::path::Path, name: &str, rgb: [u8; 3]) {
    let mut img = image::RgbImage::new(1, 1);
    img.put_pixel(0, 0, image::Rgb(rgb));
    img.save(dir.join(name)).expect("png written");
}

#[test]
fn normalmap_derivatives_tilt_to_the_map_normal() {
    let dir = temp_dir("normalmap");
    // (191, 128, 255) decodes to n ≈ (0.498, 0.004, 1): the surface leans against +s.
    pixel_png(&dir, "n.png", [191, 128, 255]);
    pixel_png(&dir, "flat.png", [128, 128, 255]);
    let mut d = SceneDescription::default();
    add_tex(
        &mut d,
        "nm",
        TextureType::Float,
        "normalmap",
        vec![("filename", s("n.png"))],
    );
    add_tex(
        &mut d,
        "flat",
        TextureType::Float,
        "normalmap",
        vec![("filename", s("flat.png")), ("uscale", f(-32.0))],
    );
    let mut set = TextureSet::new(
        &d,
        TextureCtx {
            files: dir.clone().into(),
        },
    );
    let nm = float_of(&mut set, "nm");
    let si = si_at(0.3, 0.6, Vec3A::ZERO);
    assert_eq!(nm.eval(&si), 0.0);
    // Height h(s): normal ∝ (−h_s, −h_t, 1), so h_s = −n.x/n.z.
    let nx = 2.0 * 191.0 / 255.0 - 1.0;
    let ny = 2.0 * 128.0 / 255.0 - 1.0;
    let d = nm.duv(&si, 0.001);
    assert!((d.x + nx).abs() < 1e-4 && (d.y + ny).abs() < 1e-4, "{d:?}");
    let flat = float_of(&mut set, "flat").duv(&si, 0.001);
    assert!(flat.length() < 0.2, "{flat:?}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn image_bump_derivative_is_the_slope_per_unit_u_at_any_uscale() {
    let dir = temp_dir("bumpimg");
    // A 4-texel ramp 0, 85, 170, 255 along s (gamma 1): slope 1/3 per texel, 4 texels per
    // unit s, so dh/ds = 4/3 between texel centres.
    let mut img = image::GrayImage::new(4, 1);
    for x in 0..4 {
        img.put_pixel(x, 0, image::Luma([(x * 85) as u8]));
    }
    img.save(dir.join("ramp.png")).expect("png written");
    let mut d = SceneDescription::default();
    for (name, us) in [("one", 1.0), ("neg", -32.0)] {
        add_tex(
            &mut d,
            name,
            TextureType::Float,
            "imagemap",
            vec![
                ("filename", s("ramp.png")),
                ("gamma", f(1.0)),
                ("uscale", f(us)),
                ("wrap", s("clamp")),
            ],
        );
    }
    let mut set = TextureSet::new(
        &d,
        TextureCtx {
            files: dir.clone().into(),
        },
    );
    let one = float_of(&mut set, "one").duv(&si_at(0.5, 0.5, Vec3A::ZERO), 0.001);
    assert!((one.x - 4.0 / 3.0).abs() < 1e-5, "{one:?}");
    assert_eq!(one.y, 0.0);
    // uscale −32 at u = −1/64: s = 0.5 again, and du = −32 · 4/3.
    let neg = float_of(&mut set, "neg").duv(&si_at(-1.0 / 64.0, 0.5, Vec3A::ZERO), 0.001);
    assert!((neg.x + 32.0 * 4.0 / 3.0).abs() < 1e-3, "{neg:?}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn imagemap_filters_white_wrap_and_gamma_after_filtering() {
    let dir = temp_dir("imgfilters");
    let mut img = image::GrayImage::new(2, 1);
    img.put_pixel(0, 0, image::Luma([0]));
    img.put_pixel(1, 0, image::Luma([255]));
    img.save(dir.join("two.png")).expect("png written");
    let mut d = SceneDescription::default();
    let tex = |name: &str, extra: Vec<(&'static str, ParamValue)>, d: &mut SceneDescription| {
        let mut p = vec![("filename", s("two.png"))];
        p.extend(extra);
        add_tex(d, name, TextureType::Float, "imagemap", p);
    };
    tex("g", vec![], &mut d);
    tex(
        "white",
        vec![("wrap", s("white")), ("gamma", f(1.0))],
        &mut d,
    );
    tex(
        "tri",
        vec![("filtertype", s("mipmap_trilinear")), ("gamma", f(1.0))],
        &mut d,
    );
    tex(
        "ewa",
        vec![("filtertype", s("mipmap_ewa")), ("gamma", f(1.0))],
        &mut d,
    );
    let mut set = TextureSet::new(
        &d,
        TextureCtx {
            files: dir.clone().into(),
        },
    );
    // Halfway between the texels: bilinear gives 0.5, then gamma 2.2: 0.5^2.2 = 0.2176.
    let g = float_of(&mut set, "g").eval(&si_at(0.5, 0.5, Vec3A::ZERO));
    assert!(close(g, 0.5f32.powf(2.2)), "{g}");
    // Left of the first texel centre with white outside: lerp(0.5, white 1, texel 0) = 0.5.
    let w = float_of(&mut set, "white").eval(&si_at(0.0, 0.5, Vec3A::ZERO));
    assert!(close(w, 0.5), "{w}");
    // Power-of-two images are used as they are: mipmap kinds read the finest level bilinearly.
    for name in ["tri", "ewa"] {
        let v = float_of(&mut set, name).eval(&si_at(0.5, 0.5, Vec3A::ZERO));
        assert!(close(v, 0.5), "{name}: {v}");
    }
    assert_eq!(set.images_loaded(), 1);
    assert!(set.warnings.is_empty(), "{:?}", set.warnings);
    std::fs::remove_dir_all(&dir).ok();
}
