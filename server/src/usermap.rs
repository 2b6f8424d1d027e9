//! A job's user sampling map on the master (LuxRender's `luxSetUserSamplingMap`, which its
//! master forwarded to every slave with `updateServerUserSamplingMap`): set, cleared and read
//! through the REST API (`crate::rest`), kept in the store (`crate::db`, table
//! `sampling_maps`) so a restarted master keeps it, and combined with the job's noise-aware map
//! in its run state (`crate::noisemap`), which sends the result to every worker with its
//! acknowledgements.
//!
//! ```text
//! PUT image bytes --luxfarm::render::usermap (size from the header first, luminance,
//!   finite, >= 0, not all zero)--> weights --store (weights, version)-->
//!   run state: NoiseMapState::set_user --> combined map at a new version --> acks
//! DELETE --store (NULL, version)--> run state: Cleared --> noise-aware map or uniform --> acks
//! master start: job loaded (crate::lease) --initial_user_map: the stored row--> run state
//! ```
//!
//! Edits run one at a time ([`edits`]) and load the job first, so a job's run state always
//! holds the last stored map: a load racing an edit either reads the store after the edit or
//! is the run state the edit then updates. A job whose sampler takes no maps (metropolis,
//! erpt) keeps the map in the store, unapplied, and the answer says why.

use crate::auth::Identity;
use crate::db::{JobRow, UserMapRow};
use crate::error::{Result, ServerError};
use crate::farm::{lock, now_ms, Farm, JobRt};
use crate::noisemap::UserMap;
use luxfarm::render::usermap::{weights_from_image, UserMapError};
use luxfarm::sampler::map::SamplingMap;
use std::sync::{Arc, Mutex, MutexGuard};

/// Serialises edits of user maps (rare) across the master.
static EDITS: Mutex<()> = Mutex::new(());

/// Held while a user map is edited.
fn edits() -> MutexGuard<'static, ()> {
    EDITS.lock().unwrap_or_else(|p| p.into_inner())
}

/// A job's user sampling map as the REST API shows it.
#[derive(Debug, serde::Serialize, utoipa::ToSchema)]
pub struct UserMapView {
    pub job: String,
    /// The film buffer's size (the crop window's): the map has one weight per pixel.
    pub width: u32,
    pub height: u32,
    /// False once cleared.
    pub set: bool,
    /// The map version the workers get for this change (it grows with every change of the
    /// user or noise-aware map).
    pub version: u64,
    /// Whether the job's sampler applies the map (all but metropolis and erpt); absent when
    /// reading a job that is not loaded.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub applied: Option<bool>,
    /// Why the map is not applied, when it is not.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub warning: Option<String>,
    /// The weights as uploaded (each pixel's luminance), row-major from the top row (GET
    /// only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub weights: Option<Vec<f32>>,
}

/// An image that cannot be a map: 400 when it is no image, 422 when it is the wrong size or
/// its weights are refused.
fn refused(e: UserMapError) -> ServerError {
    match e {
        UserMapError::Decode(_) => ServerError::BadRequest(e.to_string()),
        UserMapError::Size { .. } | UserMapError::Map(_) => {
            ServerError::Unprocessable(e.to_string())
        }
    }
}

/// The job of an edit, loaded: it exists (404), the caller may change it (403), it has not
/// ended (409).
fn editable(farm: &Farm, id: &str, who: &Identity) -> Result<(JobRow, Arc<JobRt>)> {
    let row = farm.job_row(id)?;
    who.check_manage(&row.owner)?;
    if row.state.is_final() {
        return Err(ServerError::Conflict(format!(
            "job {id} is {}: its sampling map can no longer change",
            row.state.as_str()
        )));
    }
    let rt = farm.job_rt(&row)?;
    Ok((row, rt))
}

/// Sets the job's user sampling map from an image (`PUT .../sampling-map`).
pub fn put(farm: &Farm, id: &str, who: &Identity, image: &[u8]) -> Result<UserMapView> {
    let (row, rt) = editable(farm, id, who)?;
    let (w, h) = (rt.info.width, rt.info.height);
    let weights = weights_from_image(image, w, h).map_err(refused)?;
    let map = SamplingMap::from_weights(&weights, w, h)
        .map_err(|e| ServerError::Unprocessable(e.to_string()))?;
    let version = store(farm, &rt, Some(&weights), UserMap::Set(Arc::new(map)))?;
    tracing::info!(job = %row.id, version, "user sampling map set");
    Ok(view(&rt, true, version, None))
}

/// Clears the job's user sampling map (`DELETE .../sampling-map`): sampling goes back to
/// uniform, or to the noise-aware map alone.
pub fn delete(farm: &Farm, id: &str, who: &Identity) -> Result<UserMapView> {
    let (row, rt) = editable(farm, id, who)?;
    let cleared = UserMap::Cleared {
        width: rt.info.width,
        height: rt.info.height,
    };
    let version = store(farm, &rt, None, cleared)?;
    tracing::info!(job = %row.id, version, "user sampling map cleared");
    Ok(view(&rt, false, version, None))
}

/// Stores an edit, then gives it to the job's run state (when its sampler takes maps); the
/// version the workers get.
fn store(farm: &Farm, rt: &JobRt, weights: Option<&[f32]>, map: UserMap) -> Result<u64> {
    let _one_at_a_time = edits();
    let candidate = lock(&rt.state).noise_map.version().saturating_add(1);
    let size = (rt.info.width, rt.info.height);
    lock(&farm.db).set_user_map(&rt.id, size, weights, candidate, now_ms())?;
    let version = match rt.info.map_refusal {
        None => lock(&rt.state).noise_map.set_user(map, candidate),
        Some(_) => candidate,
    };
    farm.touch();
    Ok(version)
}

/// The answer to an edit.
fn view(rt: &JobRt, set: bool, version: u64, weights: Option<Vec<f32>>) -> UserMapView {
    UserMapView {
        job: rt.id.clone(),
        width: rt.info.width,
        height: rt.info.height,
        set,
        version,
        applied: Some(rt.info.map_refusal.is_none()),
        warning: rt.info.map_refusal.map(str::to_string),
        weights,
    }
}

/// The job's user sampling map (`GET .../sampling-map`): 404 for an unknown job and for a job
/// without one (never set, or cleared).
pub fn get(farm: &Farm, id: &str) -> Result<UserMapView> {
    let row = farm.job_row(id)?;
    let stored = lock(&farm.db).user_map(&row.id)?;
    let Some(UserMapRow {
        width,
        height,
        weights: Some(weights),
        version,
        ..
    }) = stored
    else {
        return Err(ServerError::NotFound(format!(
            "job {id} has no user sampling map"
        )));
    };
    let rt = lock(&farm.jobs).get(id).cloned();
    Ok(UserMapView {
        job: row.id,
        width,
        height,
        set: true,
        version,
        applied: rt.as_ref().map(|rt| rt.info.map_refusal.is_none()),
        warning: rt.and_then(|rt| rt.info.map_refusal.map(str::to_string)),
        weights: Some(weights),
    })
}

/// The user map a job being loaded starts with, and its stored version (a master restart
/// keeps it). A stored map that no longer fits the job's film is logged and left out.
pub fn initial_user_map(farm: &Farm, job_id: &str, w: u32, h: u32) -> Result<(UserMap, u64)> {
    let Some(row) = lock(&farm.db).user_map(job_id)? else {
        return Ok((UserMap::None, 0));
    };
    let map = match &row.weights {
        None => UserMap::Cleared {
            width: w,
            height: h,
        },
        Some(weights) => match SamplingMap::from_weights(weights, row.width, row.height)
            .and_then(|m| m.check_film(w, h).map(|()| m))
        {
            Ok(m) => UserMap::Set(Arc::new(m)),
            Err(e) => {
                tracing::error!(job = %job_id, error = %e, "stored user sampling map left out");
                UserMap::None
            }
        },
    };
    Ok((map, row.version))
}
