//! Everything the master asks of the render core: inspecting a scene (parsed confined to its
//! bundle directory), films (new, decode a delta, FLM checkpoints), images and the convergence
//! test.

use crate::codec;
use crate::error::{Result, ServerError};
use luxfarm::film::convergence::{ConvergenceTest, YeeParams};
pub use luxfarm::film::Film;
use luxfarm::film::FilmParams;
use luxfarm::lxs::{self, ParseOptions};
use std::io::Write;
use std::path::{Path, PathBuf};

/// What the master needs to know about a scene.
#[derive(Clone, Debug)]
pub struct SceneInfo {
    pub params: FilmParams,
    /// Buffer (crop window) size.
    pub width: u32,
    pub height: u32,
    pub pixels: u64,
    pub groups: Vec<String>,
    pub haltspp: Option<f64>,
    pub halttime: Option<f64>,
    pub haltthreshold: Option<f64>,
    pub convergence_step: f64,
    /// Base name of the outputs (the film's `filename`, else the scene's stem).
    pub basename: String,
}

/// Parses `root/scene` with its Includes confined to `root` and reads its film parameters.
/// Scene errors become 400s naming file:line:column.
pub fn inspect(root: &Path, scene: &Path) -> Result<SceneInfo> {
    let opts = ParseOptions {
        confine_to_root: true,
        ..ParseOptions::default()
    };
    let path = root.join(scene);
    let desc = lxs::parse_file(&path, &opts).map_err(|e| {
        ServerError::BadRequest(format!("scene error: {}", strip_root(&e.to_string(), root)))
    })?;
    let params = FilmParams::from_entity(desc.film.as_ref()).map_err(|e| {
        ServerError::BadRequest(format!("film error: {}", strip_root(&e.to_string(), root)))
    })?;
    let stem = scene
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("scene")
        .to_string();
    let basename = Path::new(&params.filename)
        .file_name()
        .and_then(|s| s.to_str())
        .filter(|s| !s.is_empty())
        .unwrap_or(&stem)
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
        groups,
        haltspp: params.haltspp.map(f64::from),
        halttime: params.halttime.map(f64::from),
        haltthreshold: params.haltthreshold.map(f64::from),
        convergence_step: params.convergence_step.max(1.0),
        basename,
        params,
    })
}

/// Error messages name files inside the bundle relative to it, not the master's disk.
fn strip_root(msg: &str, root: &Path) -> String {
    let root = format!("{}/", root.display());
    msg.replace(&root, "")
}

/// An empty film of the scene's layout.
pub fn new_film(info: &SceneInfo) -> Film {
    Film::new(info.width, info.height, info.groups.clone())
}

/// Writes bytes to `path` atomically (temporary file, fsync, rename).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = path.with_extension("tmp");
    {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
    }
    std::fs::rename(&tmp, path)?;
    Ok(())
}

/// Writes a checkpoint (lossless `lxd1`) atomically.
pub fn write_checkpoint(film: &Film, path: &Path) -> Result<()> {
    write_atomic(path, &codec::encode(film))
}

/// Reads a checkpoint.
pub fn read_checkpoint(path: &Path) -> Result<Film> {
    let bytes = std::fs::read(path)?;
    codec::decode(&bytes).map_err(|e| ServerError::Internal(format!("{}: {e}", path.display())))
}

/// FLM bytes of a film (LuxRender's format, for downloads and outputs).
pub fn flm_bytes(film: &Film, info: &SceneInfo) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    luxfarm::film::flm::write_flm(film, &info.params, &mut out).map_err(ServerError::internal)?;
    Ok(out)
}

/// Writes the job's outputs under `dir`: `BASENAME.png` (tonemapped), `BASENAME.exr`
/// (linear) and `BASENAME.flm`.
pub fn write_outputs(film: &Film, info: &SceneInfo, dir: &Path) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let base = dir.join(&info.basename);
    let mut written = Vec::new();
    for (ext, bytes) in [
        ("png", png_bytes(film, info, None)?),
        ("exr", exr_bytes(film, info)?),
        ("flm", flm_bytes(film, info)?),
    ] {
        let path = base.with_extension(ext);
        write_atomic(&path, &bytes)?;
        written.push(path);
    }
    Ok(written)
}

/// A tonemapped 8-bit PNG of the film (the scene's tonemapper), scaled down so its longer
/// side is at most `max_size`.
pub fn png_bytes(film: &Film, info: &SceneInfo, max_size: Option<u32>) -> Result<Vec<u8>> {
    let img = luxfarm::tonemap::tonemap_display(film, &info.params.tonemap);
    let mut buf = Vec::with_capacity(img.rgb.len() * 3);
    for p in &img.rgb {
        buf.extend(p.iter().map(|&c| luxfarm::tonemap::quantize8(c)));
    }
    let mut rgb = image::RgbImage::from_raw(img.width, img.height, buf)
        .ok_or_else(|| ServerError::internal("image size mismatch"))?;
    if let Some(max) = max_size.filter(|&m| m > 0) {
        let longest = img.width.max(img.height);
        if longest > max {
            let scale = max as f64 / longest as f64;
            let w = ((img.width as f64 * scale).round() as u32).max(1);
            let h = ((img.height as f64 * scale).round() as u32).max(1);
            rgb = image::imageops::resize(&rgb, w, h, image::imageops::FilterType::Triangle);
        }
    }
    let mut out = std::io::Cursor::new(Vec::new());
    rgb.write_to(&mut out, image::ImageFormat::Png)
        .map_err(ServerError::internal)?;
    Ok(out.into_inner())
}

/// An EXR (linear RGB, f32, untonemapped) of the film.
pub fn exr_bytes(film: &Film, info: &SceneInfo) -> Result<Vec<u8>> {
    use exr::prelude::*;
    let img = luxfarm::tonemap::untonemapped(film, &info.params.tonemap);
    let (w, h) = (img.width as usize, img.height as usize);
    let pixels = img.rgb;
    let channels = SpecificChannels::rgb(|p: Vec2<usize>| {
        let c = pixels.get(p.y() * w + p.x()).copied().unwrap_or([0.0; 3]);
        (c[0], c[1], c[2])
    });
    let image = Image::from_channels((w, h), channels);
    let mut out = std::io::Cursor::new(Vec::new());
    image
        .write()
        .to_buffered(&mut out)
        .map_err(ServerError::internal)?;
    Ok(out.into_inner())
}

/// Whether [`convergence_update`] works in this build.
pub const CONVERGENCE_AVAILABLE: bool = true;

/// State of a job's convergence test (haltthreshold).
#[derive(Default)]
pub struct Convergence {
    pub last_spp: f64,
    pub test: Option<ConvergenceTest>,
    pub last_failing: Option<f64>,
}

/// Runs the convergence test (Yee perceptual difference against the previous snapshot of the
/// display image): the failing-pixel fraction, None on the first snapshot.
pub fn convergence_update(
    c: &mut Convergence,
    film: &Film,
    info: &SceneInfo,
) -> Result<Option<f64>> {
    let image = luxfarm::tonemap::tonemap_display(film, &info.params.tonemap);
    let first = c.test.is_none();
    let test = c
        .test
        .get_or_insert_with(|| ConvergenceTest::new(YeeParams::default()));
    let failing = test.update(&image);
    if first {
        return Ok(None);
    }
    c.last_failing = Some(failing);
    Ok(Some(failing))
}
