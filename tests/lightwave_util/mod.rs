//! Helpers of the LightWave tests: the shared samples, loading a scene at a frame, shrinking
//! its film for fast renders, reading transforms back, and writing small LWO2 objects and
//! scenes of our own (from the LWO2 and LWSC specifications, not from the samples).

#![allow(dead_code)]

use glam::{DMat4, DVec3};
use luxfarm::lxs::{ParamValue, ParseOptions, SceneDescription};
use std::path::{Path, PathBuf};

/// `../shared/scenes/formats/lightwave` (else /work/shared/...).
pub fn samples() -> PathBuf {
    let local = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared"));
    let base = if local.join("scenes").is_dir() {
        local
    } else {
        PathBuf::from("/work/shared")
    };
    base.join("scenes/formats/lightwave")
}

/// This repository's LightWave test data.
pub fn data() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/lightwave"))
}

pub fn load_at(path: &Path, frame: Option<i64>) -> SceneDescription {
    let opts = ParseOptions {
        frame,
        ..ParseOptions::default()
    };
    luxfarm::formats::load(path, &opts).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Sets the film's resolution (and keeps everything else).
pub fn shrink(desc: &mut SceneDescription, w: i32, h: i32) {
    let film = desc.film.as_mut().expect("a film");
    film.params.add("xresolution", ParamValue::Integer(vec![w]));
    film.params.add("yresolution", ParamValue::Integer(vec![h]));
}

/// The world position of the origin of shape `i` (its object-to-world translation).
pub fn shape_origin(desc: &SceneDescription, i: usize) -> DVec3 {
    let m: DMat4 = desc.shapes[i].object_to_world.start();
    m.transform_point3(DVec3::ZERO)
}

/// Big-endian IFF chunk (4-byte length, padded).
pub fn chunk(id: &[u8; 4], body: &[u8]) -> Vec<u8> {
    let mut v = id.to_vec();
    v.extend_from_slice(&(body.len() as u32).to_be_bytes());
    v.extend_from_slice(body);
    if body.len() % 2 == 1 {
        v.push(0);
    }
    v
}

/// Sub-chunk (2-byte length, padded).
pub fn sub(id: &[u8; 4], body: &[u8]) -> Vec<u8> {
    let mut v = id.to_vec();
    v.extend_from_slice(&(body.len() as u16).to_be_bytes());
    v.extend_from_slice(body);
    if body.len() % 2 == 1 {
        v.push(0);
    }
    v
}

/// A null-terminated string padded to even length.
pub fn s0(s: &str) -> Vec<u8> {
    let mut v = s.as_bytes().to_vec();
    v.push(0);
    if v.len() % 2 == 1 {
        v.push(0);
    }
    v
}

pub fn f4(x: f32) -> Vec<u8> {
    x.to_be_bytes().to_vec()
}

/// An LWO2 file of one layer (pivot given) with `points` and `polys` (each with a surface
/// index into `surfaces`: (name, colour, diffuse, luminosity)).
pub fn lwo2(
    pivot: [f32; 3],
    points: &[[f32; 3]],
    polys: &[(&[u16], u16)],
    surfaces: &[(&str, [f32; 3], f32, f32)],
) -> Vec<u8> {
    lwo2_with(pivot, points, polys, surfaces, &[], &[])
}

/// [`lwo2`] with `extra` chunks (whole chunks, e.g. VMAPs) after the polygons and
/// `surf_extra` sub-chunks at the end of every SURF.
pub fn lwo2_with(
    pivot: [f32; 3],
    points: &[[f32; 3]],
    polys: &[(&[u16], u16)],
    surfaces: &[(&str, [f32; 3], f32, f32)],
    extra: &[Vec<u8>],
    surf_extra: &[u8],
) -> Vec<u8> {
    let mut body = b"LWO2".to_vec();
    let tags: Vec<u8> = surfaces.iter().flat_map(|s| s0(s.0)).collect();
    body.extend(chunk(b"TAGS", &tags));
    let mut layr = vec![0, 0, 0, 0];
    for c in pivot {
        layr.extend(f4(c));
    }
    layr.extend(s0(""));
    body.extend(chunk(b"LAYR", &layr));
    let pnts: Vec<u8> = points.iter().flatten().flat_map(|&c| f4(c)).collect();
    body.extend(chunk(b"PNTS", &pnts));
    let mut pols = b"FACE".to_vec();
    for (vs, _) in polys {
        pols.extend((vs.len() as u16).to_be_bytes());
        for v in *vs {
            pols.extend(v.to_be_bytes());
        }
    }
    body.extend(chunk(b"POLS", &pols));
    let mut ptag = b"SURF".to_vec();
    for (i, (_, s)) in polys.iter().enumerate() {
        ptag.extend((i as u16).to_be_bytes());
        ptag.extend(s.to_be_bytes());
    }
    body.extend(chunk(b"PTAG", &ptag));
    for c in extra {
        body.extend_from_slice(c);
    }
    for (name, color, diff, lumi) in surfaces {
        let mut s = s0(name);
        s.extend(s0(""));
        let mut colr: Vec<u8> = color.iter().flat_map(|&c| f4(c)).collect();
        colr.extend([0, 0]);
        s.extend(sub(b"COLR", &colr));
        s.extend(sub(b"DIFF", &[f4(*diff), vec![0, 0]].concat()));
        s.extend(sub(b"LUMI", &[f4(*lumi), vec![0, 0]].concat()));
        s.extend_from_slice(surf_extra);
        body.extend(chunk(b"SURF", &s));
    }
    chunk(b"FORM", &body)
}

/// A unit square in the XY plane facing -Z (towards a camera at -Z looking +Z), corners
/// listed clockwise seen from the front, as LightWave lists them.
pub fn square_lwo(color: [f32; 3]) -> Vec<u8> {
    lwo2(
        [0.0; 3],
        &[
            [-0.5, -0.5, 0.0],
            [-0.5, 0.5, 0.0],
            [0.5, 0.5, 0.0],
            [0.5, -0.5, 0.0],
        ],
        &[(&[0, 1, 2, 3], 0)],
        &[("Square", color, 1.0, 0.0)],
    )
}

/// An envelope block of one key.
pub fn const_env(v: f64) -> String {
    format!("{{ Envelope\n  1\n  Key {v} 0 0 0 0 0 0 0 0\n  Behaviors 1 1\n}}\n")
}

/// Motion channels 0-8 given as one constant each.
pub fn motion(values: [f64; 9]) -> String {
    let mut s = String::from("NumChannels 9\n");
    for (i, v) in values.iter().enumerate() {
        s += &format!("Channel {i}\n{}", const_env(*v));
    }
    s
}

/// A camera at the origin looking +Z at 64x48.
pub fn camera_block() -> String {
    format!(
        "AddCamera 30000000\nCameraName Camera\nCameraMotion\n{}ZoomFactor 3.2\nFrameSize 64 48\n",
        motion([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0])
    )
}
