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
