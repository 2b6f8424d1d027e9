//! Everything the master asks of the render core: inspecting a scene (parsed confined to its
//! bundle directory), films (new, checkpoints), the job's outputs and images, and the halt
//! rules' convergence state.
//!
//! Nothing here encodes, tonemaps or decides by itself: images and the files a Film asks for
//! come from `luxfarm::output` (the same code `luxfarm render` uses), atomic writes from
//! `luxfarm::atomic_write`, halt decisions from `luxfarm::halt`.

use crate::codec;
use crate::error::{Result, ServerError};
use luxfarm::atomic_write::{write_atomic, FileError};
use luxfarm::fileio::SceneFiles;
pub use luxfarm::film::Film;
use luxfarm::film::{BufferType, FilmParams};
pub use luxfarm::halt::Convergence;
use luxfarm::lxs::ParseOptions;
use luxfarm::output;
use std::path::{Path, PathBuf};

/// What the master needs to know about a scene.
#[derive(Clone, Debug)]
pub struct SceneInfo {
    pub params: FilmParams,
    /// Buffer (crop window) size.
    pub width: u32,
    pub height: u32,
    pub pixels: u64,
    /// Pixels of the sample extent (the buffer widened by the pixel filter's width): what a
    /// pass samples and haltspp counts against, as LuxRender's `samplePerPass`
    /// (`luxfarm::render::extent`).
    pub pass_pixels: u64,
    pub groups: Vec<String>,
    /// The film's buffers (a bidirectional render adds a per-screen light buffer), as the
    /// workers' films have them.
    pub buffers: Vec<BufferType>,
    pub haltspp: Option<f64>,
    pub halttime: Option<f64>,
    pub haltthreshold: Option<f64>,
    pub convergence_step: f64,
    /// The sampler draws pixels by a noise-aware sampling map (`"bool noiseaware"`): the
    /// master builds it from the merged film and sends it to the workers.
    pub noise_aware: bool,
    /// Why the scene's sampler takes no sampling maps (metropolis, erpt), when it does not:
    /// a user sampling map is then stored but not applied (`crate::usermap`).
    pub map_refusal: Option<&'static str>,
    /// Base name of the outputs in the job's output directory (`output::farm_basename`: the
    /// last component of the film's `filename`, else the scene's stem).
    pub basename: String,
    /// The job's name when the submission gives none.
    pub name: String,
    /// The scene file inside its bundle (for messages).
    pub scene: String,
    /// Whether the scene has a Camera statement, and how many shapes (object instances
    /// included) and lights it holds: what admission control asks of a renderable scene.
    pub has_camera: bool,
    pub shapes: usize,
    pub lights: usize,
}

/// Parses `root/scene` with its Includes confined to `root` and reads its film parameters.
/// Scene errors become 400s naming file:line:column.
pub fn inspect(root: &Path, scene: &Path, frame: Option<i64>) -> Result<SceneInfo> {
    let opts = ParseOptions {
        confine_to_root: true,
        frame,
        ..ParseOptions::default()
    };
    let path = root.join(scene);
    let desc = luxfarm::formats::load(&path, &opts).map_err(|e| {
        ServerError::BadRequest(format!("scene error: {}", strip_root(&e.to_string(), root)))
    })?;
    // Every file the scene names must lie inside the bundle, as the workers will require.
    let base = path.parent().unwrap_or(root);
    let files = SceneFiles::confined(root, base).map_err(ServerError::internal)?;
    luxfarm_wire::bundle::check_scene_files(&desc, &files).map_err(|e| {
        ServerError::BadRequest(format!("scene error: {}", strip_root(&e.to_string(), root)))
    })?;
    let mut params = FilmParams::from_entity(desc.film.as_ref()).map_err(|e| {
        ServerError::BadRequest(format!("film error: {}", strip_root(&e.to_string(), root)))
    })?;
    // The camera response file, read like the scene's other files (its outputs apply it).
    params.tonemap.effects.load_response(&files).map_err(|m| {
        ServerError::BadRequest(format!(
            "film error: cameraresponse: {}",
            strip_root(&m, root)
        ))
    })?;
    let basename = output::farm_basename(scene, &params);
    // A job's default name: the Film's filename when the scene gives one, else the scene's
    // own name in the bundle.
    let stem = scene
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("scene");
    let name = desc
        .film
        .as_ref()
        .and_then(|f| f.params.string("filename"))
        .and_then(|f| Path::new(f).file_name().and_then(|n| n.to_str()))
        .filter(|n| !n.is_empty())
        .unwrap_or(stem)
        .to_string();
    let groups = if desc.light_groups.is_empty() {
        vec!["default".to_string()]
    } else {
        desc.light_groups.clone()
    };
    Ok(SceneInfo {
        width: params.x_pixel_count,
        height: params.y_pixel_count,
        pixels: params.pixel_count(),
        pass_pixels: luxfarm::render::SampleExtent::of_scene(&desc)
            .map_or(params.pixel_count(), |e| e.pixels()),
        groups,
        buffers: luxfarm::render::film_buffers(&desc),
        haltspp: params.haltspp.map(f64::from),
        halttime: params.halttime.map(f64::from),
        haltthreshold: params.haltthreshold.map(f64::from),
        convergence_step: params.convergence_step.max(1.0),
        noise_aware: noise_aware(&desc),
        map_refusal: map_refusal(&desc),
        basename,
        name,
        scene: scene.to_string_lossy().replace('\\', "/"),
        has_camera: desc.camera.is_some(),
        shapes: desc.shapes.len() + desc.instances.len(),
        lights: desc.lights.len(),
        params,
    })
}

/// Whether the scene's sampler is noise-aware, as the render core reads it (a sampler that
/// does not build is refused by the workers anyway: no map then).
fn noise_aware(desc: &luxfarm::lxs::SceneDescription) -> bool {
    let mut warnings = Vec::new();
    luxfarm::sampler::Sampler::build(desc.sampler.as_ref(), &mut warnings)
        .is_ok_and(|s| s.noise_aware())
}

/// Why the scene's sampler takes no sampling maps, when it does not (a sampler that does not
/// build: none, the workers refuse the scene anyway).
fn map_refusal(desc: &luxfarm::lxs::SceneDescription) -> Option<&'static str> {
    let mut warnings = Vec::new();
    luxfarm::sampler::Sampler::build(desc.sampler.as_ref(), &mut warnings)
        .ok()
        .and_then(|s| s.map_refusal())
}

/// Error messages name files inside the bundle relative to it, not the master's disk.
fn strip_root(msg: &str, root: &Path) -> String {
    let root = format!("{}/", root.display());
    msg.replace(&root, "")
}

/// An empty film of the scene's layout.
pub fn new_film(info: &SceneInfo) -> Film {
    Film::with_buffers(
        info.width,
        info.height,
        info.groups.clone(),
        info.buffers.clone(),
    )
    .unwrap_or_else(|_| Film::new(info.width, info.height, info.groups.clone()))
}

/// Writes a checkpoint (lossless `lxd1`) atomically, streamed to the file (no encoded copy
/// of the film in memory).
pub fn write_checkpoint(film: &Film, path: &Path) -> Result<()> {
    write_atomic(path, |w| {
        codec::encode_to(film, w).map_err(|source| FileError {
            path: path.to_path_buf(),
            source,
        })
    })
    .map_err(|e: FileError| ServerError::Io(e.source))
}

/// Reads a checkpoint (errors leave naming the file to the caller).
pub fn read_checkpoint(path: &Path) -> Result<Film> {
    let bytes = std::fs::read(path)?;
    codec::decode(&bytes).map_err(|e| ServerError::Internal(e.to_string()))
}

/// FLM bytes of a film (LuxRender's format, for downloads and outputs).
pub fn flm_bytes(film: &Film, info: &SceneInfo) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    luxfarm::film::flm::write_flm(film, &info.params, &mut out).map_err(ServerError::internal)?;
    Ok(out)
}

/// Writes the job's outputs under `dir`: the files the scene's Film asks for, named
/// `BASENAME.exr`, `.png`, `.tga`, `.flm` as `luxfarm render` names them.
pub fn write_outputs(film: &Film, info: &SceneInfo, dir: &Path) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    output::write_outputs(film, &info.params, &dir.join(&info.basename))
        .map_err(ServerError::internal)
}

/// A tonemapped 8-bit PNG of the film (the scene's tonemapper), scaled down so its longer
/// side is at most `max_size`.
pub fn png_bytes(film: &Film, info: &SceneInfo, max_size: Option<u32>) -> Result<Vec<u8>> {
    output::preview_png(film, &info.params.tonemap, max_size).map_err(ServerError::internal)
}

/// An EXR (linear RGB, f32, untonemapped) of the film.
pub fn exr_bytes(film: &Film, info: &SceneInfo) -> Result<Vec<u8>> {
    output::linear_exr(film, &info.params.tonemap).map_err(ServerError::internal)
}
