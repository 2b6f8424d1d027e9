//! LightWave scenes: `.lws` files (LWSC 3, 4 and 5; LightWave 6 and later) with their LWO2 and
//! LWOB objects, imported at one animation frame into the same [`SceneDescription`] a .lxs
//! file gives.
//!
//! ```text
//! .lws --text.rs (numbered lines)--> scene.rs (globals; items: scene_items.rs; envelope.rs)
//!      --> items.rs Scene
//!   objects --paths.rs (content directory, confinement)--> library.rs
//!          --object.rs: lwo2.rs (+ surf2.rs) | lwob.rs--> model.rs Model
//!   frame --motion.rs (coords.rs)--> placements
//!   --camera.rs, lights.rs, material.rs, mesh.rs (triangulate.rs, projection.rs)-->
//!   --emit.rs (DescriptionBuilder: LuxRender statements)--> SceneDescription
//! ```
//!
//! `assemble.rs` runs these steps. The frame is `ParseOptions::frame`, else the scene's
//! `CurrentFrame`, else its `FirstFrame`; time is frame / `FramesPerSecond`. Errors name the
//! .lws file, line and column, or the object file and the byte offset of the bad chunk (with
//! the .lws line that loaded it); what cannot be rendered is a located warning, one per kind.
//! Every file read counts against `ParseOptions::max_total_bytes`, every chunk length is
//! checked against the bytes left before anything is allocated, and with
//! `ParseOptions::confine_to_root` no file outside the scene's directory is read.

mod assemble;
mod camera;
mod coords;
mod emit;
mod envelope;
mod iff;
mod items;
mod keywords;
mod library;
mod lights;
mod lwo2;
mod lwob;
mod material;
mod mesh;
mod model;
mod motion;
mod object;
mod paths;
mod projection;
mod scene;
mod scene_items;
mod surf2;
mod text;
mod triangulate;

use crate::lxs::{LxsError, ParseOptions, SceneDescription};
use std::path::Path;

/// Imports the LightWave scene at `path` at the frame `opts` asks for.
pub fn load(path: &Path, opts: &ParseOptions) -> Result<SceneDescription, LxsError> {
    assemble::load(path, opts)
}

/// Whether the start of a file is an LWSC scene.
pub fn detect(head: &str) -> bool {
    scene::looks_like_lwsc(head)
}

/// Parses LWSC text and places its items at `frame` without loading objects (pivots of
/// object layers are taken as the origin; for fuzzing and tools): `Ok` with the number of
/// items, or the located error.
pub fn parse_scene_text(name: &str, text: &str, frame: i64) -> Result<usize, LxsError> {
    let p = scene::read(name, text)?;
    let time = p.scene.frame_time(frame);
    let placed = motion::evaluate(&p.scene, time, &|_| glam::DVec3::ZERO)?;
    Ok(placed.len())
}

/// Parses object file bytes (LWO2, LWOB) without a scene (for fuzzing and tools): `Ok` with
/// the number of polygons, or the error.
pub fn parse_object_bytes(name: &str, bytes: &[u8]) -> Result<usize, LxsError> {
    let m = object::parse(bytes, name)?;
    Ok(m.layers.iter().map(|l| l.polygons.len()).sum())
}
