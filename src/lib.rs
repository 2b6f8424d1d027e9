//! luxfarm render core: LuxRender scene parsing, scene building, rendering, films and FLM.
//!
//! Data flows one way (see DESIGN.md):
//! `lxs` (text -> SceneDescription) -> `scene` (build only what is referenced) ->
//! `render` (seeded sample streams) -> `film` (f64 sums per light group, Film parameters, FLM)
//! -> `tonemap` (film sums to RGB) -> `imageio` (pixel buffers to PNG/TGA/EXR bytes) ->
//! `output` (the files the Film asks for, named the same way locally and on a farm).
//! `halt` reads the film (through `tonemap` for the convergence test) and says when a render
//! is done. Each stage imports only the stages before it: `film` imports none of `tonemap`,
//! `imageio`, `output`; `imageio` imports neither `film` nor `tonemap`. `atomic_write` sits
//! below them all: every file written (FLM, images, the master's checkpoints) goes through it.
//!
//! Plugin families live in one folder each, one file per plugin: `camera`, `sampler`, `filter`,
//! `shape`, `light`, `material`, `texture`, `integrator`, `tonemap`.

pub mod accel;
pub mod atomic_write;
pub mod camera;
pub mod film;
pub mod filter;
pub mod formats;
pub mod geometry;
pub mod halt;
pub mod imageio;
pub mod integrator;
pub mod light;
pub mod lxs;
pub mod material;
pub mod output;
pub mod plugin;
pub mod render;
pub mod sampler;
pub mod sampling;
pub mod scene;
pub mod shape;
pub mod spectrum;
pub mod texture;
pub mod tonemap;
