//! The outputs a Film statement asks for, at the end of the back end: given a film, the
//! Film's parameters and a base name, write exactly the files LuxRender's fleximage would
//! (`write_exr`, `write_png`, `write_tga`, `write_resume_flm`), named `BASENAME.exr`, `.png`,
//! `.tga`, `.flm`; and, at the start of a render, resume from (or set aside) the resume FLM.
//!
//! Data flows in one way: `crate::film` (sums, parameters, FLM) -> `crate::tonemap` (RGB)
//! -> `crate::imageio` (encoded bytes) -> here. `luxfarm render` and the master both call
//! [`write_outputs`] and name their base the same way ([`basename`], [`farm_basename`]), so
//! a scene gives the same files locally and on a farm. [`images`] turns a film into the
//! pixel buffers the encoders take (also the images the master serves from memory).
//! Every file is written atomically ([`crate::atomic_write`]).

pub mod images;

use crate::film::flm::{merge_flm, write_flm_file};
use crate::film::{Film, FilmError, FilmParams};
use crate::imageio::ImageError;
use std::fs::File;
use std::path::{Path, PathBuf};

pub use images::{linear_exr, preview_png};

/// Everything that can go wrong while writing outputs.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error(transparent)]
    Film(#[from] FilmError),
    #[error(transparent)]
    Image(#[from] ImageError),
}

/// One kind of output file of a Film.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputKind {
    /// `write_exr`: OpenEXR, tonemapped or linear (`write_exr_applyimaging`).
    Exr,
    /// `write_png`: tonemapped PNG.
    Png,
    /// `write_tga`: tonemapped TGA.
    Tga,
    /// `write_resume_flm`: the film itself (LuxRender's FLM), to resume or merge.
    Flm,
}

impl OutputKind {
    /// Every kind, in the order they are written.
    pub const ALL: [OutputKind; 4] = [
        OutputKind::Exr,
        OutputKind::Png,
        OutputKind::Tga,
        OutputKind::Flm,
    ];

    /// What follows the base name in the file's name.
    pub fn suffix(self) -> &'static str {
        match self {
            OutputKind::Exr => ".exr",
            OutputKind::Png => ".png",
            OutputKind::Tga => ".tga",
            OutputKind::Flm => ".flm",
        }
    }

    /// Whether the Film asks for this output.
    pub fn is_requested(self, params: &FilmParams) -> bool {
        match self {
            OutputKind::Exr => params.exr.enabled,
            OutputKind::Png => params.png.enabled,
            OutputKind::Tga => params.tga.enabled,
            OutputKind::Flm => params.write_resume_flm,
        }
    }
}

/// The outputs the Film asks for, in the order they are written.
pub fn requested(params: &FilmParams) -> Vec<OutputKind> {
    OutputKind::ALL
        .into_iter()
        .filter(|k| k.is_requested(params))
        .collect()
}

/// The file of an output: the base name with the kind's suffix appended (as LuxRender: a
/// base name `a.b` gives `a.b.png`).
pub fn path(basename: &Path, kind: OutputKind) -> PathBuf {
    with_suffix(basename, kind.suffix())
}

fn with_suffix(base: &Path, suffix: &str) -> PathBuf {
    let mut s = base.as_os_str().to_os_string();
    s.push(suffix);
    PathBuf::from(s)
}

/// The base name of a local render's outputs: `explicit` (`-o`) when given, else the Film's
/// `filename` beside the scene (the scene's file stem when `filename` is empty).
pub fn basename(scene: &Path, params: &FilmParams, explicit: Option<&Path>) -> PathBuf {
    if let Some(b) = explicit {
        return b.to_path_buf();
    }
    let dir = scene.parent().unwrap_or(Path::new(""));
    if params.filename.is_empty() {
        dir.join(scene_stem(scene))
    } else {
        dir.join(&params.filename)
    }
}

/// The base name a master gives a job's outputs inside the job's output directory: the last
/// component of the Film's `filename` (a scene never names a place outside that directory),
/// else the scene's file stem.
pub fn farm_basename(scene: &Path, params: &FilmParams) -> String {
    Path::new(&params.filename)
        .file_name()
        .and_then(|s| s.to_str())
        .filter(|s| !s.is_empty() && *s != "..")
        .map(str::to_string)
        .unwrap_or_else(|| scene_stem(scene))
}

fn scene_stem(scene: &Path) -> String {
    scene
        .file_stem()
        .and_then(|s| s.to_str())
        .filter(|s| !s.is_empty())
        .unwrap_or("luxout")
        .to_string()
}

/// Writes every output the parameters enable; returns the files written. The EXR's Z channel
/// takes the depth sums the film carries (a farm job's merged deltas), normalised as
/// `write_exr_zbuf_normalizationtype` asks; see [`write_outputs_with_z`] for given depths.
pub fn write_outputs(
    film: &Film,
    params: &FilmParams,
    basename: &Path,
) -> Result<Vec<PathBuf>, OutputError> {
    let z = film.depth().map(|d| d.depths(params.exr.zbuf_norm));
    write_outputs_with_z(film, params, basename, z.as_deref())
}

/// As [`write_outputs`], with an optional Z buffer (depth per buffer pixel) for the EXR's
/// `write_exr_ZBuf` channel. A Z channel asked for without depths is left out with a warning.
pub fn write_outputs_with_z(
    film: &Film,
    params: &FilmParams,
    basename: &Path,
    z: Option<&[f32]>,
) -> Result<Vec<PathBuf>, OutputError> {
    let z = z.filter(|z| z.len() == film.pixel_count());
    if params.wants_zbuf() && z.is_none() {
        tracing::warn!("a Z buffer output is enabled but no depth buffer is available: omitted");
    }
    let mut display = None;
    let mut written = Vec::new();
    for kind in requested(params) {
        let file = path(basename, kind);
        match kind {
            OutputKind::Exr => images::write_exr(film, params, &file, z)?,
            OutputKind::Png => {
                let d = display.get_or_insert_with(|| images::Display::new(film, &params.tonemap));
                images::write_png(d, params, &file)?
            }
            OutputKind::Tga => {
                let d = display.get_or_insert_with(|| images::Display::new(film, &params.tonemap));
                images::write_tga(d, params, &file)?
            }
            OutputKind::Flm => write_flm_file(&file, film, params)?,
        }
        written.push(file);
    }
    Ok(written)
}

/// At the start of a render, as LuxRender: with `write_resume_flm` and
/// `restart_resume_flm`, an existing `BASENAME.flm` is moved to `BASENAME.flm1` and the
/// render starts afresh; without `restart_resume_flm`, an existing `BASENAME.flm` is merged
/// into `film` (it must match its layout). Returns the FLM resumed from, if any.
pub fn resume(
    film: &mut Film,
    params: &FilmParams,
    basename: &Path,
) -> Result<Option<PathBuf>, FilmError> {
    if !params.write_resume_flm {
        return Ok(None);
    }
    let flm = path(basename, OutputKind::Flm);
    if !flm.exists() {
        return Ok(None);
    }
    if params.restart_resume_flm {
        let old = with_suffix(basename, ".flm1");
        std::fs::rename(&flm, &old).map_err(|e| FilmError::file(&flm, e))?;
        tracing::info!("previous resume film kept as {}", old.display());
        return Ok(None);
    }
    let f = File::open(&flm).map_err(|e| FilmError::file(&flm, e))?;
    merge_flm(film, std::io::BufReader::new(f))?;
    tracing::info!("resumed from {} ({:.2} spp)", flm.display(), film.spp());
    Ok(Some(flm))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requested_outputs_follow_the_film_flags() {
        let mut p = FilmParams::with_resolution(4, 4);
        assert_eq!(requested(&p), [OutputKind::Png]);
        p.png.enabled = false;
        assert!(requested(&p).is_empty());
        p.tga.enabled = true;
        p.exr.enabled = true;
        p.write_resume_flm = true;
        assert_eq!(
            requested(&p),
            [OutputKind::Exr, OutputKind::Tga, OutputKind::Flm]
        );
    }

    #[test]
    fn names_append_the_suffix() {
        assert_eq!(
            path(Path::new("out/a.b"), OutputKind::Png),
            Path::new("out/a.b.png")
        );
        let mut p = FilmParams::with_resolution(4, 4);
        let scene = Path::new("scenes/room/room.lxs");
        assert_eq!(basename(scene, &p, None), Path::new("scenes/room/luxout"));
        assert_eq!(
            basename(scene, &p, Some(Path::new("x/y"))),
            Path::new("x/y")
        );
        assert_eq!(farm_basename(scene, &p), "luxout");
        p.filename = "renders/final".into();
        assert_eq!(
            basename(scene, &p, None),
            Path::new("scenes/room/renders/final")
        );
        assert_eq!(farm_basename(scene, &p), "final");
        p.filename = String::new();
        assert_eq!(basename(scene, &p, None), Path::new("scenes/room/room"));
        assert_eq!(farm_basename(scene, &p), "room");
        p.filename = "../..".into();
        assert_eq!(farm_basename(scene, &p), "room");
    }
}
