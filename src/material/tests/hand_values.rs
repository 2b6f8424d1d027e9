//! Known values at chosen angles, computed by hand from LuxRender 1.x's formulas (the numbers
//! in the assertions come from the formulas in the comments, not from the code under test),
//! and reciprocity of the reflection-only BSDFs: metal (an `.nk` file of constant n, k),
//! metal2, velvet, carpaint and roughglass, each built from a scene description.

use super::*;

/// The BSDF of material `i` of a built set at the flat test hit (normal +z, world = local).
fn built(mats: Vec<MaterialDesc>, ctx: &MaterialCtx) -> MaterialSet {
    let n = mats.len();
    let d = scene(mats);
    let used: Vec<usize> = (0..n).collect();
    MaterialSet::build(&d, &used, ctx).unwrap()
}

fn close(got: f32, want: f64, rel: f64, what: &str) {
    assert!(
        (got as f64 - want).abs() <= rel * want.abs().max(1e-6),
        "{what}: {got} vs hand value {want}"
    );
}

/// Mirror direction of `wo` about +z.
fn mirrored(wo: Vec3A) -> Vec3A {
    Vec3A::new(-wo.x, -wo.y, wo.z)
}

/// f(wo, wi) = f(wi, wo) for pairs all over the upper hemisphere.
fn assert_reciprocal(name: &str, b: &Bsdf) {
    let mut rng = Rng(0x5eed);
    for _ in 0..200 {
        let wo = dir(85.0 * rng.next(), 360.0 * rng.next());
        let wi = dir(85.0 * rng.next(), 360.0 * rng.next());
        let (a, c) = (b.f(wo, wi), b.f(wi, wo));
        for k in 0..3 {
            assert!(
                (a[k] - c[k]).abs() <= 1e-4 * a[k].abs().max(1e-3),
                "{name}: f(wo, wi) {a:?} vs f(wi, wo) {c:?}"
            );
        }
    }
}

/// metal: F·D·G/(4 cos_o cos_i) with the conductor Fresnel term. An `.nk` file (luxpop
/// format, Å) of n = 0.2, k = 3 everywhere gives F(0°) = ((n-1)² + k²)/((n+1)² + k²) =
/// 9.64/10.44; the default roughness 0.1 × 0.1 = 0.01 gives D(h = n) = 1/(0.01π), G = 1, so
/// f(0°, 0°) = 0.92337/(4 · 0.01π) = 7.34796.
#[test]
fn metal_from_an_nk_file_has_the_conductor_value_at_normal_incidence() {
    let dir_ = std::env::temp_dir().join(format!("luxfarm-nk-{}", std::process::id()));
    std::fs::create_dir_all(&dir_).unwrap();
    std::fs::write(
        dir_.join("flat.nk"),
        "; constant optical constants\n3000 0.2 3.0\n8000 0.2 3.0\n",
    )
    .unwrap();
    let ctx = MaterialCtx {
        files: dir_.clone().into(),
    };
    let set = built(
        vec![mat("m", "metal", vec![("filename", s("flat.nk"))], 1)],
        &ctx,
    );
    let _ = std::fs::remove_dir_all(&dir_);
    assert!(set.warnings.is_empty(), "{:?}", set.warnings);
    let b = set.get(Some(0)).bsdf(&flat_si(), 0.5);
    let v = b.f(Vec3A::Z, Vec3A::Z);
    for k in 0..3 {
        close(v[k], 7.347958, 1e-4, "metal f(0°, 0°)");
    }
    assert_reciprocal("metal", &b);
}

/// metal2 with a constant fresnel 1.5 is a dielectric reflector: F(0°) = 0.04, so with
/// roughness 0.01 f(0°, 0°) = 0.04/(4 · 0.01π) = 1/π. At 60° in the mirror direction: the
/// exact dielectric F(cos 0.5, 1 → 1.5) = 0.0891867, G1(0.5) = 0.5/(0.5 · 0.99 + 0.01), and
/// f = F D G1² / (4 · 0.5 · 0.5) = 2.782964.
#[test]
fn metal2_dielectric_values_at_normal_and_sixty_degrees() {
    let set = built(
        vec![mat(
            "m",
            "metal2",
            vec![
                ("fresnel", f(1.5)),
                ("uroughness", f(0.1)),
                ("vroughness", f(0.1)),
            ],
            1,
        )],
        &MaterialCtx::default(),
    );
    let b = set.get(Some(0)).bsdf(&flat_si(), 0.5);
    close(
        b.f(Vec3A::Z, Vec3A::Z).g,
        std::f64::consts::FRAC_1_PI,
        1e-4,
        "metal2 f(0°, 0°)",
    );
    let wo = dir(60.0, 25.0);
    close(b.f(wo, mirrored(wo)).r, 2.782964, 1e-4, "metal2 f(60°)");
    assert_reciprocal("metal2", &b);
}

/// velvet with LuxRender's defaults (Kd 0.3, p1 -2, p2 20, p3 2, thickness 0.1). Back along
/// wi = wo the phase angle has cos = -1: 1 + 2 + 20 · 1 + 2 · (-1) = 21, so
/// f = Kd · 21 · 0.1 / (4π cos_i cos_o): 0.0501338 at 0° and 0.2005352 at 60°. In the
/// mirror direction at 60° (cos = 0.5) the phase is negative and clamps to 0.
#[test]
fn velvet_defaults_give_the_asperity_values() {
    let set = built(vec![mat("v", "velvet", vec![], 1)], &MaterialCtx::default());
    let b = set.get(Some(0)).bsdf(&flat_si(), 0.5);
    close(
        b.f(Vec3A::Z, Vec3A::Z).r,
        0.05013381,
        1e-4,
        "velvet f(0°, 0°)",
    );
    let wo = dir(60.0, 40.0);
    close(b.f(wo, wo).b, 0.20053523, 1e-4, "velvet f(60°, 60°) back");
    assert_eq!(b.f(wo, mirrored(wo)), Rgb::BLACK);
    // Away from the clamp the model is symmetric in wo and wi.
    let (a, c) = (dir(20.0, 10.0), dir(50.0, 200.0));
    close(b.f(a, c).r, b.f(c, a).r as f64, 1e-5, "velvet reciprocity");
}

/// carpaint without a name: Kd 0.5 and one layer Ks1 0.2, R1 0.1, M1 0.5 (Ks2 = Ks3 = 0). At
/// normal incidence S = 0 so the base is Kd/π; the layer has roughness M² = 0.25, D = 4/π,
/// G = 1 and Schlick's F(0°) = R1: f = 0.5/π + 0.2 · 0.1 · (4/π)/4 = 0.1655211.
#[test]
fn carpaint_one_layer_value_at_normal_incidence() {
    let c = |v: f32| ParamValue::Color(vec![[v, v, v]]);
    let set = built(
        vec![mat(
            "c",
            "carpaint",
            vec![
                ("Kd", c(0.5)),
                ("Ks1", c(0.2)),
                ("Ks2", c(0.0)),
                ("Ks3", c(0.0)),
                ("R1", f(0.1)),
                ("M1", f(0.5)),
            ],
            1,
        )],
        &MaterialCtx::default(),
    );
    let b = set.get(Some(0)).bsdf(&flat_si(), 0.5);
    close(
        b.f(Vec3A::Z, Vec3A::Z).r,
        0.16552114,
        1e-4,
        "carpaint f(0°, 0°)",
    );
    assert_reciprocal("carpaint", &b);
}

/// roughglass (index 1.5, roughness 0.1 × 0.1): reflection at normal incidence is
/// F D G/(4 cos cos) = 0.04/(4 · 0.01π) = 1/π; straight transmission is Walter et al.'s
/// (1 - F) D G η_t² |o·h||i·h| / (cos_o cos_i (η_o o·h + η_t i·h)²) = 0.96 D 2.25/0.25, in
/// radiance form divided by η_t² = 2.25: 0.96 · 4/(0.01π) = 122.23100.
#[test]
fn roughglass_reflection_and_transmission_at_normal_incidence() {
    let set = built(
        vec![mat(
            "g",
            "roughglass",
            vec![
                ("index", f(1.5)),
                ("uroughness", f(0.1)),
                ("vroughness", f(0.1)),
            ],
            1,
        )],
        &MaterialCtx::default(),
    );
    let b = set.get(Some(0)).bsdf(&flat_si(), 0.5);
    close(
        b.f(Vec3A::Z, Vec3A::Z).r,
        std::f64::consts::FRAC_1_PI,
        1e-4,
        "roughglass reflection",
    );
    close(
        b.f(Vec3A::Z, -Vec3A::Z).r,
        122.230996,
        1e-4,
        "roughglass transmission",
    );
}

/// metal2 with a fresnel texture (`fresnelname "gold"`) reflects as gold: the conductor of
/// gold's (n, k) at normal incidence, red over green over blue, where the constant default
/// (a dielectric of index 5) is grey.
#[test]
fn metal2_takes_its_optical_constants_from_a_fresnel_texture() {
    let text = "WorldBegin\n\
        Texture \"au\" \"fresnel\" \"fresnelname\" \"string name\" [\"gold\"]\n\
        MakeNamedMaterial \"m\" \"string type\" [\"metal2\"] \"texture fresnel\" [\"au\"] \
        \"float uroughness\" [0.1] \"float vroughness\" [0.1]\n\
        MakeNamedMaterial \"d\" \"string type\" [\"metal2\"]\n\
        WorldEnd\n";
    let d = crate::lxs::parse_str(text, "metal2.lxs", &Default::default()).unwrap();
    let set = MaterialSet::build(&d, &[0, 1], &MaterialCtx::default()).unwrap();
    assert!(set.warnings.is_empty(), "{:?}", set.warnings);
    let gold = set.get(Some(0)).bsdf(&flat_si(), 0.5).f(Vec3A::Z, Vec3A::Z);
    let (n, k) = crate::spectrum::nk::NkTable::preset("gold")
        .unwrap()
        .to_rgb();
    let want =
        crate::material::bxdf::fresnel::conductor(1.0, Rgb::from_array(n), Rgb::from_array(k));
    // f(0°, 0°) = F(0) D(0) G1² / 4 with D(0) = 1/(π r) for the Schlick distribution: the
    // channels keep F's ratios.
    for c in 0..3 {
        close(
            gold[c] / gold[1],
            (want[c] / want[1]) as f64,
            1e-3,
            "gold's colour",
        );
    }
    assert!(gold.r > gold.g && gold.g > gold.b, "{gold:?}");
    let grey = set.get(Some(1)).bsdf(&flat_si(), 0.5).f(Vec3A::Z, Vec3A::Z);
    close(grey.r, grey.b as f64, 1e-6, "the default is grey");
}
