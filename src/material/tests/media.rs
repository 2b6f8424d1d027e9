//! glass2 takes its index from the shape's volumes: MaterialSet::bind_media.

use super::*;
use crate::lxs::{VolumeDesc, Xform};

fn add_volume(d: &mut SceneDescription, name: &str, fresnel: f32) {
    let mut ps = ParamSet::new();
    ps.add("fresnel", f(fresnel));
    d.named_volumes.insert(name.to_string(), d.volumes.len());
    d.volumes.push(VolumeDesc {
        name: Some(name.to_string()),
        entity: crate::lxs::Entity {
            kind: "clear".into(),
            params: ps,
            loc: loc(50),
        },
        object_to_world: Xform::identity(),
    });
}

fn eta_of(set: &MaterialSet, i: usize) -> f32 {
    match set.get(Some(i)).bsdf(&flat_si(), 0.9).lobes {
        Lobes::Dielectric(d) => d.eta,
        other => panic!("{other:?}"),
    }
}

#[test]
fn glass2_index_is_interior_over_exterior() {
    let mut d = scene(vec![
        mat("glass2", "glass2", vec![], 1),
        mat("matte", "matte", vec![], 2),
        mat(
            "mix",
            "mix",
            vec![
                ("namedmaterial1", s("glass2")),
                ("namedmaterial2", s("matte")),
                ("amount", f(0.25)),
            ],
            3,
        ),
    ]);
    add_volume(&mut d, "world", 1.0);
    add_volume(&mut d, "glass", 1.459);
    add_volume(&mut d, "water", 1.333);
    let mut set = MaterialSet::build(&d, &[0, 1, 2], &MaterialCtx::default()).unwrap();
    // Without volumes the shell is invisible (index 1).
    assert_eq!(eta_of(&set, 0), 1.0);
    let a = set.bind_media(&d, 0, Some("glass"), Some("world")).unwrap();
    assert_ne!(a, 0);
    assert!((eta_of(&set, a) - 1.459).abs() < 1e-6);
    // The same pair reuses the copy; another pair builds another.
    assert_eq!(
        set.bind_media(&d, 0, Some("glass"), Some("world")).unwrap(),
        a
    );
    let b = set.bind_media(&d, 0, Some("glass"), Some("water")).unwrap();
    assert!((eta_of(&set, b) - 1.459 / 1.333).abs() < 1e-6);
    // Only an exterior: 1 / n_exterior.
    let c = set.bind_media(&d, 0, None, Some("water")).unwrap();
    assert!((eta_of(&set, c) - 1.0 / 1.333).abs() < 1e-6);
    // A material without glass2 is not copied.
    assert_eq!(
        set.bind_media(&d, 1, Some("glass"), Some("world")).unwrap(),
        1
    );
    // A mix that contains glass2 is.
    let m = set.bind_media(&d, 2, Some("glass"), Some("world")).unwrap();
    assert!(m > 2);
    let glassy = (0..100)
        .map(|i| set.get(Some(m)).bsdf(&flat_si(), (i as f32 + 0.5) / 100.0))
        .filter_map(|b| match b.lobes {
            Lobes::Dielectric(d) => Some(d.eta),
            _ => None,
        })
        .collect::<Vec<_>>();
    assert_eq!(glassy.len(), 75);
    assert!(glassy.iter().all(|&e| (e - 1.459).abs() < 1e-6));
    assert!(set.warnings.is_empty(), "{:?}", set.warnings);
}

fn add_tex_volume(d: &mut SceneDescription, name: &str, tex: &str) {
    let mut ps = ParamSet::new();
    ps.add("fresnel", ParamValue::Texture(tex.to_string()));
    d.named_volumes.insert(name.to_string(), d.volumes.len());
    d.volumes.push(VolumeDesc {
        name: Some(name.to_string()),
        entity: crate::lxs::Entity {
            kind: "homogeneous".into(),
            params: ps,
            loc: loc(60),
        },
        object_to_world: Xform::identity(),
    });
}

#[test]
fn glass2_reads_a_fresnel_texture_and_disperses_with_it() {
    use crate::lxs::TextureType;
    use crate::texture::tests::add_tex;
    let mut d = scene(vec![
        mat("plain", "glass2", vec![], 1),
        mat(
            "disp",
            "glass2",
            vec![("dispersion", ParamValue::Bool(vec![true]))],
            2,
        ),
    ]);
    let cauchy = vec![("cauchya", f(1.5)), ("cauchyb", f(0.05))];
    add_tex(&mut d, "ct", TextureType::Fresnel, "cauchy", cauchy);
    add_tex_volume(&mut d, "glass", "ct");
    add_volume(&mut d, "water", 1.333);
    let mut set = MaterialSet::build(&d, &[0, 1], &MaterialCtx::default()).unwrap();
    let plain = set.bind_media(&d, 0, Some("glass"), None).unwrap();
    let disp = set.bind_media(&d, 1, Some("glass"), Some("water")).unwrap();
    // Without dispersion: the mean index over 380–720 nm, 1.5 + 0.05 × mean(1/λ²) with
    // mean(1/λ²) ≈ (1/0.38 − 1/0.72) / 0.34 = 3.655 µm⁻², so 1.6828.
    assert!(
        (eta_of(&set, plain) - 1.6828).abs() < 1e-3,
        "{}",
        eta_of(&set, plain)
    );
    assert!(!set.get(Some(plain)).disperses());
    assert!(set.get(Some(plain)).dispersion(&flat_si(), 0.5).is_none());
    // With dispersion: the lobes keep the mean ratio; at 500 nm the ratio is
    // (1.5 + 0.05 / 0.25) / 1.333.
    let m = set.get(Some(disp));
    assert!(m.disperses());
    let base = eta_of(&set, disp);
    assert!((base - 1.6828 / 1.333).abs() < 1e-3, "{base}");
    let si = flat_si();
    let d500 = m.dispersion(&si, 0.5).expect("disperses");
    assert!((base + d500.shift(500.0) - 1.7 / 1.333).abs() < 1e-5);
    assert!(
        d500.shift(450.0) > d500.shift(650.0),
        "blue bends more than red"
    );
    assert!(set.warnings.is_empty(), "{:?}", set.warnings);
}
