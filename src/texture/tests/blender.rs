//! The `blender_*` textures: hand-computed values of the closed-form patterns (blend, magic,
//! wood waves, brightness/contrast), the noise patterns against the noise library, parameter
//! spellings and fallbacks, and the bump derivative.

use super::super::blender::noiselib::{self, Fractal, NoiseBasis};
use super::super::*;
use super::{add_tex, f, float_of, s, si_at};
use crate::lxs::{ParamValue, SceneDescription, TextureType};
use glam::Vec3A;

fn int(v: i32) -> ParamValue {
    ParamValue::Integer(vec![v])
}

fn close(a: f32, b: f32) -> bool {
    (a - b).abs() < 1e-5
}

fn value(d: &SceneDescription, name: &str, p: Vec3A) -> f32 {
    let mut set = TextureSet::new(d, TextureCtx::default());
    let t = float_of(&mut set, name);
    assert!(set.warnings.is_empty(), "{name}: {:?}", set.warnings);
    t.eval(&si_at(0.0, 0.0, p))
}

#[test]
fn blend_types_and_brightness_contrast() {
    let mut d = SceneDescription::default();
    for ty in ["lin", "quad", "ease", "diag", "sphere", "halo", "radial"] {
        add_tex(
            &mut d,
            ty,
            TextureType::Float,
            "blender_blend",
            vec![("type", s(ty))],
        );
    }
    add_tex(
        &mut d,
        "flip",
        TextureType::Float,
        "blender_blend",
        vec![("flipxy", ParamValue::Bool(vec![true]))],
    );
    add_tex(
        &mut d,
        "bc",
        TextureType::Float,
        "blender_blend",
        vec![("contrast", f(2.0)), ("bright", f(1.1))],
    );
    add_tex(
        &mut d,
        "lerp",
        TextureType::Float,
        "blender_blend",
        vec![("tex1", f(0.2)), ("tex2", f(0.6))],
    );
    let p = |x, y, z| Vec3A::new(x, y, z);
    assert!(close(value(&d, "lin", p(0.5, 0.0, 0.0)), 0.75));
    assert!(close(value(&d, "quad", p(0.0, 0.0, 0.0)), 0.25));
    // ease at t = ½: 3·¼ − 2·⅛ = ½.
    assert!(close(value(&d, "ease", p(0.0, 0.0, 0.0)), 0.5));
    assert!(close(value(&d, "diag", p(0.2, 0.6, 0.0)), 0.7));
    assert!(close(value(&d, "sphere", p(0.3, 0.4, 0.0)), 0.5));
    assert!(close(value(&d, "halo", p(0.3, 0.4, 0.0)), 0.25));
    // radial at (0, 1): atan2(1, 0)/2π + ½ = ¾.
    assert!(close(value(&d, "radial", p(0.0, 1.0, 0.0)), 0.75));
    assert!(close(value(&d, "flip", p(0.0, 0.5, 0.0)), 0.75));
    // (½ − ½)·2 + 1.1 − ½ = 0.6.
    assert!(close(value(&d, "bc", p(0.0, 0.0, 0.0)), 0.6));
    // lerp(0.75, 0.2, 0.6) = 0.5.
    assert!(close(value(&d, "lerp", p(0.5, 0.0, 0.0)), 0.5));
}

#[test]
fn magic_at_depth_zero_and_wood_waves() {
    let mut d = SceneDescription::default();
    add_tex(
        &mut d,
        "magic",
        TextureType::Float,
        "blender_magic",
        vec![("noisedepth", int(0)), ("turbulence", f(5.0))],
    );
    for (name, wave) in [("sin", "sin"), ("saw", "saw"), ("tri", "tri")] {
        add_tex(
            &mut d,
            name,
            TextureType::Float,
            "blender_wood",
            vec![("noisebasis2", s(wave))],
        );
    }
    add_tex(
        &mut d,
        "rings",
        TextureType::Float,
        "blender_wood",
        vec![("type", s("rings"))],
    );
    let p = Vec3A::new(0.1, 0.2, 0.05);
    // Depth 0, turbulence 5: turb = 1, then 2 at the end:
    // x = sin(5·0.35)/2, y = cos(5·0.05)/2, z = −cos(5·(−0.25))/2; rgb = ½ − (x, y, z),
    // value = min(0.35 r + 0.45 g + 0.2 b, 1).
    let x = (5.0f32 * 0.35).sin() / 2.0;
    let y = (5.0f32 * 0.05).cos() / 2.0;
    let z = -(5.0f32 * -0.25).cos() / 2.0;
    let (r, g, b) = (0.5 - x, 0.5 - y, 0.5 - z);
    let expect = (0.35 * r.max(0.0) + 0.45 * g.max(0.0) + 0.2 * b.max(0.0)).min(1.0);
    assert!(close(value(&d, "magic", p), expect), "{expect}");
    // Bands: wave(10·(x + y + z)) = wave(3.5).
    assert!(close(value(&d, "sin", p), 0.5 + 0.5 * 3.5f32.sin()));
    assert!(close(
        value(&d, "saw", p),
        3.5 / (2.0 * std::f32::consts::PI)
    ));
    let tri = 1.0
        - 2.0
            * ((3.5 / (2.0 * std::f32::consts::PI) + 0.5).floor()
                - 3.5 / (2.0 * std::f32::consts::PI))
                .abs();
    assert!(close(value(&d, "tri", p), tri));
    let r = (0.1f32 * 0.1 + 0.2 * 0.2 + 0.05 * 0.05).sqrt() * 20.0;
    assert!(close(value(&d, "rings", p), 0.5 + 0.5 * r.sin()));
}

#[test]
fn noise_patterns_follow_the_noise_library() {
    let mut d = SceneDescription::default();
    add_tex(
        &mut d,
        "clouds",
        TextureType::Float,
        "blender_clouds",
        vec![
            ("noisebasis", s("improved_perlin")),
            ("noisedepth", int(3)),
            ("noisetype", s("hard_noise")),
        ],
    );
    add_tex(
        &mut d,
        "clouds_doc",
        TextureType::Float,
        "blender_clouds",
        vec![("noise_size", f(0.5)), ("noise_depth", int(1))],
    );
    add_tex(
        &mut d,
        "marble",
        TextureType::Float,
        "blender_marble",
        vec![("type", s("sharp")), ("noisebasis", s("voronoi_f1"))],
    );
    add_tex(
        &mut d,
        "musgrave",
        TextureType::Float,
        "blender_musgrave",
        vec![
            ("type", s("fbm")),
            ("octs", f(3.5)),
            ("noisebasis", s("original_perlin")),
        ],
    );
    add_tex(
        &mut d,
        "stucci",
        TextureType::Float,
        "blender_stucci",
        vec![("type", s("wall_out")), ("noisebasis", s("cell_noise"))],
    );
    add_tex(
        &mut d,
        "voronoi",
        TextureType::Float,
        "blender_voronoi",
        vec![
            ("distmetric", s("manhattan")),
            ("w2", f(0.5)),
            ("outscale", f(0.7)),
        ],
    );
    add_tex(
        &mut d,
        "dist",
        TextureType::Float,
        "blender_distortednoise",
        vec![("type", s("voronoi_crackle")), ("distamount", f(2.0))],
    );
    add_tex(&mut d, "noise", TextureType::Float, "blender_noise", vec![]);
    let p = Vec3A::new(0.37, -0.21, 0.6);
    let [x, y, z] = [p.x, p.y, p.z];
    let clouds = noiselib::g_turbulence(0.25, x, y, z, 3, true, NoiseBasis::ImprovedPerlin);
    assert!(close(value(&d, "clouds", p), clouds.clamp(0.0, 1.0)));
    let doc = noiselib::g_turbulence(0.5, x, y, z, 1, false, NoiseBasis::BlenderOriginal);
    assert!(close(value(&d, "clouds_doc", p), doc.clamp(0.0, 1.0)));
    let t = noiselib::g_turbulence(0.25, x, y, z, 2, false, NoiseBasis::VoronoiF1);
    let m = (0.5 + 0.5 * (5.0 * (x + y + z) + 5.0 * t).sin()).sqrt();
    assert!(close(value(&d, "marble", p), m.clamp(0.0, 1.0)));
    let f = Fractal {
        h: 1.0,
        lacunarity: 2.0,
        octaves: 3.5,
        offset: 1.0,
        gain: 1.0,
        basis: NoiseBasis::OriginalPerlin,
    };
    let mg = f.fbm([x / 0.25, y / 0.25, z / 0.25]);
    assert!(close(value(&d, "musgrave", p), mg.clamp(0.0, 1.0)));
    let b2 = noiselib::g_noise(0.25, x, y, z, false, NoiseBasis::CellNoise);
    let st = 1.0
        - noiselib::g_noise(
            0.25,
            x,
            y,
            z + 5.0 / 200.0 * b2 * b2,
            false,
            NoiseBasis::CellNoise,
        );
    assert!(close(value(&d, "stucci", p), st.max(0.0)));
    let (da, _) = noiselib::voronoi(
        x / 0.25,
        y / 0.25,
        z / 0.25,
        2.5,
        noiselib::Distance::Manhattan,
    );
    let v = 0.7 / 1.5 * (da[0] + 0.5 * da[1]).abs();
    assert!(close(value(&d, "voronoi", p), v.clamp(0.0, 1.0)));
    let q = [x / 0.25, y / 0.25, z / 0.25];
    // LuxRender's order: the `noisebasis` noise displaces, the `type` basis is sampled.
    let dn = noiselib::vl_noise(
        q,
        2.0,
        NoiseBasis::BlenderOriginal,
        NoiseBasis::VoronoiCrackle,
    );
    assert!(close(value(&d, "dist", p), dn.clamp(0.0, 1.0)));
    let n = value(&d, "noise", p);
    assert!((0.0..=1.0).contains(&n));
    assert_eq!(n, value(&d, "noise", p), "the noise repeats at a point");
}

#[test]
fn unknown_choices_fall_back_with_a_warning_and_bump_derivatives_difference_the_pattern() {
    let mut d = SceneDescription::default();
    add_tex(
        &mut d,
        "w",
        TextureType::Float,
        "blender_wood",
        vec![("type", s("planks")), ("noisebasis", s("simplex"))],
    );
    add_tex(&mut d, "lin", TextureType::Float, "blender_blend", vec![]);
    let mut set = TextureSet::new(&d, TextureCtx::default());
    let w = float_of(&mut set, "w");
    assert_eq!(set.warnings.len(), 2, "{:?}", set.warnings);
    let p = Vec3A::new(0.1, 0.2, 0.05);
    assert!(close(w.eval(&si_at(0.0, 0.0, p)), 0.5 + 0.5 * 3.5f32.sin()));
    // lin: value (1 + x)/2, so d/du along dpdu = x̂ is ½.
    let lin = float_of(&mut set, "lin");
    let d = lin.duv(&si_at(0.0, 0.0, Vec3A::new(0.1, 0.0, 0.0)), 0.001);
    assert!((d.x - 0.5).abs() < 1e-3 && d.y.abs() < 1e-6, "{d:?}");
}
