//! Job outputs on demand: the merged film as FLM, a tonemapped PNG (preview, optionally
//! scaled down) or an EXR, from the live film of a rendering job or the last checkpoint.

use crate::error::{Result, ServerError};
use crate::farm::{lock, Farm};
use crate::scene;
use std::sync::atomic::Ordering;

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

/// Makes `format` (png, exr, flm) of job `id`; `max_size` bounds the PNG's longer side.
pub fn render(farm: &Farm, id: &str, format: &str, max_size: Option<u32>) -> Result<Output> {
    let row = farm.job_row(id)?;
    let version = film_version(farm, id)?;
    let live = lock(&farm.jobs).get(id).cloned();
    let (film, info) = match live {
        Some(rt) => (lock(&rt.film).clone(), rt.info.clone()),
        None => {
            let path = crate::halt::latest_checkpoint(farm, &row).ok_or_else(|| {
                ServerError::NotReady(format!("job {id} has no merged samples yet"))
            })?;
            let info = scene::inspect(&farm.scene_dir(&row.bundle_hash), row.scene_path.as_ref())?;
            (scene::read_checkpoint(&path)?, info)
        }
    };
    let (bytes, content_type) = match format {
        "png" => (scene::png_bytes(&film, &info, max_size)?, "image/png"),
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
