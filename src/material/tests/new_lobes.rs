//! The materials added for LuxRender 1.x coverage: glossy_lossy (and plastic, substrate),
//! non-separable glossy, metal2, scatter, cloth, thin films, architectural glass, velvet's
//! 1.x parameters, compositing flags.

use super::bxdf::fresnel_blend::FresnelBlend;
use super::bxdf::scatter::SchlickScatter;
use super::*;

fn build_one(kind: &str, params: Vec<(&str, ParamValue)>) -> (MaterialSet, Bsdf) {
    let d = scene(vec![mat("m", kind, params, 1)]);
    let set = MaterialSet::build(&d, &[0], &MaterialCtx::default()).unwrap();
    let b = set.get(Some(0)).bsdf(&flat_si(), 0.5);
    (set, b)
}

fn color(r: f32, g: f32, b: f32) -> ParamValue {
    ParamValue::Color(vec![[r, g, b]])
}

#[test]
fn fresnel_blend_hand_value_at_normal_incidence_and_consistent_sampling() {
    let fb = FresnelBlend {
        kd: Rgb::splat(0.5),
        ks: Rgb::splat(0.04),
        ka: Rgb::BLACK,
        depth: 0.0,
        dist: SchlickDist::unclamped(0.1, 0.1),
    };
    let b = bsdf(Lobes::FresnelBlend(fb));
    // wo = wi = n: diffuse 28/(23π)·Kd(1-Ks)·(31/32)², specular Ks·D(n)/4 = Ks/(4π r).
    let v = b.f(Vec3A::Z, Vec3A::Z).r;
    let diffuse = 28.0 / (23.0 * PI) * 0.5 * 0.96 * (31.0f32 / 32.0).powi(2);
    let spec = 0.04 / (4.0 * PI * 0.01);
    assert!(
        (v - (diffuse + spec)).abs() < 1e-4 * (diffuse + spec),
        "{v}"
    );
    for theta in [10.0, 50.0, 80.0] {
        check_lobe("fresnel blend", &b, dir(theta, 30.0), 1.0);
    }
}

#[test]
fn plastic_keeps_its_legacy_roughness_and_substrate_its_own() {
    let (set, b) = build_one(
        "plastic",
        vec![
            ("Kd", color(0.5, 0.5, 0.5)),
            ("Ks", color(0.1, 0.1, 0.1)),
            ("roughness", f(0.000571)),
        ],
    );
    match b.lobes {
        Lobes::FresnelBlend(fb) => {
            assert!((fb.dist.roughness - 0.000571f32.powi(2)).abs() < 1e-12);
            assert_eq!(fb.kd, Rgb::splat(0.5));
        }
        other => panic!("{other:?}"),
    }
    assert!(set.warnings.is_empty(), "{:?}", set.warnings);
    let (_, b) = build_one(
        "substrate",
        vec![("uroughness", f(0.2)), ("vroughness", f(0.05))],
    );
    match b.lobes {
        Lobes::FresnelBlend(fb) => assert!((fb.dist.roughness - 0.01).abs() < 1e-7),
        other => panic!("{other:?}"),
    }
}

#[test]
fn non_separable_glossy_is_one_schlick_brdf() {
    let (set, b) = build_one(
        "glossy",
        vec![
            ("separable", ParamValue::Bool(vec![false])),
            ("Kd", color(0.6, 0.6, 0.6)),
            ("Ks", color(0.05, 0.05, 0.05)),
            ("uroughness", f(0.2)),
            ("vroughness", f(0.2)),
        ],
    );
    assert!(set.warnings.is_empty());
    let Lobes::SchlickBrdf(sb) = b.lobes.clone() else {
        panic!("{:?}", b.lobes)
    };
    // At normal incidence: (1 - Ks)·Kd/π + Ks·D(n)·G/4, D(n) = 1/(π r), G = 1.
    let r = 0.04f32;
    let want = 0.95 * 0.6 / PI + 0.05 / (PI * r) / 4.0;
    assert!((b.f(Vec3A::Z, Vec3A::Z).r - want).abs() < 1e-4 * want);
    // Back side: only the (1 - S) diffuse part.
    let back = sb.f(-dir(20.0, 0.0), -dir(40.0, 180.0));
    assert!(back.r > 0.0 && back.r < 0.6 / PI);
    for theta in [0.0, 45.0, 75.0] {
        check_lobe("glossy non-separable", &b, dir(theta, 10.0), 1.0);
    }
}

#[test]
fn metal2_constant_fresnel_is_a_dielectric_reflector() {
    let (set, b) = build_one(
        "metal2",
        vec![
            ("fresnel", f(5.0)),
            ("uroughness", f(0.2)),
            ("vroughness", f(0.2)),
        ],
    );
    assert!(set.warnings.is_empty());
    let Lobes::Microfacet(m) = b.lobes.clone() else {
        panic!("{:?}", b.lobes)
    };
    // Normal incidence reflectance ((5-1)/(5+1))² of the dielectric interface.
    let fr = m.fresnel.eval(1.0).r;
    assert!((fr - 4.0 / 9.0).abs() < 1e-5, "{fr}");
    for theta in [0.0, 40.0, 70.0] {
        check_lobe("metal2", &b, dir(theta, 0.0), 1.0);
    }
    // The default is a dielectric of index 5.
    let (_, d) = build_one("metal2", vec![]);
    let Lobes::Microfacet(m) = d.lobes else {
        panic!()
    };
    let fr = m.fresnel.eval(1.0);
    assert!((0..3).all(|i| (fr[i] - 4.0 / 9.0).abs() < 1e-6), "{fr:?}");
}

#[test]
fn scatter_is_a_phase_function_with_kd_albedo() {
    // g = 0: isotropic, f |cos| = Kd/(4π) in every direction, pdf uniform.
    let s = SchlickScatter::new(Rgb::splat(0.7), Rgb::BLACK);
    let b = bsdf(Lobes::Scatter(s));
    let wo = dir(30.0, 0.0);
    for wi in [dir(60.0, 90.0), -dir(10.0, 200.0)] {
        let v = b.f(wo, wi).r * wi.z.abs();
        assert!((v - 0.7 / (4.0 * PI)).abs() < 1e-6, "{v}");
        assert!((b.pdf(wo, wi) - 1.0 / (4.0 * PI)).abs() < 1e-6);
    }
    // Forward scattering: with g > 0 more light continues through the surface (wi = -wo).
    let s = SchlickScatter::new(Rgb::WHITE, Rgb::splat(0.5));
    let k = 0.5f32 * (1.55 - 0.55 * 0.25);
    let b = bsdf(Lobes::Scatter(s));
    let through = -wo;
    let v = b.f(wo, through).r * through.z.abs();
    let want = (1.0 - k * k) / (4.0 * PI * (1.0 - k).powi(2));
    assert!((v - want).abs() < 1e-4 * want, "{v} vs {want}");
    let (mc, success) = sampled_albedo(&b, wo, 50_000);
    assert!((mc - 1.0).abs() < 1e-3 && success > 0.99, "{mc} {success}");
    let (num, pdf_int) = numeric(&b, wo);
    assert!((num - 1.0).abs() < 0.01 && (pdf_int - 1.0).abs() < 0.01);
    // The scene material reads Kd and a float or colour g.
    let (set, b) = build_one(
        "scatter",
        vec![("Kd", color(0.64, 0.2, 0.16)), ("g", f(-0.3))],
    );
    assert!(set.warnings.is_empty());
    assert!(matches!(b.lobes, Lobes::Scatter(_)));
}

#[test]
fn cloth_presets_build_and_reflect_their_colours_on_average() {
    for name in super::cloth_patterns::PRESETS {
        let (set, b) = build_one(
            "cloth",
            vec![
                ("presetname", s(name)),
                ("warp_Kd", color(0.2, 0.2, 0.2)),
                ("weft_Kd", color(0.2, 0.2, 0.2)),
                ("warp_Ks", color(0.3, 0.3, 0.3)),
                ("weft_Ks", color(0.3, 0.3, 0.3)),
                ("repeat_u", f(10.0)),
                ("repeat_v", f(10.0)),
            ],
        );
        assert!(set.warnings.is_empty(), "{name}: {:?}", set.warnings);
        assert!(matches!(b.lobes, Lobes::Cloth(_)), "{name}");
        check_lobe(name, &b, dir(35.0, 20.0), 2.0);
    }
    // The specular part reflects Ks on average over positions and diffuse light.
    let d = scene(vec![mat(
        "c",
        "cloth",
        vec![
            ("presetname", s("cotton_twill")),
            ("warp_Ks", color(0.5, 0.5, 0.5)),
            ("weft_Ks", color(0.5, 0.5, 0.5)),
            ("repeat_u", f(3.0)),
            ("repeat_v", f(3.0)),
        ],
        1,
    )]);
    let set = MaterialSet::build(&d, &[0], &MaterialCtx::default()).unwrap();
    let m = set.get(Some(0));
    let mut rng = Rng(99);
    let n = 60_000;
    let mut sum = 0.0f64;
    for _ in 0..n {
        let si = si_at(rng.next(), rng.next(), Vec3A::ZERO);
        let b = m.bsdf(&si, 0.5);
        let wo = crate::sampling::cosine_hemisphere(rng.next2());
        let wi = crate::sampling::cosine_hemisphere(rng.next2());
        // ρ_hh = π E[f] over cosine-distributed pairs.
        sum += (b.f(wo, wi).r * PI) as f64;
    }
    let rho = sum / n as f64;
    assert!((rho - 0.5).abs() < 0.05, "{rho}");
    // An unknown preset is denim, with a located warning.
    let (set, _) = build_one("cloth", vec![("presetname", s("tweed"))]);
    assert!(set.warnings.iter().any(|w| w.to_string().contains("tweed")));
}

#[test]
fn thin_films_colour_mirror_glass_and_shinymetal_reflections() {
    // d = 50 nm · 1.375 = 68.75 nm at normal incidence: green (550 nm) cancelled.
    let film = vec![
        ("film", f(50.0)),
        ("filmindex", f(1.375)),
        ("Kr", color(1.0, 1.0, 1.0)),
    ];
    let (set, b) = build_one("mirror", film.clone());
    assert!(set.warnings.is_empty());
    let s = b.sample_f(Vec3A::Z, 0.5, Vec2::ZERO).unwrap();
    let refl = s.f * (s.wi.z / s.pdf);
    let want = super::bxdf::thin_film::path_factor(68.75);
    assert!((refl.g - want.g).abs() < 1e-5 && refl.g < 0.15, "{refl:?}");
    // Glass: the film colours the reflected part only.
    let (_, g) = build_one("glass", film.clone());
    let r = g.sample_f(Vec3A::Z, 0.0, Vec2::ZERO).unwrap();
    assert!(r.wi.z > 0.0);
    let Lobes::Dielectric(d) = &g.lobes else {
        panic!()
    };
    assert!(d.film.is_some());
    // Without a film nothing changes.
    let (_, plain) = build_one("mirror", vec![("film", f(0.0))]);
    let s = plain.sample_f(Vec3A::Z, 0.5, Vec2::ZERO).unwrap();
    assert!((s.f.g * s.wi.z / s.pdf - 1.0).abs() < 1e-6);
    let (_, sm) = build_one("shinymetal", film);
    let Lobes::GlossyMirror { mirror, .. } = sm.lobes else {
        panic!()
    };
    assert!(mirror.film.is_some());
}

#[test]
fn architectural_glass_reflects_on_its_front_and_passes_from_behind() {
    let (_, b) = build_one(
        "glass",
        vec![("architectural", ParamValue::Bool(vec![true]))],
    );
    let wo = dir(30.0, 0.0);
    let fr = super::bxdf::fresnel::dielectric(wo.z, 1.0, 1.5);
    let t_front = 1.0 - fr * (1.0 + (1.0 - fr) * (1.0 - fr));
    let mut seen = (false, false);
    for i in 0..64 {
        let u = (i as f32 + 0.5) / 64.0;
        let s = b.sample_f(wo, u, Vec2::ZERO).unwrap();
        // Each lobe is picked in proportion to its weight: both carry fr + t_front.
        let w = s.f * (s.wi.z.abs() / s.pdf);
        assert!((w.r - (fr + t_front)).abs() < 1e-5, "{w:?}");
        if s.wi.z > 0.0 {
            seen.0 = true;
            assert!((s.pdf - fr / (fr + t_front)).abs() < 1e-5);
        } else {
            seen.1 = true;
            assert!((s.wi + wo).length() < 1e-5, "no bending");
        }
    }
    assert!(seen.0 && seen.1);
    // From behind, everything passes unchanged.
    let s = b.sample_f(-wo, 0.0, Vec2::ZERO).unwrap();
    assert!((s.wi - wo).length() < 1e-5);
    assert!((s.f.r * s.wi.z.abs() / s.pdf - 1.0).abs() < 1e-5);
}

#[test]
fn velvet_uses_luxrender_1x_parameters() {
    let (set, b) = build_one("velvet", vec![("p3", f(3.0))]);
    assert!(set.warnings.is_empty());
    let Lobes::Velvet(v) = b.lobes else { panic!() };
    assert_eq!((v.a1, v.a2, v.a3), (-2.0, 20.0, 3.0));
    assert_eq!(v.r, Rgb::splat(0.3));
    assert!((v.thickness - 0.1).abs() < 1e-7);
    let d = scene(vec![mat("m", "velvet", vec![("p3", f(3.0))], 1)]);
    let _ = MaterialSet::build(&d, &[0], &MaterialCtx::default()).unwrap();
    assert!(d.materials[0].entity.params.unused().next().is_none());
}

#[test]
fn every_material_reads_the_compositing_flags() {
    for kind in ["matte", "glass", "cloth", "null"] {
        let d = scene(vec![mat(
            "m",
            kind,
            vec![
                ("compo_visible_material", ParamValue::Bool(vec![false])),
                ("compo_override_alpha", ParamValue::Bool(vec![true])),
                ("compo_override_alpha_value", f(0.5)),
            ],
            1,
        )]);
        let set = MaterialSet::build(&d, &[0], &MaterialCtx::default()).unwrap();
        let c = set.get(Some(0)).compositing;
        assert!(
            !c.visible_material && c.override_alpha == Some(0.5),
            "{kind}"
        );
        assert!(
            d.materials[0].entity.params.unused().next().is_none(),
            "{kind}"
        );
    }
}
