//! luxfarm render core: LuxRender scene parsing, scene building, rendering, films and FLM.
//!
//! Data flows one way (see DESIGN.md):
//! `lxs` (text -> SceneDescription) -> `scene` (build only what is referenced) ->
//! `render` (seeded sample streams) -> `film` (f64 sums per light group, FLM) -> `tonemap`
//! -> `imageio` (PNG/EXR/TGA).
//!
//! Plugin families live in one folder each, one file per plugin: `camera`, `sampler`, `filter`,
//! `shape`, `light`, `material`, `texture`, `integrator`, `tonemap`.

pub mod accel;
pub mod camera;
pub mod film;
pub mod filter;
pub mod formats;
pub mod geometry;
pub mod imageio;
pub mod integrator;
pub mod light;
pub mod lxs;
pub mod material;
pub mod plugin;
pub mod render;
pub mod sampler;
pub mod sampling;
pub mod scene;
pub mod shape;
pub mod spectrum;
pub mod texture;
pub mod tonemap;
