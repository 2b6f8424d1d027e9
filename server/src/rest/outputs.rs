//! REST handlers of a job's outputs: the preview and full-size images (tonemapped per
//! request), the film, the EXR, the scene's tonemapping, and the speed/accuracy trade (error
//! history, projections, the convergence-map overlay). Routed and documented in the parent.

use super::*;

/// Image query: size and tonemapping of preview.png and image.png. The tonemapping is applied
/// to this response only (the job and its stored outputs keep the scene's). Missing kernel
/// parameters keep the scene's values when `kernel` is the scene's kernel, else LuxRender's
/// defaults; `gamma` defaults to the scene's. Bad values are a 400 naming the parameter.
#[derive(Debug, Default, serde::Deserialize, utoipa::IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct ImageQuery {
    /// The PNG's longer side at most this many pixels (preview.png: 1024 by default;
    /// image.png: full size).
    #[param(value_type = Option<u32>, minimum = 1)]
    pub max_size: Option<String>,
    /// Tonemapping kernel: `reinhard`, `linear`, `contrast`, `maxwhite` or `autolinear`
    /// (default: the scene's).
    pub kernel: Option<String>,
    /// reinhard: prescale (> 0; LuxRender default 1).
    #[param(value_type = Option<f64>)]
    pub reinhard_prescale: Option<String>,
    /// reinhard: postscale (>= 0; default 1).
    #[param(value_type = Option<f64>)]
    pub reinhard_postscale: Option<String>,
    /// reinhard: burn (> 0; default 6).
    #[param(value_type = Option<f64>)]
    pub reinhard_burn: Option<String>,
    /// linear: film sensitivity, ISO (> 0; default 50).
    #[param(value_type = Option<f64>)]
    pub linear_sensitivity: Option<String>,
    /// linear: exposure time in seconds (> 0; default 1).
    #[param(value_type = Option<f64>)]
    pub linear_exposure: Option<String>,
    /// linear: f-stop (> 0, <= 1000; default 2.8).
    #[param(value_type = Option<f64>)]
    pub linear_fstop: Option<String>,
    /// linear: the gamma of the middle-grey mapping (> 0, <= 10; default 1).
    #[param(value_type = Option<f64>)]
    pub linear_gamma: Option<String>,
    /// contrast: display adaptation luminance Ywa (> 0; default 1).
    #[param(value_type = Option<f64>)]
    pub contrast_ywa: Option<String>,
    /// Output gamma (> 0, <= 10; default: the scene's, LuxRender's 2.2).
    #[param(value_type = Option<f64>)]
    pub gamma: Option<String>,
}

impl ImageQuery {
    /// The validated tonemapping request.
    fn tonemap(&self) -> Result<TonemapOverride> {
        TonemapOverride::parse(
            self.kernel.as_deref(),
            [
                ("reinhard_prescale", &self.reinhard_prescale),
                ("reinhard_postscale", &self.reinhard_postscale),
                ("reinhard_burn", &self.reinhard_burn),
                ("linear_sensitivity", &self.linear_sensitivity),
                ("linear_exposure", &self.linear_exposure),
                ("linear_fstop", &self.linear_fstop),
                ("linear_gamma", &self.linear_gamma),
                ("contrast_ywa", &self.contrast_ywa),
                ("gamma", &self.gamma),
            ]
            .map(|(n, v)| (n, v.as_deref())),
        )
    }

    /// The validated `max_size` (None when absent).
    fn max_size(&self) -> Result<Option<u32>> {
        let Some(text) = self.max_size.as_deref().map(str::trim) else {
            return Ok(None);
        };
        match text.parse::<u32>() {
            Ok(n) if n >= 1 => Ok(Some(n)),
            _ => Err(ServerError::BadRequest(format!(
                "parameter max_size: {text:?} is not a positive integer"
            ))),
        }
    }
}

pub(super) async fn output(
    farm: AppState,
    id: String,
    format: &'static str,
    max_size: Option<u32>,
    tm: TonemapOverride,
    headers: &HeaderMap,
    file_name: Option<&str>,
) -> Result<Response> {
    let f = farm.clone();
    let i = id.clone();
    let version = blocking(move || crate::output::film_version(&f, &i)).await?;
    let etag = format!("\"{version}-{}-{}\"", max_size.unwrap_or(0), tm.tag());
    let matches = headers
        .get(header::IF_NONE_MATCH)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| v.split(',').any(|t| t.trim() == etag || t.trim() == "*"));
    if matches {
        return Ok((StatusCode::NOT_MODIFIED, [(header::ETAG, etag)]).into_response());
    }
    let out =
        blocking(move || crate::output::render_with(&farm, &id, format, max_size, &tm)).await?;
    let mut resp = (
        [
            (header::CONTENT_TYPE, out.content_type.to_string()),
            (header::ETAG, etag),
            (header::CACHE_CONTROL, "no-cache".to_string()),
        ],
        out.bytes,
    )
        .into_response();
    if let Some(name) = file_name {
        if let Ok(v) = HeaderValue::from_str(&format!("attachment; filename=\"{name}\"")) {
            resp.headers_mut().insert(header::CONTENT_DISPOSITION, v);
        }
    }
    Ok(resp)
}

/// Tonemapped preview of the merged film (by default the scene's tonemapper; the query
/// chooses another kernel and parameters for this response only); ETag / If-None-Match
/// answer 304 while the film and the query's tonemapping are unchanged.
#[utoipa::path(get, path = "/api/v1/jobs/{id}/preview.png",
    params(("id" = String, Path), ImageQuery),
    responses((status = 200, content_type = "image/png", body = Vec<u8>), (status = 304),
              (status = 400, body = ErrorBody), (status = 404, body = ErrorBody),
              (status = 503, body = ErrorBody)))]
pub(super) async fn preview_png(
    State(farm): State<AppState>,
    Path(id): Path<String>,
    q: std::result::Result<Query<ImageQuery>, QueryRejection>,
    headers: HeaderMap,
) -> Result<Response> {
    let q = query(q)?;
    let (tm, size) = (q.tonemap()?, q.max_size()?.or(Some(1024)));
    output(farm, id, "png", size, tm, &headers, None).await
}

/// A job's tonemapping settings: the scene's and LuxRender's defaults (what preview.png and
/// image.png use for parameters the query leaves out).
#[utoipa::path(get, path = "/api/v1/jobs/{id}/tonemap", params(("id" = String, Path)),
    responses((status = 200, body = TonemapView), (status = 404, body = ErrorBody)))]
pub(super) async fn job_tonemap(
    State(farm): State<AppState>,
    Path(id): Path<String>,
) -> Result<Json<TonemapView>> {
    let info = blocking(move || crate::output::scene_info(&farm, &id)).await?;
    Ok(Json(TonemapView::new(&info.params.tonemap)))
}

/// Query of a job's trade: the target relative error to project to.
#[derive(Debug, Default, serde::Deserialize, utoipa::IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct TradeQuery {
    /// Target relative error of the film in (0, 10] (e.g. 0.01 for 1 %).
    #[param(value_type = Option<f64>)]
    pub target: Option<String>,
}

/// A job's error estimates over time (the film's relative error, and the convergence test's
/// failing fraction) with the projected times to its haltthreshold and to the relative error
/// `target`. The history is empty for a job not rendering and after a master restart.
#[utoipa::path(get, path = "/api/v1/jobs/{id}/trade", params(("id" = String, Path), TradeQuery),
    responses((status = 200, body = crate::trade::TradeView), (status = 400, body = ErrorBody),
              (status = 404, body = ErrorBody)))]
pub(super) async fn job_trade(
    State(farm): State<AppState>,
    Path(id): Path<String>,
    q: std::result::Result<Query<TradeQuery>, QueryRejection>,
) -> Result<Json<crate::trade::TradeView>> {
    let q = query(q)?;
    let target = match q.target.as_deref().map(str::trim).filter(|t| !t.is_empty()) {
        Some(t) => Some(crate::trade::parse_target(t).map_err(ServerError::BadRequest)?),
        None => None,
    };
    Ok(Json(
        blocking(move || views::trade_view(&farm, &id, target)).await?,
    ))
}

/// The job's last convergence map as a PNG (same size as preview.png for the same
/// `max_size`): passing pixels dark blue, failing ones yellow to red by how far they are above
/// the visible threshold. 503 before the first test, 404 for a job not rendering.
#[utoipa::path(get, path = "/api/v1/jobs/{id}/convergence.png",
    params(("id" = String, Path), ImageQuery),
    responses((status = 200, content_type = "image/png", body = Vec<u8>),
              (status = 400, body = ErrorBody), (status = 404, body = ErrorBody),
              (status = 503, body = ErrorBody)))]
pub(super) async fn convergence_png(
    State(farm): State<AppState>,
    Path(id): Path<String>,
    q: std::result::Result<Query<ImageQuery>, QueryRejection>,
) -> Result<Response> {
    let q = query(q)?;
    let size = q.max_size()?.unwrap_or(1024);
    let png = blocking(move || views::convergence_png(&farm, &id, size)).await?;
    Ok((
        [
            (header::CONTENT_TYPE, "image/png"),
            (header::CACHE_CONTROL, "no-store"),
        ],
        png,
    )
        .into_response())
}

/// The merged film as a LuxRender FLM.
#[utoipa::path(get, path = "/api/v1/jobs/{id}/film.flm", params(("id" = String, Path)),
    responses((status = 200, content_type = "application/octet-stream", body = Vec<u8>),
              (status = 404, body = ErrorBody)))]
pub(super) async fn film_flm(
    State(farm): State<AppState>,
    Path(id): Path<String>,
    headers: HeaderMap,
) -> Result<Response> {
    let tm = TonemapOverride::default();
    output(farm, id, "flm", None, tm, &headers, Some("film.flm")).await
}

/// The merged film as EXR.
#[utoipa::path(get, path = "/api/v1/jobs/{id}/image.exr", params(("id" = String, Path)),
    responses((status = 200, content_type = "image/x-exr", body = Vec<u8>),
              (status = 404, body = ErrorBody)))]
pub(super) async fn image_exr(
    State(farm): State<AppState>,
    Path(id): Path<String>,
    headers: HeaderMap,
) -> Result<Response> {
    let tm = TonemapOverride::default();
    let name = output_file(&farm, &id, "exr").await?;
    output(farm, id, "exr", None, tm, &headers, Some(&name)).await
}

/// The merged film tonemapped to PNG, at full resolution unless `max_size` is given; the
/// same tonemapping parameters as preview.png.
#[utoipa::path(get, path = "/api/v1/jobs/{id}/image.png",
    params(("id" = String, Path), ImageQuery),
    responses((status = 200, content_type = "image/png", body = Vec<u8>), (status = 304),
              (status = 400, body = ErrorBody), (status = 404, body = ErrorBody)))]
pub(super) async fn image_png(
    State(farm): State<AppState>,
    Path(id): Path<String>,
    q: std::result::Result<Query<ImageQuery>, QueryRejection>,
    headers: HeaderMap,
) -> Result<Response> {
    let q = query(q)?;
    let (tm, size) = (q.tonemap()?, q.max_size()?);
    let name = output_file(&farm, &id, "png").await?;
    output(farm, id, "png", size, tm, &headers, Some(&name)).await
}

/// The download name of a job's output: `NAME_0001.png` for a frame of a sequence.
pub(super) async fn output_file(farm: &AppState, id: &str, ext: &'static str) -> Result<String> {
    let (f, i) = (farm.clone(), id.to_string());
    blocking(move || Ok(f.job_row(&i)?.output_name(ext))).await
}
