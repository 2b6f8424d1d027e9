//! Job outputs on demand (the REST/gRPC API): the merged film as FLM, a tonemapped PNG
//! (preview, optionally scaled down, optionally with another tonemapping, see [`tonemap`]) or
//! a linear EXR, from the live film of a rendering job or the last checkpoint. The images are
//! made by the core's `luxfarm::output` (through [`crate::scene`]); the files a finished job
//! leaves are another matter: the ones its Film asks for ([`crate::scene::write_outputs`]).

pub mod tonemap;

use crate::error::{Result, ServerError};
use crate::farm::{lock, Farm};
use crate::scene::{self, SceneInfo};
use std::sync::atomic::Ordering;
use tonemap::TonemapOverride;

/// An output and the film version it was made from (the ETag).
pub struct Output {
    pub bytes: Vec<u8>,
    pub version: String,
    pub content_type: &'static str,
}

/// The current version tag of a job's film (changes whenever deltas are merged).
pub fn film_version(farm: &Farm, id: &str) -> Result<String> {
    let row = farm.job_row(id)?;
    let live = lock(&farm.jobs)
        .get(id)
        .map(|rt| rt.version.load(Ordering::Relaxed) + 1)
        .unwrap_or(0);
    Ok(format!("{}-{}", row.ckpt_gen, live))
}

/// The scene information of job `id` (the live job's, else parsed from its stored scene).
pub fn scene_info(farm: &Farm, id: &str) -> Result<SceneInfo> {
    let row = farm.job_row(id)?;
    if let Some(rt) = lock(&farm.jobs).get(id) {
        return Ok(rt.info.clone());
    }
    scene::inspect(
        &farm.scene_dir(&row.bundle_hash),
        row.scene_path.as_ref(),
        row.frame,
    )
}

/// Makes `format` (png, exr, flm) of job `id` with the scene's tonemapping; `max_size`
/// bounds the PNG's longer side.
pub fn render(farm: &Farm, id: &str, format: &str, max_size: Option<u32>) -> Result<Output> {
    render_with(farm, id, format, max_size, &TonemapOverride::default())
}

/// [`render`] with the PNG tonemapped as `tm` asks (over the scene's settings).
pub fn render_with(
    farm: &Farm,
    id: &str,
    format: &str,
    max_size: Option<u32>,
    tm: &TonemapOverride,
) -> Result<Output> {
    let row = farm.job_row(id)?;
    let version = film_version(farm, id)?;
    let live = lock(&farm.jobs).get(id).cloned();
    let (film, mut info) = match live {
        Some(rt) => (lock(&rt.film).clone(), rt.info.clone()),
        None => {
            let path = crate::halt::latest_checkpoint(farm, &row).ok_or_else(|| {
                ServerError::NotReady(format!("job {id} has no merged samples yet"))
            })?;
            let info = scene::inspect(
                &farm.scene_dir(&row.bundle_hash),
                row.scene_path.as_ref(),
                row.frame,
            )?;
            (scene::read_checkpoint(&path)?, info)
        }
    };
    let (bytes, content_type) = match format {
        "png" => {
            info.params.tonemap = tm.apply(&info.params.tonemap);
            (scene::png_bytes(&film, &info, max_size)?, "image/png")
        }
        "exr" => (scene::exr_bytes(&film, &info)?, "image/x-exr"),
        "flm" => (scene::flm_bytes(&film, &info)?, "application/octet-stream"),
        other => {
            return Err(ServerError::BadRequest(format!(
                "unknown output format {other:?} (png, exr or flm)"
            )))
        }
    };
    Ok(Output {
        bytes,
        version,
        content_type,
    })
}
