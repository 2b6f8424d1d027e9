//! luxfarm render core: scene formats, the world and its render setup, rendering, films and
//! FLM, tonemapping and outputs. ARCHITECTURE.md (repository root) maps it.
//!
//! Data flows one way:
//! `formats` (any scene file -> `lxs::SceneDescription`) -> `render::setup` (the render setup:
//! camera, film parameters, filter, sampler, integrator; and the `scene::World`: geometry,
//! materials, textures, lights — never importing an integrator) -> `render` (seeded sample
//! streams) -> `film` (f64 sums per light group, Film parameters, FLM) -> `tonemap` (film
//! sums to RGB) -> `imageio` (pixel buffers to PNG/TGA/EXR bytes) -> `output` (the files the
//! Film asks for, named the same way locally and on a farm). `halt` reads the film (through
//! `tonemap` for the convergence test) and says when a render is done. Each stage imports only
//! the stages before it; `tests/architecture.rs` checks it. `atomic_write` sits below them
//! all: every file written (FLM, images, the master's checkpoints) goes through it; `fileio`
//! beside it opens every file a scene names (confined to the bundle on a farm). `isa` names the
//! x86-64 level the code was built for and the one the CPU supports (the production install's
//! per-level binaries).
//!
//! Plugin families live in one folder each, one file per plugin, built by one convention
//! (`plugin`): `camera`, `sampler`, `filter`, `shape`, `light`, `material`, `texture`,
//! `integrator`, `tonemap`. Shared building blocks: `geometry`, `spectrum`, `sampling`.

pub mod accel;
pub mod atomic_write;
pub mod camera;
pub mod fileio;
pub mod film;
pub mod filter;
pub mod formats;
pub mod geometry;
pub mod halt;
pub mod imageio;
pub mod integrator;
pub mod isa;
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
pub mod volume;
