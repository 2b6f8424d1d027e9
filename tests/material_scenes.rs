//! Material classes end to end: `tests/data/surfaces/materials.lxs` (every LuxRender 1.x
//! material class with its parameters) builds without a fallback or refusal warning and
//! renders a finite, lit image; legacy names keep their parameters with a located warning;
//! allmaterials_08 from LuxRender's TestSuite gets its glass2 index from its volumes, a
//! scatter surface and its checkerboard floor.

mod render_util;

use luxfarm::lxs::SceneDescription;
use luxfarm::material::MaterialKind;
use luxfarm::render::setup::Renderable;
use luxfarm::render::SessionOptions;
use render_util::*;
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/surfaces")
        .join(name)
}

/// The material name of every world shape, in primitive order.
fn shape_materials(desc: &SceneDescription) -> Vec<Option<String>> {
    desc.shapes
        .iter()
        .filter(|s| !s.portal)
        .map(|s| {
            s.material
                .and_then(|m| desc.materials.get(m))
                .and_then(|m| m.name.clone())
        })
        .collect()
}

/// The fallback warning of a scene with media whose surface integrator cannot carry paths
/// through them (bidirectional renders it with path).
fn is_media_warning(w: &str) -> bool {
    w.contains("does not render participating media yet")
}

#[test]
fn every_material_class_builds_without_fallback_and_renders() {
    let path = data("materials.lxs");
    let desc = parse(&path);
    let base = path.parent().unwrap();
    let scene = Renderable::build(&desc, base).expect("scene builds");
    let warnings: Vec<String> = desc
        .warnings
        .iter()
        .chain(&scene.warnings)
        .map(|d| d.to_string())
        .filter(|w| !is_media_warning(w))
        .collect();
    assert!(warnings.is_empty(), "{warnings:#?}");
    // Each sphere got the material class it names (no fallback to the default matte).
    let names = shape_materials(&desc);
    let mut kinds = Vec::new();
    for (prim, name) in names.iter().enumerate() {
        let Some(name) = name else { continue };
        if name == "floor" {
            continue;
        }
        let m = scene.world.material(prim as u32);
        let md = desc.named_material(name).expect("named material exists");
        assert_eq!(m.type_name, md.entity.kind, "{name}");
        kinds.push(md.entity.kind.clone());
        if name == "glass2" {
            match &m.kind {
                MaterialKind::Glass2(g) => assert!((glass2_eta(g) - 1.459).abs() < 1e-5),
                other => panic!("{other:?}"),
            }
        }
    }
    kinds.sort();
    kinds.dedup();
    for class in [
        "carpaint",
        "cloth",
        "doubleside",
        "glass",
        "glass2",
        "glossy",
        "glossy_lossy",
        "glossycoating",
        "glossytranslucent",
        "layered",
        "matte",
        "mattetranslucent",
        "metal",
        "metal2",
        "mirror",
        "mix",
        "null",
        "roughglass",
        "scatter",
        "shinymetal",
        "velvet",
    ] {
        assert!(kinds.iter().any(|k| k == class), "{class} missing");
    }
    let film = render(
        &desc,
        base,
        SessionOptions {
            threads: 2,
            seed: 3,
            stream: 0,
        },
        2,
    );
    let xyz = normalized_xyz(&film);
    assert!(xyz.iter().all(|p| p.iter().all(|v| v.is_finite())));
    let mean_y = xyz.iter().map(|p| p[1]).sum::<f64>() / xyz.len() as f64;
    assert!(mean_y > 0.0, "black image");
}

#[test]
fn legacy_materials_keep_their_parameters_with_a_located_warning() {
    let text = r#"LookAt 0 -5 1 0 0 1 0 0 1
Camera "perspective" "float fov" [40]
Film "fleximage" "integer xresolution" [8] "integer yresolution" [8] "integer haltspp" [1]
WorldBegin
LightSource "point" "point from" [0 -3 3] "color L" [10 10 10]
AttributeBegin
Material "plastic" "color Kd" [0.5 0.5 0.5] "color Ks" [0.2 0.2 0.2] "float roughness" [0.000571]
Shape "sphere" "float radius" [1]
AttributeEnd
AttributeBegin
Material "substrate" "color Kd" [0.5 0.5 0.5] "float uroughness" [0.2] "float vroughness" [0.05]
Translate 3 0 0
Shape "sphere" "float radius" [1]
AttributeEnd
WorldEnd
"#;
    let path = Path::new("/tmp/luxfarm-material-legacy.lxs");
    let desc = parse_text(text, path);
    let scene = Renderable::build(&desc, Path::new("/tmp")).expect("builds");
    let mut w: Vec<String> = scene.warnings.iter().map(|d| d.to_string()).collect();
    w.extend(desc.warnings.iter().map(|d| d.to_string()));
    let legacy: Vec<&String> = w.iter().filter(|m| m.contains("legacy")).collect();
    assert_eq!(legacy.len(), 2, "{w:#?}");
    assert!(legacy[0].contains(":7:") && legacy[0].contains("plastic"));
    assert!(legacy[1].contains(":11:") && legacy[1].contains("substrate"));
    assert!(!w.iter().any(|m| m.contains("unused")), "{w:#?}");
    for prim in 0..2 {
        let m = scene.world.material(prim);
        let MaterialKind::GlossyLossy(g) = &m.kind else {
            panic!("{:?}", m.kind)
        };
        let u = g.u.as_const().unwrap();
        let v = g.v.as_const().unwrap();
        if prim == 0 {
            assert_eq!((u, v), (0.000571, 0.000571));
        } else {
            assert_eq!((u, v), (0.2, 0.05));
        }
    }
}

#[test]
fn allmaterials_08_glass2_scatter_and_checker_as_luxrender_defines_them() {
    let path = scene_path("testsuite/allmaterials_08/allmaterials_08.lxs");
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace(
            "\"integer xresolution\" [700]",
            "\"integer xresolution\" [24]",
        )
        .replace(
            "\"integer yresolution\" [700]",
            "\"integer yresolution\" [24]",
        );
    let desc = parse_text(&text, &path);
    let base = path.parent().unwrap();
    let scene = Renderable::build(&desc, base).expect("allmaterials_08 builds");
    let w: Vec<String> = scene.warnings.iter().map(|d| d.to_string()).collect();
    assert!(
        !w.iter()
            .any(|m| m.contains("not supported: using the default matte")),
        "{w:#?}"
    );
    // Its clear and homogeneous volumes are rendered: the five that act on light ("world" is
    // a vacuum), two of them scattering; no volume is reported as ignored.
    let media = scene.world.media().expect("allmaterials_08 has media");
    assert_eq!(media.media.len(), 5);
    assert_eq!(media.media.iter().filter(|m| m.scatters()).count(), 2);
    assert!(
        !w.iter()
            .any(|m| m.contains("ignored") && m.contains("olume")),
        "{w:#?}"
    );
    let names = shape_materials(&desc);
    let (mut glass2, mut scatter, mut cube) = (0, 0, 0);
    for (prim, name) in names.iter().enumerate() {
        let m = scene.world.material(prim as u32);
        match name.as_deref() {
            Some("glass2") => {
                glass2 += 1;
                let MaterialKind::Glass2(g) = &m.kind else {
                    panic!("{:?}", m.kind)
                };
                // Interior "glass2" (fresnel 1.459) in Exterior "world" (1).
                assert!((glass2_eta(g) - 1.459).abs() < 1e-5, "{}", glass2_eta(g));
            }
            Some("mix") => {
                let MaterialKind::Mix(mix) = &m.kind else {
                    panic!("{:?}", m.kind)
                };
                let MaterialKind::Glass2(g) = &mix.m1.kind else {
                    panic!("{:?}", mix.m1.kind)
                };
                assert!((glass2_eta(g) - 1.459).abs() < 1e-5);
                assert!(matches!(mix.m2.kind, MaterialKind::Scatter(_)));
            }
            Some("scatter") => {
                scatter += 1;
                assert!(matches!(m.kind, MaterialKind::Scatter(_)), "{:?}", m.kind);
            }
            Some("cube") => {
                cube += 1;
                let MaterialKind::Matte(mm) = &m.kind else {
                    panic!("{:?}", m.kind)
                };
                assert!(mm.kd.as_const().is_none(), "the checker texture drives Kd");
            }
            _ => {}
        }
    }
    assert!(glass2 > 0 && scatter > 0 && cube > 0);
    let film = render(
        &desc,
        base,
        SessionOptions {
            threads: 2,
            seed: 1,
            stream: 0,
        },
        1,
    );
    let xyz = normalized_xyz(&film);
    assert!(xyz.iter().all(|p| p.iter().all(|v| v.is_finite())));
    assert!(xyz.iter().map(|p| p[1]).sum::<f64>() > 0.0);
}

#[test]
fn null_surfaces_neither_show_nor_cast_shadows() {
    let scene = |with_null: bool| {
        let null = if with_null {
            "AttributeBegin\nMaterial \"null\"\nTranslate 0 0 1\nShape \"sphere\" \"float radius\" [0.6]\nAttributeEnd\n"
        } else {
            ""
        };
        format!(
            r#"LookAt 0 -4 4 0 0 0 0 0 1
Camera "perspective" "float fov" [45]
Film "fleximage" "integer xresolution" [16] "integer yresolution" [16] "integer haltspp" [1]
SurfaceIntegrator "directlighting"
WorldBegin
LightSource "point" "point from" [0 0 3] "color L" [10 10 10]
Material "matte"
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point P" [-3 -3 0 3 -3 0 3 3 0 -3 3 0]
{null}WorldEnd
"#
        )
    };
    let opts = SessionOptions {
        threads: 1,
        seed: 4,
        stream: 0,
    };
    let path = Path::new("/tmp/luxfarm-material-null.lxs");
    let plain = render(&parse_text(&scene(false), path), Path::new("/tmp"), opts, 1);
    let with = render(&parse_text(&scene(true), path), Path::new("/tmp"), opts, 1);
    let (a, b) = (normalized_xyz(&plain), normalized_xyz(&with));
    for (p, q) in a.iter().zip(&b) {
        assert!(
            (p[1] - q[1]).abs() <= 1e-3 * p[1].max(1.0),
            "{p:?} vs {q:?}"
        );
    }
}

#[test]
fn compositing_flags_apply_where_luxrender_applies_them() {
    let scene = |integrator: &str, compo: &str| {
        format!(
            r#"LookAt 0 -4 0 0 0 0 0 0 1
Camera "perspective" "float fov" [20]
Film "fleximage" "integer xresolution" [9] "integer yresolution" [9] "integer haltspp" [1]
SurfaceIntegrator "{integrator}"
WorldBegin
LightSource "point" "point from" [0 -3 2] "color L" [10 10 10]
AttributeBegin
Material "matte" {compo}
Shape "sphere" "float radius" [1]
AttributeEnd
WorldEnd
"#
        )
    };
    let opts = SessionOptions {
        threads: 1,
        seed: 2,
        stream: 0,
    };
    let centre = |text: String| {
        let path = Path::new("/tmp/luxfarm-material-compo.lxs");
        let desc = parse_text(&text, path);
        let f = render(&desc, Path::new("/tmp"), opts, 1);
        let p = f.pixel(0, 0, 4, 4).expect("pixel");
        (p[1] / p[4], p[3] / p[4])
    };
    let hidden = r#""bool compo_visible_material" ["false"]"#;
    // distributedpath: an invisible material gives alpha 0 and no light.
    let (y, a) = centre(scene("distributedpath", hidden));
    assert_eq!((y, a), (0.0, 0.0));
    // An overridden alpha replaces the hit's alpha, the surface stays visible.
    let (y, a) = centre(scene(
        "distributedpath",
        r#""bool compo_override_alpha" ["true"] "float compo_override_alpha_value" [0.25]"#,
    ));
    assert!(y > 0.0 && (a - 0.25).abs() < 1e-6, "{y} {a}");
    // LuxRender's path integrator ignores the flags.
    let (y, a) = centre(scene("path", hidden));
    assert!(y > 0.0 && a == 1.0);
}

/// glass2's index (its volumes' indices are constant over the surface).
fn glass2_eta(g: &luxfarm::material::glass2::Glass2) -> f32 {
    g.eta(&luxfarm::geometry::SurfaceInteraction::default())
}
