//! Texture tests: checkerboards, arithmetic textures, imagemaps from generated PNG and EXR
//! files with every wrap and filter mode, on-demand building and error locations; the other
//! classes in [`classes`] (procedural and blending textures, hand-computed values), the
//! spectral and fresnel ones in [`optics`].

mod blender;
mod classes;
mod optics;

use super::mapping::Mapping2D;
use super::*;
use crate::lxs::{Entity, Loc, ParamValue, SceneDescription, TextureDesc, TextureType, Xform};
use glam::{DMat4, DVec3, Vec2, Vec3A};

pub(crate) fn loc(line: u32) -> Loc {
    Loc {
        file: Arc::from("scene.lxs"),
        line,
        col: 1,
    }
}

pub(crate) fn si_at(u: f32, v: f32, p: Vec3A) -> SurfaceInteraction {
    let mut si = SurfaceInteraction {
        uv: Vec2::new(u, v),
        ..Default::default()
    };
    si.it.p = p;
    si.it.n = Vec3A::Z;
    si.shading.n = Vec3A::Z;
    si.shading.dpdu = Vec3A::X;
    si.shading.dpdv = Vec3A::Y;
    si.dpdu = Vec3A::X;
    si.dpdv = Vec3A::Y;
    si
}

/// Adds a texture declaration to `desc`.
pub(crate) fn add_tex(
    desc: &mut SceneDescription,
    name: &str,
    ty: TextureType,
    class: &str,
    params: Vec<(&str, ParamValue)>,
) {
    let mut ps = ParamSet::new();
    for (n, v) in params {
        ps.add(n, v);
    }
    let line = desc.textures.len() as u32 + 1;
    desc.textures.push(TextureDesc {
        name: name.to_string(),
        value_type: ty,
        entity: Entity {
            kind: class.to_string(),
            params: ps,
            loc: loc(line),
        },
        object_to_world: Xform::identity(),
    });
    desc.named_textures
        .insert((ty, name.to_string()), desc.textures.len() - 1);
}

pub(crate) fn f(v: f32) -> ParamValue {
    ParamValue::Float(vec![v])
}

pub(crate) fn s(v: &str) -> ParamValue {
    ParamValue::String(vec![v.to_string()])
}

pub(crate) fn tex_ref(name: &str) -> ParamValue {
    ParamValue::Texture(name.to_string())
}

pub(crate) fn color_of(set: &mut TextureSet, name: &str) -> ColorTex {
    let mut ps = ParamSet::new();
    ps.add("Kd", tex_ref(name));
    set.color_param(&ps, "Kd", Rgb::BLACK)
        .expect("texture builds")
}

pub(crate) fn float_of(set: &mut TextureSet, name: &str) -> FloatTex {
    let mut ps = ParamSet::new();
    ps.add("x", tex_ref(name));
    set.float_param(&ps, "x", 0.0).expect("texture builds")
}

#[test]
fn checkerboard_2d_and_3d() {
    let mut d = SceneDescription::default();
    add_tex(
        &mut d,
        "c2",
        TextureType::Float,
        "checkerboard",
        vec![("uscale", f(4.0)), ("vscale", f(4.0))],
    );
    add_tex(
        &mut d,
        "c3",
        TextureType::Float,
        "checkerboard",
        vec![
            ("dimension", ParamValue::Integer(vec![3])),
            ("tex1", f(0.25)),
            ("tex2", f(0.75)),
        ],
    );
    let mut set = TextureSet::new(&d, TextureCtx::default());
    let c2 = float_of(&mut set, "c2");
    assert_eq!(c2.eval(&si_at(0.1, 0.1, Vec3A::ZERO)), 1.0);
    assert_eq!(c2.eval(&si_at(0.3, 0.1, Vec3A::ZERO)), 0.0);
    assert_eq!(c2.eval(&si_at(0.3, 0.3, Vec3A::ZERO)), 1.0);
    assert_eq!(c2.eval(&si_at(-0.1, 0.1, Vec3A::ZERO)), 0.0);
    let c3 = float_of(&mut set, "c3");
    assert_eq!(c3.eval(&si_at(0.0, 0.0, Vec3A::new(0.5, 0.5, 0.5))), 0.25);
    assert_eq!(c3.eval(&si_at(0.0, 0.0, Vec3A::new(1.5, 0.5, 0.5))), 0.75);
    assert_eq!(c3.eval(&si_at(0.0, 0.0, Vec3A::new(1.5, -0.5, 0.5))), 0.25);
}

#[test]
fn checkerboard_3d_mapping_options() {
    let mut d = SceneDescription::default();
    add_tex(
        &mut d,
        "c3",
        TextureType::Float,
        "checkerboard",
        vec![
            ("dimension", ParamValue::Integer(vec![3])),
            ("coordinates", s("local")),
            ("scale", ParamValue::Vector(vec![[0.1, 0.1, 0.1]])),
            ("translate", ParamValue::Vector(vec![[0.05, 0.0, 0.0]])),
        ],
    );
    let mut set = TextureSet::new(&d, TextureCtx::default());
    let c3 = float_of(&mut set, "c3");
    // Cells are 0.1 wide, shifted by 0.05 along x.
    assert_eq!(c3.eval(&si_at(0.0, 0.0, Vec3A::new(0.07, 0.05, 0.05))), 1.0);
    assert_eq!(c3.eval(&si_at(0.0, 0.0, Vec3A::new(0.03, 0.05, 0.05))), 0.0);
    assert_eq!(c3.eval(&si_at(0.0, 0.0, Vec3A::new(0.16, 0.05, 0.05))), 0.0);
    // `local` without transformed shapes is the world point; nothing to warn about.
    assert!(set.warnings.is_empty(), "{:?}", set.warnings);
}

#[test]
fn checkerboard_3d_uses_the_texture_transform() {
    let mut d = SceneDescription::default();
    add_tex(
        &mut d,
        "c3",
        TextureType::Float,
        "checkerboard",
        vec![("dimension", ParamValue::Integer(vec![3]))],
    );
    d.textures[0].object_to_world = Xform::fixed(DMat4::from_scale(DVec3::splat(2.0)));
    let mut set = TextureSet::new(&d, TextureCtx::default());
    let c3 = float_of(&mut set, "c3");
    // LuxRender's 3D mappings take the declaration's transform as world-to-texture: under
    // Scale 2 world x = 0.6 is texture x = 1.2, the second cell.
    assert_eq!(c3.eval(&si_at(0.0, 0.0, Vec3A::new(0.2, 0.2, 0.2))), 1.0);
    assert_eq!(c3.eval(&si_at(0.0, 0.0, Vec3A::new(0.6, 0.2, 0.2))), 0.0);
    assert_eq!(c3.eval(&si_at(0.0, 0.0, Vec3A::new(1.1, 0.2, 0.2))), 1.0);
}

#[test]
fn arithmetic_textures_and_parameter_forms() {
    let mut d = SceneDescription::default();
    let c = |r, g, b| ParamValue::Color(vec![[r, g, b]]);
    add_tex(
        &mut d,
        "a",
        TextureType::Color,
        "constant",
        vec![("value", c(0.2, 0.4, 0.6))],
    );
    add_tex(
        &mut d,
        "half",
        TextureType::Float,
        "constant",
        vec![("value", f(0.5))],
    );
    add_tex(
        &mut d,
        "sc",
        TextureType::Color,
        "scale",
        vec![("tex1", tex_ref("a")), ("tex2", f(2.0))],
    );
    add_tex(
        &mut d,
        "ad",
        TextureType::Color,
        "add",
        vec![("tex1", tex_ref("a")), ("tex2", c(0.1, 0.1, 0.1))],
    );
    add_tex(
        &mut d,
        "sb",
        TextureType::Color,
        "subtract",
        vec![("tex1", tex_ref("a")), ("tex2", f(0.1))],
    );
    add_tex(
        &mut d,
        "mx",
        TextureType::Color,
        "mix",
        vec![
            ("amount", tex_ref("half")),
            ("tex1", tex_ref("a")),
            ("tex2", c(1.0, 1.0, 1.0)),
        ],
    );
    add_tex(
        &mut d,
        "bb",
        TextureType::Color,
        "blackbody",
        vec![("temperature", f(6500.0))],
    );
    let mut set = TextureSet::new(&d, TextureCtx::default());
    let si = si_at(0.5, 0.5, Vec3A::ZERO);
    let close = |a: Rgb, b: Rgb| (0..3).all(|i| (a[i] - b[i]).abs() < 1e-6);
    assert!(close(
        color_of(&mut set, "sc").eval(&si),
        Rgb::new(0.4, 0.8, 1.2)
    ));
    assert!(close(
        color_of(&mut set, "ad").eval(&si),
        Rgb::new(0.3, 0.5, 0.7)
    ));
    assert!(close(
        color_of(&mut set, "sb").eval(&si),
        Rgb::new(0.1, 0.3, 0.5)
    ));
    assert!(close(
        color_of(&mut set, "mx").eval(&si),
        Rgb::new(0.6, 0.7, 0.8)
    ));
    assert!(close(
        color_of(&mut set, "bb").eval(&si),
        crate::spectrum::blackbody(6500.0)
    ));
    // A colour parameter given as a float is grey; absent, the default.
    let mut ps = ParamSet::new();
    ps.add("Kd", f(0.3));
    let g = set.color_param(&ps, "Kd", Rgb::WHITE).unwrap();
    assert_eq!(g.as_const(), Some(Rgb::splat(0.3)));
    let dflt = set
        .color_param(&ParamSet::new(), "Kd", Rgb::splat(0.9))
        .unwrap();
    assert_eq!(dflt.as_const(), Some(Rgb::splat(0.9)));
}

#[test]
fn unknown_class_and_missing_names_are_located_errors() {
    let mut d = SceneDescription::default();
    add_tex(&mut d, "w", TextureType::Float, "wood", vec![]);
    let mut set = TextureSet::new(&d, TextureCtx::default());
    let mut ps = ParamSet::new();
    ps.push(crate::lxs::Param::new("x", tex_ref("w"), loc(9)));
    let e = set.float_param(&ps, "x", 0.0).unwrap_err();
    assert_eq!(
        e.to_string(),
        "scene.lxs:1:1: unknown float texture class \"wood\""
    );
    let mut ps = ParamSet::new();
    ps.push(crate::lxs::Param::new("x", tex_ref("nope"), loc(9)));
    let e = set.color_param(&ps, "x", Rgb::BLACK).unwrap_err();
    assert_eq!(
        e.to_string(),
        "scene.lxs:9:1: no color texture named \"nope\""
    );
}

#[test]
fn self_reference_is_a_cycle_error() {
    let mut d = SceneDescription::default();
    add_tex(
        &mut d,
        "s",
        TextureType::Float,
        "scale",
        vec![("tex1", tex_ref("s"))],
    );
    let mut set = TextureSet::new(&d, TextureCtx::default());
    let mut ps = ParamSet::new();
    ps.add("x", tex_ref("s"));
    assert!(matches!(
        set.float_param(&ps, "x", 0.0),
        Err(TextureError::Cycle { .. })
    ));
}

pub(crate) fn temp_dir(tag: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("luxfarm-tex-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// A 2x2 image: top row red, green; bottom row blue, white (8-bit 0/255 values).
fn write_png(dir: &std::path::Path) {
    let mut img = image::RgbImage::new(2, 2);
    img.put_pixel(0, 0, image::Rgb([255, 0, 0]));
    img.put_pixel(1, 0, image::Rgb([0, 255, 0]));
    img.put_pixel(0, 1, image::Rgb([0, 0, 255]));
    img.put_pixel(1, 1, image::Rgb([255, 255, 255]));
    img.save(dir.join("t.png")).expect("png written");
}

fn write_exr(dir: &std::path::Path) {
    let px = [
        [2.0f32, 0.0, 0.0],
        [0.0, 2.0, 0.0],
        [0.0, 0.0, 2.0],
        [2.0, 2.0, 2.0],
    ];
    exr::prelude::write_rgb_file(dir.join("t.exr"), 2, 2, |x, y| {
        let p = px[y * 2 + x];
        (p[0], p[1], p[2])
    })
    .expect("exr written");
}

fn imagemap(d: &mut SceneDescription, name: &str, file: &str, extra: Vec<(&str, ParamValue)>) {
    let mut params = vec![("filename", s(file)), ("gamma", f(1.0))];
    params.extend(extra);
    add_tex(d, name, TextureType::Color, "imagemap", params);
}

#[test]
fn imagemap_png_nearest_bilinear_and_wrap_modes() {
    let dir = temp_dir("png");
    write_png(&dir);
    let mut d = SceneDescription::default();
    imagemap(&mut d, "near", "t.png", vec![("filtertype", s("nearest"))]);
    imagemap(&mut d, "bil", "t.png", vec![]);
    imagemap(
        &mut d,
        "black",
        "t.png",
        vec![("filtertype", s("nearest")), ("wrap", s("black"))],
    );
    imagemap(
        &mut d,
        "clamp",
        "t.png",
        vec![("filtertype", s("nearest")), ("wrap", s("clamp"))],
    );
    imagemap(
        &mut d,
        "gain",
        "t.png",
        vec![("filtertype", s("nearest")), ("gain", f(0.5))],
    );
    imagemap(
        &mut d,
        "gamma",
        "t.png",
        vec![("filtertype", s("nearest")), ("gamma", f(2.2))],
    );
    let mut set = TextureSet::new(
        &d,
        TextureCtx {
            files: dir.clone().into(),
        },
    );
    let at = |t: &ColorTex, u: f32, v: f32| t.eval(&si_at(u, v, Vec3A::ZERO));
    let near = color_of(&mut set, "near");
    // t = 0 is the top row.
    assert_eq!(at(&near, 0.25, 0.75), Rgb::new(0.0, 0.0, 1.0));
    assert_eq!(at(&near, 0.75, 0.75), Rgb::WHITE);
    assert_eq!(at(&near, 0.25, 0.25), Rgb::new(1.0, 0.0, 0.0));
    assert_eq!(at(&near, 0.75, 0.25), Rgb::new(0.0, 1.0, 0.0));
    // Repeat wraps.
    assert_eq!(at(&near, 1.25, 0.25), Rgb::new(1.0, 0.0, 0.0));
    let bil = color_of(&mut set, "bil");
    let c = at(&bil, 0.5, 0.5);
    assert!((c.r - 0.5).abs() < 1e-5 && (c.g - 0.5).abs() < 1e-5 && (c.b - 0.5).abs() < 1e-5);
    let black = color_of(&mut set, "black");
    assert_eq!(at(&black, 1.25, 0.25), Rgb::BLACK);
    assert_eq!(at(&black, 0.25, 0.25), Rgb::new(1.0, 0.0, 0.0));
    let clamp = color_of(&mut set, "clamp");
    assert_eq!(at(&clamp, 1.75, 0.25), Rgb::new(0.0, 1.0, 0.0));
    assert_eq!(at(&clamp, -3.0, 3.0), Rgb::new(0.0, 0.0, 1.0));
    assert_eq!(at(&color_of(&mut set, "gain"), 0.75, 0.75), Rgb::splat(0.5));
    assert_eq!(set.images_loaded(), 1);
    assert_eq!(at(&color_of(&mut set, "gamma"), 0.75, 0.75), Rgb::WHITE);
    assert_eq!(
        set.images_loaded(),
        1,
        "gain and gamma apply to lookups: one file"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn imagemap_exr_and_float_channels() {
    let dir = temp_dir("exr");
    write_exr(&dir);
    let mut d = SceneDescription::default();
    imagemap(&mut d, "c", "t.exr", vec![("filtertype", s("nearest"))]);
    add_tex(
        &mut d,
        "g",
        TextureType::Float,
        "imagemap",
        vec![
            ("filename", s("t.exr")),
            ("gamma", f(1.0)),
            ("channel", s("green")),
            ("filtertype", s("nearest")),
        ],
    );
    add_tex(
        &mut d,
        "m",
        TextureType::Float,
        "imagemap",
        vec![
            ("filename", s("t.exr")),
            ("gamma", f(1.0)),
            ("filtertype", s("nearest")),
        ],
    );
    let mut set = TextureSet::new(
        &d,
        TextureCtx {
            files: dir.clone().into(),
        },
    );
    let c = color_of(&mut set, "c");
    assert_eq!(
        c.eval(&si_at(0.25, 0.25, Vec3A::ZERO)),
        Rgb::new(2.0, 0.0, 0.0)
    );
    assert_eq!(c.eval(&si_at(0.75, 0.75, Vec3A::ZERO)), Rgb::splat(2.0));
    let g = float_of(&mut set, "g");
    assert_eq!(g.eval(&si_at(0.75, 0.25, Vec3A::ZERO)), 2.0);
    assert_eq!(g.eval(&si_at(0.25, 0.25, Vec3A::ZERO)), 0.0);
    let m = float_of(&mut set, "m");
    assert!((m.eval(&si_at(0.25, 0.25, Vec3A::ZERO)) - 2.0 / 3.0).abs() < 1e-6);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn unreferenced_images_are_never_loaded_and_missing_files_are_errors() {
    let dir = temp_dir("lazy");
    write_png(&dir);
    let mut d = SceneDescription::default();
    imagemap(&mut d, "used", "t.png", vec![]);
    imagemap(&mut d, "unused", "does-not-exist.png", vec![]);
    let mut set = TextureSet::new(
        &d,
        TextureCtx {
            files: dir.clone().into(),
        },
    );
    color_of(&mut set, "used");
    assert_eq!(set.images_loaded(), 1);
    assert_eq!(set.built_names(), vec!["used".to_string()]);
    let mut ps = ParamSet::new();
    ps.add("Kd", tex_ref("unused"));
    let e = set.color_param(&ps, "Kd", Rgb::BLACK).unwrap_err();
    assert!(matches!(e, TextureError::Image { .. }), "{e}");
    assert!(
        e.to_string()
            .starts_with("scene.lxs:2:1: cannot load image"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn uv_texture_and_mappings() {
    let mut d = SceneDescription::default();
    add_tex(
        &mut d,
        "uv",
        TextureType::Color,
        "uv",
        vec![("uscale", f(2.0)), ("vscale", f(1.0)), ("udelta", f(0.1))],
    );
    add_tex(
        &mut d,
        "planar",
        TextureType::Color,
        "uv",
        vec![("mapping", s("planar")), ("udelta", f(0.25))],
    );
    add_tex(
        &mut d,
        "bad",
        TextureType::Color,
        "uv",
        vec![("mapping", s("cubic"))],
    );
    let mut set = TextureSet::new(&d, TextureCtx::default());
    let c = color_of(&mut set, "uv").eval(&si_at(0.3, 0.4, Vec3A::ZERO));
    assert!((c.r - 0.7).abs() < 1e-6 && (c.g - 0.4).abs() < 1e-6);
    let p = color_of(&mut set, "planar").eval(&si_at(0.0, 0.0, Vec3A::new(0.5, 0.125, 9.0)));
    assert!((p.r - 0.75).abs() < 1e-6 && (p.g - 0.125).abs() < 1e-6);
    // Spherical: s from the azimuth, t from the polar angle.
    let mut sd = d.textures[0].clone();
    sd.entity.params = ParamSet::new();
    sd.entity.params.add("mapping", s("spherical"));
    let m = Mapping2D::from_params(&sd).unwrap();
    let st = m.map(&si_at(0.0, 0.0, Vec3A::new(0.0, 1.0, 0.0)));
    assert!(
        (st.x - 0.25).abs() < 1e-6 && (st.y - 0.5).abs() < 1e-6,
        "{st:?}"
    );
    sd.entity.params = ParamSet::new();
    sd.entity.params.add("mapping", s("cylindrical"));
    let m = Mapping2D::from_params(&sd).unwrap();
    let st = m.map(&si_at(0.0, 0.0, Vec3A::new(-2.0, 0.0, 0.5)));
    assert!(
        (st.x - 0.5).abs() < 1e-6 && (st.y - 0.25).abs() < 1e-6,
        "{st:?}"
    );
    let mut ps = ParamSet::new();
    ps.add("Kd", tex_ref("bad"));
    assert!(matches!(
        set.color_param(&ps, "Kd", Rgb::BLACK),
        Err(TextureError::BadParam { .. })
    ));
}
