//! REST handlers of a job's user sampling map (`/api/v1/jobs/{id}/sampling-map`): PUT an
//! image of the film's pixel size (its luminance weighs each pixel's samples), GET the
//! weights back as JSON, DELETE to return to uniform (or noise-aware) sampling. The work is
//! `crate::usermap`'s; routed and documented in the parent.

use super::*;
use crate::usermap::{self, UserMapView};

/// Set the job's user sampling map (LuxRender's user sampling map): the body is an image (PNG,
/// JPEG, TGA, HDR or OpenEXR) of the film's pixel size (the crop window's when the Film has
/// one); each pixel's luminance (values as stored: 8-bit divided by 255, floats as they are)
/// is its weight. With a noise-aware sampler the workers sample by the product of both maps.
/// Metropolis and erpt jobs keep the map unapplied (`applied` false, `warning` says why).
#[utoipa::path(put, path = "/api/v1/jobs/{id}/sampling-map", params(("id" = String, Path)),
    request_body(content = Vec<u8>, description = "the map image", content_type = "application/octet-stream"),
    responses((status = 200, body = UserMapView), (status = 400, body = ErrorBody),
              (status = 403, body = ErrorBody), (status = 404, body = ErrorBody),
              (status = 409, body = ErrorBody), (status = 413, body = ErrorBody),
              (status = 422, body = ErrorBody)))]
pub(super) async fn put_sampling_map(
    State(farm): State<AppState>,
    Extension(who): Extension<Identity>,
    Path(id): Path<String>,
    req: Request,
) -> Result<Json<UserMapView>> {
    let announced = req
        .headers()
        .get(header::CONTENT_LENGTH)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.parse::<u64>().ok());
    if let Some(n) = announced.filter(|&n| n > farm.cfg.max_upload) {
        return Err(ServerError::TooLarge(format!(
            "upload of {n} bytes exceeds the limit of {}",
            farm.cfg.max_upload
        )));
    }
    let bytes = Bytes::from_request(req, &())
        .await
        .map_err(|e| match e.status() {
            StatusCode::PAYLOAD_TOO_LARGE => ServerError::TooLarge(e.body_text()),
            _ => ServerError::BadRequest(e.body_text()),
        })?;
    Ok(Json(
        blocking(move || usermap::put(&farm, &id, &who, &bytes)).await?,
    ))
}

/// The job's user sampling map: its size, version and weights (row-major from the top row).
/// 404 when the job has none.
#[utoipa::path(get, path = "/api/v1/jobs/{id}/sampling-map", params(("id" = String, Path)),
    responses((status = 200, body = UserMapView), (status = 404, body = ErrorBody)))]
pub(super) async fn get_sampling_map(
    State(farm): State<AppState>,
    Path(id): Path<String>,
) -> Result<Json<UserMapView>> {
    Ok(Json(blocking(move || usermap::get(&farm, &id)).await?))
}

/// Clear the job's user sampling map: the workers go back to uniform sampling (or to the
/// noise-aware map alone).
#[utoipa::path(delete, path = "/api/v1/jobs/{id}/sampling-map", params(("id" = String, Path)),
    responses((status = 200, body = UserMapView), (status = 403, body = ErrorBody),
              (status = 404, body = ErrorBody), (status = 409, body = ErrorBody)))]
pub(super) async fn delete_sampling_map(
    State(farm): State<AppState>,
    Extension(who): Extension<Identity>,
    Path(id): Path<String>,
) -> Result<Json<UserMapView>> {
    Ok(Json(
        blocking(move || usermap::delete(&farm, &id, &who)).await?,
    ))
}
