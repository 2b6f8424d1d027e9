//! Spectral colour textures (blackbody, equalenergy, gaussian, lampspectrum, tabulateddata)
//! and fresnel textures (constant, fresnelcolor, fresnelname, sopra, luxpop, cauchy,
//! sellmeier, and the blends of them): values against hand computations and the data they
//! keep.

use super::super::*;
use super::{add_tex, color_of, f, s, si_at, temp_dir, tex_ref};
use crate::lxs::{ParamValue, SceneDescription, TextureType};
use crate::spectrum::nk::NkTable;
use crate::spectrum::spd::Spd;
use glam::Vec3A;

fn fresnel_of(set: &mut TextureSet, name: &str) -> FresnelTex {
    let mut ps = ParamSet::new();
    ps.add("fresnel", tex_ref(name));
    set.fresnel_param(&ps, "fresnel", 1.5)
        .expect("fresnel texture builds")
}

fn floats(v: &[f32]) -> ParamValue {
    ParamValue::Float(v.to_vec())
}

#[test]
fn spectral_colours_keep_their_spectra() {
    let dir = temp_dir("tabulated");
    std::fs::write(
        dir.join("r.txt"),
        "wavelength: nm data: reflectance\n380 0.5\n720 0.5\n",
    )
    .unwrap();
    let mut d = SceneDescription::default();
    add_tex(
        &mut d,
        "bb",
        TextureType::Color,
        "blackbody",
        vec![("temperature", f(3000.0))],
    );
    add_tex(
        &mut d,
        "ee",
        TextureType::Color,
        "equalenergy",
        vec![("energy", f(2.0))],
    );
    add_tex(
        &mut d,
        "g",
        TextureType::Color,
        "gaussian",
        vec![("wavelength", f(450.0)), ("width", f(20.0))],
    );
    add_tex(
        &mut d,
        "lamp",
        TextureType::Color,
        "lampspectrum",
        vec![("name", s("LPS"))],
    );
    add_tex(
        &mut d,
        "candle",
        TextureType::Color,
        "lampspectrum",
        vec![("name", s("Candle"))],
    );
    add_tex(
        &mut d,
        "tab",
        TextureType::Color,
        "tabulateddata",
        vec![("filename", s("r.txt"))],
    );
    let mut set = TextureSet::new(
        &d,
        TextureCtx {
            files: dir.clone().into(),
        },
    );
    let si = si_at(0.0, 0.0, Vec3A::ZERO);
    assert_eq!(
        color_of(&mut set, "bb").eval(&si),
        crate::spectrum::blackbody(3000.0)
    );
    // Equal energy: twice the RGB of a flat spectrum of 1.
    let ee = color_of(&mut set, "ee").eval(&si);
    let one = Spd::constant(1.0).illuminant_rgb();
    assert!((ee.r - 2.0 * one.r).abs() < 1e-4 && (ee.b - 2.0 * one.b).abs() < 1e-4);
    // A gaussian at 450 nm is blue.
    let g = color_of(&mut set, "g").eval(&si);
    assert!(g.b > g.g && g.b > g.r, "{g:?}");
    let lamp = color_of(&mut set, "lamp");
    assert!(lamp.eval(&si).r > lamp.eval(&si).b);
    match &*lamp.0 {
        TexNode::Spectral(t) => assert_eq!(t.spd.wavelengths().len(), 250),
        other => panic!("{other:?}"),
    }
    // LuxRender renders its Candle preset as a 1020 K blackbody.
    assert_eq!(
        color_of(&mut set, "candle").eval(&si),
        crate::spectrum::blackbody(1020.0)
    );
    // A flat reflectance of 0.5: grey 0.5.
    let t = color_of(&mut set, "tab").eval(&si);
    assert!(
        (t.r - 0.5).abs() < 0.01 && (t.b - 0.5).abs() < 0.01,
        "{t:?}"
    );
    assert!(set.warnings.is_empty(), "{:?}", set.warnings);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn unknown_lamps_and_unreadable_data_follow_luxrender() {
    let dir = temp_dir("tabulated2");
    std::fs::write(dir.join("short.txt"), "500 1\n").unwrap();
    let mut d = SceneDescription::default();
    add_tex(
        &mut d,
        "x",
        TextureType::Color,
        "lampspectrum",
        vec![("name", s("Torch"))],
    );
    add_tex(
        &mut d,
        "short",
        TextureType::Color,
        "tabulateddata",
        vec![("filename", s("short.txt"))],
    );
    add_tex(
        &mut d,
        "missing",
        TextureType::Color,
        "tabulateddata",
        vec![("filename", s("nope.txt"))],
    );
    let mut set = TextureSet::new(
        &d,
        TextureCtx {
            files: dir.clone().into(),
        },
    );
    let si = si_at(0.0, 0.0, Vec3A::ZERO);
    assert_eq!(
        color_of(&mut set, "x").eval(&si),
        crate::spectrum::blackbody(2900.0)
    );
    assert_eq!(set.warnings.len(), 1);
    let short = color_of(&mut set, "short").eval(&si);
    assert!((short.g - 1.0).abs() < 0.01, "{short:?}");
    assert_eq!(set.warnings.len(), 2);
    let mut ps = ParamSet::new();
    ps.add("Kd", tex_ref("missing"));
    assert!(set.color_param(&ps, "Kd", Rgb::BLACK).is_err());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn fresnel_textures() {
    let dir = temp_dir("nk");
    std::fs::write(dir.join("m.nk"), "; luxpop\n4000 1.2 3.0\n7000 1.6 4.0\n").unwrap();
    let mut d = SceneDescription::default();
    add_tex(
        &mut d,
        "c",
        TextureType::Fresnel,
        "constant",
        vec![("value", f(1.33))],
    );
    add_tex(
        &mut d,
        "col",
        TextureType::Fresnel,
        "fresnelcolor",
        vec![("Kr", ParamValue::Color(vec![[0.5, 0.5, 0.5]]))],
    );
    add_tex(
        &mut d,
        "gold",
        TextureType::Fresnel,
        "fresnelname",
        vec![("name", s("gold"))],
    );
    add_tex(
        &mut d,
        "file",
        TextureType::Fresnel,
        "fresnelname",
        vec![("filename", s("m.nk"))],
    );
    add_tex(
        &mut d,
        "lp",
        TextureType::Fresnel,
        "luxpop",
        vec![("filename", s("m.nk"))],
    );
    add_tex(
        &mut d,
        "cauchy",
        TextureType::Fresnel,
        "cauchy",
        vec![("cauchya", f(1.5)), ("cauchyb", f(0.0042))],
    );
    add_tex(
        &mut d,
        "cauchy_index",
        TextureType::Fresnel,
        "cauchy",
        vec![("index", f(1.6)), ("cauchyb", f(0.01))],
    );
    add_tex(
        &mut d,
        "sell",
        TextureType::Fresnel,
        "sellmeier",
        vec![
            ("B", floats(&[1.039_612, 0.231_792_3, 1.010_469_5])),
            ("C", floats(&[0.006_000_699, 0.020_017_914, 103.560_65])),
        ],
    );
    add_tex(
        &mut d,
        "mix",
        TextureType::Fresnel,
        "mix",
        vec![
            ("tex1", tex_ref("c")),
            ("tex2", tex_ref("gold")),
            ("amount", f(0.25)),
        ],
    );
    add_tex(
        &mut d,
        "scale",
        TextureType::Fresnel,
        "scale",
        vec![("tex1", f(2.0)), ("tex2", tex_ref("c"))],
    );
    add_tex(
        &mut d,
        "band",
        TextureType::Fresnel,
        "band",
        vec![
            ("offsets", floats(&[0.0, 1.0])),
            ("tex1", tex_ref("c")),
            ("tex2", f(2.0)),
            ("amount", f(0.5)),
        ],
    );
    add_tex(
        &mut d,
        "bilerp",
        TextureType::Fresnel,
        "bilerp",
        vec![
            ("v00", f(1.0)),
            ("v01", f(1.0)),
            ("v10", f(3.0)),
            ("v11", f(3.0)),
        ],
    );
    add_tex(
        &mut d,
        "mm",
        TextureType::Fresnel,
        "multimix",
        vec![
            ("weights", floats(&[0.5, 0.5])),
            ("tex1", f(1.0)),
            ("tex2", f(2.0)),
        ],
    );
    let mut set = TextureSet::new(
        &d,
        TextureCtx {
            files: dir.clone().into(),
        },
    );
    let si = si_at(0.25, 0.5, Vec3A::ZERO);
    assert_eq!(
        fresnel_of(&mut set, "c").eval(&si),
        Fresnel::dielectric(1.33)
    );
    let col = fresnel_of(&mut set, "col").eval(&si);
    assert!((col.n.g - 5.828_427).abs() < 1e-3 && (col.k.g - 2.0).abs() < 1e-4);
    let gold = fresnel_of(&mut set, "gold");
    let (n, k) = NkTable::preset("gold").unwrap().to_rgb();
    let g = gold.eval(&si);
    assert!(
        (g.n.r - n[0]).abs() < 1e-4 && (g.k.b - k[2]).abs() < 1e-4,
        "{g:?}"
    );
    assert!(matches!(gold.data(), Some(FresnelData::Table(_))));
    // The luxpop file (Ångström): n 1.2 → 1.6 and k 3 → 4 over 400–700 nm; the green band
    // (490–580 nm) averages n at 535 nm: 1.2 + 0.4·135/300 = 1.38. An absorbing table: the
    // texture's RGB value is the table's reading fitted to its reflectance.
    let file_tex = fresnel_of(&mut set, "file");
    let Some(FresnelData::Table(t)) = file_tex.data() else {
        panic!("a table");
    };
    assert!((t.band_averages().0[1] - 1.38).abs() < 1e-3);
    let file = file_tex.eval(&si);
    let (fn_, fk) = t.to_rgb();
    assert_eq!((file.n.to_array(), file.k.to_array()), (fn_, fk));
    assert_eq!(fresnel_of(&mut set, "lp").eval(&si), file);
    let c = fresnel_of(&mut set, "cauchy");
    assert!(matches!(c.data(), Some(FresnelData::Cauchy { .. })));
    assert!(c.eval(&si).n.b > c.eval(&si).n.r);
    // With `index` 1.6: a = 1.6 − 0.01/(0.38·0.72), so n(√(380·720) nm) = 1.6.
    match fresnel_of(&mut set, "cauchy_index").data() {
        Some(d @ FresnelData::Cauchy { .. }) => {
            let mid = (380.0f32 * 720.0).sqrt();
            assert!((d.at(mid).0 - 1.6).abs() < 1e-5);
        }
        other => panic!("{other:?}"),
    }
    let sell = fresnel_of(&mut set, "sell");
    assert!(
        (sell.eval(&si).n.g - 1.518).abs() < 0.003,
        "{:?}",
        sell.eval(&si)
    );
    let mix = fresnel_of(&mut set, "mix").eval(&si);
    assert!((mix.n.r - (0.75 * 1.33 + 0.25 * n[0])).abs() < 1e-4);
    assert!((mix.k.r - 0.25 * k[0]).abs() < 1e-4);
    assert_eq!(fresnel_of(&mut set, "scale").eval(&si).n, Rgb::splat(2.66));
    let band = fresnel_of(&mut set, "band").eval(&si);
    assert!((band.n.r - (1.33 + 2.0) / 2.0).abs() < 1e-5);
    // s = 0.25 between v00/v01 = 1 and v10/v11 = 3: 1.5.
    assert!((fresnel_of(&mut set, "bilerp").eval(&si).n.r - 1.5).abs() < 1e-5);
    assert!((fresnel_of(&mut set, "mm").eval(&si).n.r - 1.5).abs() < 1e-5);
    // A plain float is a dielectric index; absent, the default.
    let mut ps = ParamSet::new();
    ps.add("fresnel", f(1.2));
    assert_eq!(
        set.fresnel_param(&ps, "fresnel", 1.5).unwrap().as_const(),
        Some(Fresnel::dielectric(1.2))
    );
    assert_eq!(
        set.fresnel_param(&ParamSet::new(), "fresnel", 1.5)
            .unwrap()
            .as_const(),
        Some(Fresnel::dielectric(1.5))
    );
    assert!(set.warnings.is_empty(), "{:?}", set.warnings);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn fresnel_types_are_their_own_namespace() {
    let mut d = SceneDescription::default();
    add_tex(&mut d, "fb", TextureType::Float, "fbm", vec![]);
    add_tex(&mut d, "cy", TextureType::Float, "cauchy", vec![]);
    add_tex(&mut d, "wrong", TextureType::Fresnel, "fbm", vec![]);
    let mut set = TextureSet::new(&d, TextureCtx::default());
    let mut ps = ParamSet::new();
    ps.add("fresnel", tex_ref("fb"));
    assert!(matches!(
        set.fresnel_param(&ps, "fresnel", 1.5),
        Err(TextureError::WrongType { .. })
    ));
    let mut ps = ParamSet::new();
    ps.add("x", tex_ref("cy"));
    assert!(matches!(
        set.float_param(&ps, "x", 0.0),
        Err(TextureError::UnknownClass { .. })
    ));
    let mut ps = ParamSet::new();
    ps.add("fresnel", tex_ref("wrong"));
    let e = set.fresnel_param(&ps, "fresnel", 1.5).unwrap_err();
    assert!(
        e.to_string()
            .contains("unknown fresnel texture class \"fbm\""),
        "{e}"
    );
}

#[test]
fn index_at_a_wavelength_through_combinations() {
    let mut d = SceneDescription::default();
    add_tex(
        &mut d,
        "c",
        TextureType::Fresnel,
        "cauchy",
        vec![("cauchya", f(1.5)), ("cauchyb", f(0.05))],
    );
    add_tex(
        &mut d,
        "c0",
        TextureType::Fresnel,
        "cauchy",
        vec![("cauchya", f(1.4))],
    );
    add_tex(
        &mut d,
        "m",
        TextureType::Fresnel,
        "mix",
        vec![
            ("tex1", tex_ref("c")),
            ("tex2", f(1.0)),
            ("amount", f(0.25)),
        ],
    );
    add_tex(
        &mut d,
        "s",
        TextureType::Fresnel,
        "scale",
        vec![("tex1", f(2.0)), ("tex2", tex_ref("c0"))],
    );
    let mut set = TextureSet::new(&d, TextureCtx::default());
    let si = si_at(0.5, 0.5, Vec3A::ZERO);
    // Cauchy at 500 nm: 1.5 + 0.05 / 0.25 = 1.7; at 400 nm 1.5 + 0.05 / 0.16 = 1.8125.
    let c = fresnel_of(&mut set, "c");
    assert!((c.0.index_at(&si, 500.0) - 1.7).abs() < 1e-5);
    assert!(c.0.disperses());
    // mix: 0.75 × 1.7 + 0.25 × 1 at 500 nm.
    let m = fresnel_of(&mut set, "m");
    assert!((m.0.index_at(&si, 500.0) - 1.525).abs() < 1e-5);
    assert!((m.0.index_at(&si, 400.0) - (0.75 * 1.8125 + 0.25)).abs() < 1e-5);
    assert!(m.0.disperses());
    // Cauchy's law with b = 0 and a scale of it do not depend on the wavelength.
    let s = fresnel_of(&mut set, "s");
    assert!((s.0.index_at(&si, 450.0) - 2.8).abs() < 1e-5);
    assert!(!s.0.disperses() && !fresnel_of(&mut set, "c0").0.disperses());
    // A constant reads its channel by band: blue below 490 nm, red from 580 nm.
    let rgb = FresnelNode::Const(Fresnel {
        n: crate::spectrum::Rgb::new(1.4, 1.5, 1.6),
        k: crate::spectrum::Rgb::splat(0.0),
    });
    assert_eq!(rgb.index_at(&si, 450.0), 1.6);
    assert_eq!(rgb.index_at(&si, 500.0), 1.5);
    assert_eq!(rgb.index_at(&si, 650.0), 1.4);
    assert!(rgb.disperses());
}
