//! Materials made of materials: glossycoating, doubleside, layered (and its opacity blend).

use super::*;

/// Like `check_lobe`, for BSDFs that may also sample delta directions: non-specular samples
/// must agree with `f`/`pdf`, the pdf integrates to the non-specular sampling probability, and
/// the sampled albedo (specular included) matches numeric integration plus the specular part.
fn check_mixed(name: &str, b: &Bsdf, wo: Vec3A, max_albedo: f64, grid: (usize, usize)) {
    let n = 100_000;
    let mut rng = Rng(0x2545_f491);
    let (mut spec_sum, mut glossy_sum, mut glossy_ok) = (0.0f64, 0.0f64, 0usize);
    for _ in 0..n {
        let u = rng.next();
        if let Some(s) = b.sample_f(wo, u, rng.next2()) {
            let w = (s.f.average() * s.wi.dot(b.frame.n).abs() / s.pdf) as f64;
            if s.specular {
                spec_sum += w;
            } else {
                glossy_ok += 1;
                glossy_sum += w;
                let (f, p) = b.f_pdf(wo, s.wi);
                assert!(
                    (f.average() - s.f.average()).abs() <= 1e-3 * f.average().max(1e-2),
                    "{name}: f {f:?} vs {:?}",
                    s.f
                );
                assert!(
                    (p - s.pdf).abs() <= 1e-3 * p.max(1e-3),
                    "{name}: pdf {p} vs {}",
                    s.pdf
                );
            }
        }
    }
    let (num, pdf_int) = sphere_integral(grid.0, grid.1, |wi| {
        let (f, p) = b.f_pdf(wo, wi);
        ((f.average() * wi.dot(b.frame.n).abs()) as f64, p as f64)
    });
    let glossy_mc = glossy_sum / n as f64;
    assert!(
        (glossy_mc - num).abs() <= 0.03 * num.max(0.05),
        "{name}: sampled {glossy_mc} vs numeric {num}"
    );
    let frac = glossy_ok as f64 / n as f64;
    assert!(
        (pdf_int - frac).abs() < 0.03,
        "{name}: pdf integrates to {pdf_int}, {frac} of samples non-specular"
    );
    let total = num + spec_sum / n as f64;
    assert!(total <= max_albedo, "{name}: albedo {total} > {max_albedo}");
}

fn glossy_params(extra: Vec<(&'static str, ParamValue)>) -> Vec<(&'static str, ParamValue)> {
    let mut v = vec![
        ("Ks", ParamValue::Color(vec![[0.05, 0.05, 0.05]])),
        ("uroughness", f(0.15)),
        ("vroughness", f(0.15)),
        ("Ka", ParamValue::Color(vec![[0.3, 0.5, 0.7]])),
        ("d", f(0.2)),
    ];
    v.extend(extra);
    v
}

#[test]
fn glossycoating_over_matte_is_glossy() {
    let kd = ("Kd", ParamValue::Color(vec![[0.6, 0.3, 0.2]]));
    let d = scene(vec![
        mat("base", "matte", vec![kd.clone()], 1),
        mat(
            "coated",
            "glossycoating",
            glossy_params(vec![("basematerial", s("base"))]),
            2,
        ),
        mat("glossy", "glossy", glossy_params(vec![kd]), 3),
    ]);
    let set = MaterialSet::build(&d, &[1, 2], &MaterialCtx::default()).unwrap();
    assert!(set.warnings.is_empty(), "{:?}", set.warnings);
    let si = flat_si();
    let coated = set.get(Some(1)).bsdf(&si, 0.5);
    let glossy = set.get(Some(2)).bsdf(&si, 0.5);
    assert!(matches!(coated.lobes, Lobes::Composite(_)));
    let mut rng = Rng(5);
    for _ in 0..500 {
        let wo = crate::sampling::uniform_sphere(rng.next2());
        let wi = crate::sampling::uniform_sphere(rng.next2());
        let (a, b) = (coated.f(wo, wi), glossy.f(wo, wi));
        for i in 0..3 {
            assert!((a[i] - b[i]).abs() <= 1e-5 * b[i].max(1.0), "{a:?} {b:?}");
        }
        assert!((coated.pdf(wo, wi) - glossy.pdf(wo, wi)).abs() <= 1e-4);
    }
    check_mixed("glossycoating", &coated, dir(40.0, 0.0), 1.0, (600, 300));
}

#[test]
fn glossycoating_over_glass_keeps_the_delta_and_filters_transmission() {
    let d = scene(vec![
        mat("glass", "glass", vec![], 1),
        mat(
            "coated",
            "glossycoating",
            vec![
                ("basematerial", s("glass")),
                ("Ks", ParamValue::Color(vec![[0.04, 0.04, 0.04]])),
            ],
            2,
        ),
    ]);
    let set = MaterialSet::build(&d, &[1], &MaterialCtx::default()).unwrap();
    let b = set.get(Some(1)).bsdf(&flat_si(), 0.5);
    assert!(b.has_non_specular());
    let wo = dir(20.0, 0.0);
    // The transmitted delta is filtered by sqrt(1 - S) at the transmission half vector.
    let mut found = false;
    for i in 0..200 {
        let u = (i as f32 + 0.5) / 200.0;
        if let Some(s) = b.sample_f(wo, u, Vec2::new(0.3, 0.3)) {
            if s.specular && s.wi.z < 0.0 {
                found = true;
                assert!(s.f.r > 0.0 && s.f.is_finite());
            }
        }
    }
    assert!(found);
    check_mixed("coated glass", &b, wo, 1.0001, (600, 300));
}

#[test]
fn doubleside_shows_each_material_on_its_side() {
    let d = scene(vec![
        mat(
            "red",
            "matte",
            vec![("Kd", ParamValue::Color(vec![[0.8, 0.1, 0.1]]))],
            1,
        ),
        mat(
            "blue",
            "matte",
            vec![("Kd", ParamValue::Color(vec![[0.1, 0.1, 0.8]]))],
            2,
        ),
        mat(
            "two",
            "doubleside",
            vec![
                ("frontnamedmaterial", s("red")),
                ("backnamedmaterial", s("blue")),
            ],
            3,
        ),
    ]);
    let set = MaterialSet::build(&d, &[2], &MaterialCtx::default()).unwrap();
    assert!(set.warnings.is_empty());
    let b = set.get(Some(2)).bsdf(&flat_si(), 0.5);
    let (above, above2) = (dir(30.0, 0.0), dir(50.0, 120.0));
    assert!((b.f(above, above2).r - 0.8 / PI).abs() < 1e-6);
    assert!((b.f(-above, -above2).b - 0.8 / PI).abs() < 1e-6);
    // No light crosses.
    assert_eq!(b.f(above, -above2), Rgb::BLACK);
    check_lobe("doubleside front", &b, above, 0.81);
    check_lobe("doubleside back", &b, -above, 0.81);
    // A glossy back material seen from behind, front face toward the back.
    let d = scene(vec![
        mat("matte", "matte", vec![], 1),
        mat("gl", "glossy", vec![], 2),
        mat(
            "two",
            "doubleside",
            vec![
                ("frontnamedmaterial", s("matte")),
                ("backnamedmaterial", s("gl")),
                ("usefrontforback", ParamValue::Bool(vec![true])),
            ],
            3,
        ),
    ]);
    let set = MaterialSet::build(&d, &[2], &MaterialCtx::default()).unwrap();
    let b = set.get(Some(2)).bsdf(&flat_si(), 0.5);
    let glossy_front = set.get(Some(1)).bsdf(&flat_si(), 0.5);
    let (wo, wi) = (dir(20.0, 0.0), dir(20.0, 180.0));
    let back = b.f(-wo, -wi);
    let front = glossy_front.f(wo, wi);
    assert!(
        (back.r - front.r).abs() < 1e-5 * front.r,
        "{back:?} {front:?}"
    );
}

#[test]
fn layered_single_opaque_layer_is_that_layer() {
    let d = scene(vec![
        mat(
            "m",
            "matte",
            vec![("Kd", ParamValue::Color(vec![[0.5, 0.5, 0.5]]))],
            1,
        ),
        mat("l", "layered", vec![("namedmaterial1", s("m"))], 2),
    ]);
    let set = MaterialSet::build(&d, &[1], &MaterialCtx::default()).unwrap();
    assert!(set.warnings.is_empty());
    let b = set.get(Some(1)).bsdf(&flat_si(), 0.25);
    let mut rng = Rng(17);
    for _ in 0..200 {
        let wo = crate::sampling::cosine_hemisphere(rng.next2());
        let wi = crate::sampling::cosine_hemisphere(rng.next2());
        assert!((b.f(wo, wi).r - 0.5 / PI).abs() < 1e-5);
        assert!((b.pdf(wo, wi) - 1.0 / (8.0 * PI)).abs() < 1e-7);
    }
    // An empty stack is a null surface.
    let d = scene(vec![mat("l", "layered", vec![], 1)]);
    let set = MaterialSet::build(&d, &[0], &MaterialCtx::default()).unwrap();
    assert!(matches!(
        set.get(Some(0)).bsdf(&flat_si(), 0.5).lobes,
        Lobes::Null
    ));
}

/// Hand value: a half-opaque matte (R1 = 0.5) over a matte (R2 = 0.8) reflects
/// ρ1 + T² ρ2 / (1 - ρ1 ρ2) with ρ1 = 0.5·R1, T = 0.5: 0.25 + 0.25·0.8/0.8 = 0.5, for every
/// incident direction (Lambertian layers).
#[test]
fn layered_matte_stack_reflects_the_hand_computed_albedo() {
    let c = |v: f32| ParamValue::Color(vec![[v, v, v]]);
    let d = scene(vec![
        mat("top", "matte", vec![("Kd", c(0.5))], 1),
        mat("bottom", "matte", vec![("Kd", c(0.8))], 2),
        mat(
            "l",
            "layered",
            vec![
                ("namedmaterial1", s("top")),
                ("opacity1", f(0.5)),
                ("namedmaterial2", s("bottom")),
            ],
            3,
        ),
    ]);
    let set = MaterialSet::build(&d, &[2], &MaterialCtx::default()).unwrap();
    assert!(set.warnings.is_empty());
    let b = set.get(Some(2)).bsdf(&flat_si(), 0.5);
    for theta in [10.0, 60.0] {
        let wo = dir(theta, 0.0);
        let (num, _) = sphere_integral(160, 80, |wi| {
            ((b.f(wo, wi).average() * wi.z.abs()) as f64, 0.0)
        });
        assert!((num - 0.5).abs() < 0.03, "theta {theta}: albedo {num}");
    }
    check_mixed("layered", &b, dir(30.0, 0.0), 0.55, (160, 80));
}

#[test]
fn layered_glass_over_matte_samples_specular_chains() {
    let d = scene(vec![
        mat("glass", "glass", vec![], 1),
        mat("base", "matte", vec![], 2),
        mat(
            "l",
            "layered",
            vec![
                ("namedmaterial1", s("glass")),
                ("namedmaterial2", s("base")),
            ],
            3,
        ),
    ]);
    let set = MaterialSet::build(&d, &[2], &MaterialCtx::default()).unwrap();
    let b = set.get(Some(2)).bsdf(&flat_si(), 0.5);
    let wo = dir(30.0, 0.0);
    let mut specular = 0;
    let mut rng = Rng(3);
    for _ in 0..2000 {
        if let Some(s) = b.sample_f(wo, rng.next() * 0.5, rng.next2()) {
            assert!(s.specular);
            // The only specular chain through glass over matte is the glass reflection.
            assert!((s.wi - Vec3A::new(-wo.x, -wo.y, wo.z)).length() < 1e-4);
            specular += 1;
        }
    }
    assert!(specular > 0);
    // Reproducible: the same pair gives the same estimate.
    let wi = dir(45.0, 100.0);
    assert_eq!(b.f(wo, wi), b.f(wo, wi));
}
