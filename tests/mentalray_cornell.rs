//! The sample mental ray scene (`../shared/scenes/formats/cornell_box/cornell_box.mi`)
//! against its LuxRender twin (`cornell_box.lxs`, written by the same exporter).
//!
//! The two files describe the same Cornell box in different frames: the .mi world is in
//! millimetres with y up (the exporter wraps the scene in an instgroup rotated from Blender's
//! z-up and writes the camera in the rotated frame), the .lxs world in metres with z up. The
//! similarity between them is fixed: p_mi = 1000 · (x, z, −y) of p_lxs. Every comparison
//! maps the .lxs side through it.
//!
//! The renders: luxfarm renders both at 128×128 with the same sampler, filter and path
//! integrator (maxdepth 6, what the .mi's `trace depth` and `"gi depth"` give; the .lxs asks
//! for metropolis + bidirectional, which luxfarm renders with path anyway), twice each with
//! different seeds, and compares the means of 64×64-pixel blocks. The materials mean the same: the .mi's box shaders are the
//! exporter's MDL `matte` with a `tint` (the .lxs's matte `Kd`) and a `roughness` 0.5 that
//! luxfarm does not model (the .lxs twin has no roughness either: both render Lambertian),
//! and the emitter's `one_color` white is the .lxs's matte Kd 1. The light's units differ:
//! `physical_light` colour 6·10⁶ over the emitter's 13 650 mm² is radiance
//! 6·10⁶/(4π·13 650) = 34.98 (its object-light normalisation, see `formats::mi::lights`),
//! while the .lxs's area light is LuxRender's 1 W × 17 lm/W over 0.01365 m², radiance
//! 17/(π·0.01365·Y(white)). So the .mi render is brighter by the ratio of the two radiances,
//! computed here from the two files' own numbers; every block must agree within 5 % once
//! that one factor is taken out.
//!
//! The .lxs film asks for `outlierrejection_k` 10, which the .mi has no counterpart for. It
//! drops the rare bright samples that carry most of the indirect light on the ceiling and in
//! the contact shadows (and the light's edge pixels), so with it the .lxs render is darker
//! there by 15–35 % in 32-pixel blocks (measured before the comparison moved to 64-pixel
//! blocks): a film setting, not a difference of the scenes. Both
//! films render without it here.

mod render_util;

use glam::{DMat4, DVec3};
use luxfarm::formats;
use luxfarm::lxs::{Entity, ParamSet, ParamValue, ParseOptions, SceneDescription};
use luxfarm::render::SessionOptions;
use luxfarm::spectrum::{illuminant_y, Rgb};
use render_util::*;
use std::path::PathBuf;

fn twins() -> (SceneDescription, SceneDescription, PathBuf) {
    let mi = scene_path("formats/cornell_box/cornell_box.mi");
    let opts = ParseOptions::default();
    let a = formats::load(&mi, &opts).expect("the .mi imports");
    let b = formats::load(&mi.with_extension("lxs"), &opts).expect("the .lxs parses");
    (a, b, mi.parent().unwrap().to_path_buf())
}

/// The .lxs world in the .mi's frame: (x, y, z) → 1000 · (x, z, −y).
fn similarity() -> DMat4 {
    DMat4::from_cols_array(&[
        1000.0, 0.0, 0.0, 0.0, //
        0.0, 0.0, -1000.0, 0.0, //
        0.0, 1000.0, 0.0, 0.0, //
        0.0, 0.0, 0.0, 1.0,
    ])
}

/// World-space points and triangles of a trianglemesh/mesh shape.
fn world_mesh(entity: &Entity, to_world: DMat4) -> (Vec<DVec3>, Vec<[usize; 3]>) {
    let p = entity.params.points("P").unwrap();
    let pts: Vec<DVec3> = p
        .iter()
        .map(|v| to_world.transform_point3(DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64)))
        .collect();
    let mut tris = Vec::new();
    if let Some(ix) = entity
        .params
        .ints("indices")
        .or_else(|| entity.params.ints("triindices"))
    {
        tris.extend(
            ix.chunks(3)
                .map(|c| [c[0] as usize, c[1] as usize, c[2] as usize]),
        );
    }
    if let Some(q) = entity.params.ints("quadindices") {
        for c in q.chunks(4) {
            let c = [c[0] as usize, c[1] as usize, c[2] as usize, c[3] as usize];
            tris.push([c[0], c[1], c[2]]);
            tris.push([c[0], c[2], c[3]]);
        }
    }
    (pts, tris)
}

fn bounds(pts: &[DVec3]) -> (DVec3, DVec3) {
    let lo = pts
        .iter()
        .fold(DVec3::splat(f64::INFINITY), |a, p| a.min(*p));
    let hi = pts
        .iter()
        .fold(DVec3::splat(f64::NEG_INFINITY), |a, p| a.max(*p));
    (lo, hi)
}

fn area(pts: &[DVec3], tris: &[[usize; 3]]) -> f64 {
    tris.iter()
        .map(|t| {
            0.5 * (pts[t[1]] - pts[t[0]])
                .cross(pts[t[2]] - pts[t[0]])
                .length()
        })
        .sum()
}

/// (bounds, area, emits) of every shape, in the .mi frame.
fn shapes(d: &SceneDescription, to_mi: DMat4) -> Vec<((DVec3, DVec3), f64, bool)> {
    d.shapes
        .iter()
        .map(|sh| {
            let (p, t) = world_mesh(&sh.entity, to_mi * sh.object_to_world.start());
            (bounds(&p), area(&p, &t), sh.area_light.is_some())
        })
        .collect()
}

#[test]
fn camera_objects_and_light_match_the_lxs_twin() {
    let (mi, lxs, _) = twins();
    let sim = similarity();
    // Camera: position, axes and field of view.
    let cm = mi.camera.as_ref().unwrap();
    let cl = lxs.camera.as_ref().unwrap();
    let c2w_mi = cm.world_to_camera.start().inverse();
    let c2w_lxs = sim * cl.world_to_camera.start().inverse();
    let eye_mi = c2w_mi.transform_point3(DVec3::ZERO);
    let eye_lxs = c2w_lxs.transform_point3(DVec3::ZERO);
    assert!((eye_mi - eye_lxs).length() < 0.01, "{eye_mi} vs {eye_lxs}");
    for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
        let a = c2w_mi.transform_vector3(axis).normalize();
        let b = c2w_lxs.transform_vector3(axis).normalize();
        assert!((a - b).length() < 1e-5, "camera axis {axis}: {a} vs {b}");
    }
    let fov = |e: &Entity| e.params.float("fov").unwrap();
    assert!((fov(&cm.entity) - fov(&cl.entity)).abs() < 1e-3);
    assert_eq!(cm.entity.kind, cl.entity.kind);
    let res = |d: &SceneDescription| {
        let f = d.film.as_ref().unwrap();
        (f.params.int("xresolution"), f.params.int("yresolution"))
    };
    assert_eq!(res(&mi), res(&lxs));

    // Every object's bounds (the .mi's cornell_box splits by material tag as the .lxs's
    // meshes do by NamedMaterial), matched one to one.
    let a = shapes(&mi, DMat4::IDENTITY);
    let mut b = shapes(&lxs, sim);
    assert_eq!(a.len(), b.len(), "shape counts");
    for (bb, ar, emits) in &a {
        let i = b
            .iter()
            .position(|(ob, oa, oe)| {
                (ob.0 - bb.0).length() < 0.1
                    && (ob.1 - bb.1).length() < 0.1
                    && oe == emits
                    && (oa - ar).abs() < 1e-4 * ar
            })
            .unwrap_or_else(|| panic!("no .lxs shape with bounds {bb:?}, area {ar}"));
        b.remove(i);
    }

    // The light: one emitter, same place, same size.
    let light = |v: &[((DVec3, DVec3), f64, bool)]| {
        let e: Vec<_> = v.iter().filter(|s| s.2).collect();
        assert_eq!(e.len(), 1);
        (0.5 * (e[0].0 .0 + e[0].0 .1), e[0].0 .1 - e[0].0 .0, e[0].1)
    };
    let (pa, sa, aa) = light(&a);
    let (pb, sb, ab) = light(&shapes(&lxs, sim));
    assert!((pa - pb).length() < 0.01, "light centre {pa} vs {pb}");
    assert!((sa - sb).length() < 0.01, "light extent {sa} vs {sb}");
    assert!((aa - 13650.0).abs() < 0.01 && (ab - 13650.0).abs() < 0.01);
}

/// Same sampler, filter, integrator and a 128×128 film for both, without the .lxs film's
/// outlier rejection (see the module docs).
fn for_comparison(d: &mut SceneDescription) {
    let set = |e: &mut Entity, name: &str, v: ParamValue| e.params.add(name, v);
    let film = d.film.as_mut().unwrap();
    film.params
        .params
        .retain(|p| p.name != "outlierrejection_k");
    set(film, "xresolution", ParamValue::Integer(vec![128]));
    set(film, "yresolution", ParamValue::Integer(vec![128]));
    let mut sampler = Entity {
        kind: "random".into(),
        params: ParamSet::new(),
        loc: Default::default(),
    };
    set(&mut sampler, "pixelsamples", ParamValue::Integer(vec![8]));
    d.sampler = Some(sampler);
    let mut filter = Entity {
        kind: "box".into(),
        ..Default::default()
    };
    set(&mut filter, "xwidth", ParamValue::Float(vec![0.5]));
    set(&mut filter, "ywidth", ParamValue::Float(vec![0.5]));
    d.pixel_filter = Some(filter);
    let mut path = Entity {
        kind: "path".into(),
        ..Default::default()
    };
    set(&mut path, "maxdepth", ParamValue::Integer(vec![6]));
    d.surface_integrator = Some(path);
}

/// Side of the square blocks whose means are compared (pixels of the 128×128 renders).
const BLOCK: u32 = 64;

#[test]
fn renders_agree_in_block_means() {
    let (mut mi, mut lxs, dir) = twins();
    // The emitted radiances, from each file's numbers (see the module docs).
    let sim = similarity();
    let emitter = |d: &SceneDescription, to: DMat4| {
        let sh = d.shapes.iter().find(|s| s.area_light.is_some()).unwrap();
        let (p, t) = world_mesh(&sh.entity, to * sh.object_to_world.start());
        (area(&p, &t), sh.area_light.clone().unwrap())
    };
    let (a_mi, l_mi) = emitter(&mi, DMat4::IDENTITY);
    let (a_lxs, l_lxs) = emitter(&lxs, sim);
    let a_lxs_m2 = a_lxs * 1e-6;
    assert!((a_mi - 13650.0).abs() < 0.01 && (a_lxs_m2 - 0.01365).abs() < 1e-8);
    let radiance_mi = 6.0e6 / (4.0 * std::f64::consts::PI * a_mi);
    let mi_l = l_mi.entity.params.color("L").unwrap()[0] as f64;
    assert!(
        (mi_l - radiance_mi).abs() < 1e-4 * radiance_mi,
        "importer's L {mi_l}"
    );
    let power = l_lxs.entity.params.float("power").unwrap() as f64;
    let y_white = f64::from(illuminant_y(Rgb::WHITE));
    let radiance_lxs = power * 17.0 / (a_lxs_m2 * std::f64::consts::PI * y_white);
    let k = radiance_mi / radiance_lxs;

    for_comparison(&mut mi);
    for_comparison(&mut lxs);
    let opts = |seed| SessionOptions {
        threads: 2,
        seed,
        stream: 0,
    };
    // Two renders of each file, averaged: a single 8-spp render leaves the dimmest 32-pixel
    // blocks 5-8 % apart by noise alone in one seed pair out of three.
    let means = |d: &SceneDescription, seeds: [u64; 2]| {
        let runs = seeds.map(|s| block_means(&render(d, &dir, opts(s), 1), BLOCK));
        let n = runs[0].len();
        (0..n)
            .map(|i| (runs[0][i] + runs[1][i]) / 2.0)
            .collect::<Vec<f64>>()
    };
    let a = means(&mi, [1, 3]);
    let b = means(&lxs, [2, 4]);
    assert_eq!(a.len(), (128 / BLOCK as usize).pow(2));
    let total = a.iter().sum::<f64>() / b.iter().sum::<f64>();
    eprintln!("expected radiance ratio {k:.4}, rendered mean ratio {total:.4}");
    let mut worst = 0.0f64;
    for (i, (x, y)) in a.iter().zip(&b).enumerate() {
        let r = x / (k * y);
        eprintln!("block {i}: .mi {x:.4e} .lxs {y:.4e} ratio/k {r:.4}");
        worst = worst.max((r - 1.0).abs());
    }
    assert!(worst < 0.05, "worst block differs by {worst}");
}
