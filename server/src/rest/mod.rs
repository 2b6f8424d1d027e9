//! The REST API under `/api/v1` (axum), with its OpenAPI document generated from the handlers
//! (utoipa). Thin handlers over the [`Farm`]; errors are JSON `{"error","detail"}` (405 and a
//! request that takes longer than `--request-timeout` included). Submission options are read
//! by one parser whether they come as query parameters or multipart fields.

use crate::admission::SubmitOptions;
use crate::auth::Identity;
use crate::error::{json_error, ErrorBody, Result, ServerError};
use crate::farm::Farm;
use crate::output::tonemap::{TonemapOverride, TonemapSettings, TonemapView};
use crate::views::{self, JobView, WorkerView};
use axum::body::Bytes;
use axum::extract::rejection::QueryRejection;
use axum::extract::{Extension, FromRequest, Multipart, Path, Query, Request, State};
use axum::http::{header, HeaderMap, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use std::sync::Arc;
use utoipa::OpenApi;

mod maps;
mod outputs;

use maps::*;
use outputs::*;

type AppState = Arc<Farm>;

/// The OpenAPI document of the REST API.
#[derive(OpenApi)]
#[openapi(
    info(
        title = "luxfarm",
        description = "Render farm for LuxRender scenes: jobs, outputs, workers."
    ),
    paths(
        submit_job,
        list_jobs,
        get_job,
        cancel_job,
        preview_png,
        job_tonemap,
        job_trade,
        job_webhooks,
        convergence_png,
        film_flm,
        image_exr,
        image_png,
        put_sampling_map,
        get_sampling_map,
        delete_sampling_map,
        list_workers,
        forgive_worker,
        list_sequences,
        create_sequence,
        get_sequence,
        events,
        healthz,
        metrics,
        openapi_json
    ),
    components(schemas(
        JobView,
        WorkerView,
        ErrorBody,
        crate::usermap::UserMapView,
        views::JobWorkerView,
        crate::webhooks::WebhookView,
        crate::sequence::SequenceView,
        crate::sequence::FrameView,
        crate::blocks::FailureView,
        NewSequence,
        TonemapView,
        TonemapSettings,
        crate::trade::TradeView,
        crate::trade::TradePoint,
        crate::trade::Projection,
        crate::trade::ProjectionStatus,
        crate::trade::Metric,
        crate::trade::PowerFit,
        crate::db::JobState
    ))
)]
pub struct ApiDoc;

/// The REST routes (state applied).
pub fn router(farm: AppState) -> Router {
    let body_limit = usize::try_from(farm.cfg.max_upload).unwrap_or(usize::MAX);
    let timeout = std::time::Duration::from_secs_f64(farm.cfg.request_timeout);
    Router::new()
        .route("/api/v1/jobs", get(list_jobs).post(submit_job))
        .route("/api/v1/jobs/{id}", get(get_job).delete(cancel_job))
        .route("/api/v1/jobs/{id}/preview.png", get(preview_png))
        .route("/api/v1/jobs/{id}/tonemap", get(job_tonemap))
        .route("/api/v1/jobs/{id}/trade", get(job_trade))
        .route("/api/v1/jobs/{id}/webhooks", get(job_webhooks))
        .route("/api/v1/jobs/{id}/convergence.png", get(convergence_png))
        .route("/api/v1/jobs/{id}/film.flm", get(film_flm))
        .route("/api/v1/jobs/{id}/image.exr", get(image_exr))
        .route("/api/v1/jobs/{id}/image.png", get(image_png))
        .route(
            "/api/v1/jobs/{id}/sampling-map",
            get(get_sampling_map)
                .put(put_sampling_map)
                .delete(delete_sampling_map),
        )
        .route("/api/v1/workers", get(list_workers))
        .route("/api/v1/workers/{id}/forgive", post(forgive_worker))
        .route(
            "/api/v1/sequences",
            get(list_sequences).post(create_sequence),
        )
        .route("/api/v1/sequences/{id}", get(get_sequence))
        .route("/api/v1/events", get(events))
        .route("/api/events", get(events))
        .route("/api/v1/healthz", get(healthz))
        .route("/healthz", get(healthz))
        .route("/api/v1/metrics", get(metrics))
        .route("/metrics", get(metrics))
        .route("/api/v1/openapi.json", get(openapi_json))
        .method_not_allowed_fallback(method_not_allowed)
        .layer(axum::extract::DefaultBodyLimit::max(body_limit))
        .layer(axum::middleware::from_fn(
            move |req: Request, next: axum::middleware::Next| time_limited(timeout, req, next),
        ))
        .with_state(farm)
}

async fn method_not_allowed(req: Request) -> Response {
    json_error(
        StatusCode::METHOD_NOT_ALLOWED,
        "method_not_allowed",
        format!("{} is not allowed on {}", req.method(), req.uri().path()),
    )
}

/// A REST request (its body included) must be answered within `--request-timeout`.
async fn time_limited(
    limit: std::time::Duration,
    req: Request,
    next: axum::middleware::Next,
) -> Response {
    match tokio::time::timeout(limit, next.run(req)).await {
        Ok(r) => r,
        Err(_) => json_error(
            StatusCode::REQUEST_TIMEOUT,
            "request_timeout",
            format!(
                "the request took longer than {} s (--request-timeout)",
                limit.as_secs_f64()
            ),
        ),
    }
}

/// Runs blocking work off the async threads.
async fn blocking<T: Send + 'static>(f: impl FnOnce() -> Result<T> + Send + 'static) -> Result<T> {
    tokio::task::spawn_blocking(f)
        .await
        .map_err(ServerError::internal)?
}

/// Submission query parameters (halt overrides, seed, priority, scene, file name); the same
/// names as the multipart fields, read by the same parser ([`set_option`]).
#[derive(Debug, Default, serde::Deserialize, utoipa::IntoParams)]
pub struct SubmitQuery {
    /// Job name (default: the Film's filename, else the scene's file stem).
    pub name: Option<String>,
    #[param(value_type = Option<f64>)]
    pub haltspp: Option<String>,
    #[param(value_type = Option<f64>)]
    pub halttime: Option<String>,
    #[param(value_type = Option<f64>)]
    pub haltthreshold: Option<String>,
    #[param(value_type = Option<u64>)]
    pub seed: Option<String>,
    #[param(value_type = Option<i32>)]
    pub priority: Option<String>,
    /// Path of the .lxs inside a bundle holding several.
    pub scene: Option<String>,
    /// Name of the uploaded file for a raw body (decides .lxs naming).
    pub filename: Option<String>,
    /// The animation frame to render (animated scene formats such as LightWave).
    #[param(value_type = Option<i64>)]
    pub frame: Option<String>,
    /// The sequence (id from POST /api/v1/sequences) the job is a frame of.
    pub sequence: Option<String>,
    /// The frame's number in its sequence (outputs are named NAME_0001.png after it).
    #[param(value_type = Option<i64>)]
    pub sequence_frame: Option<String>,
    /// Tags a worker must all have to take the job (comma-separated).
    pub tags: Option<String>,
    /// Memory (MiB) a worker must have to take the job.
    #[param(value_type = Option<u64>)]
    pub min_memory_mb: Option<String>,
    /// The most workers on the job at once.
    #[param(value_type = Option<u32>)]
    pub max_workers: Option<String>,
    /// The job's own webhook: an http or https URL (at most 2048 bytes) posted to when the
    /// job ends (events done, failed, cancelled, halted).
    pub webhook: Option<String>,
}

impl SubmitQuery {
    fn options(&self, owner: String) -> Result<SubmitOptions> {
        let mut o = SubmitOptions {
            owner,
            ..SubmitOptions::default()
        };
        let fields = [
            ("name", &self.name),
            ("haltspp", &self.haltspp),
            ("halttime", &self.halttime),
            ("haltthreshold", &self.haltthreshold),
            ("seed", &self.seed),
            ("priority", &self.priority),
            ("scene", &self.scene),
            ("frame", &self.frame),
            ("sequence", &self.sequence),
            ("sequence_frame", &self.sequence_frame),
            ("tags", &self.tags),
            ("min_memory_mb", &self.min_memory_mb),
            ("max_workers", &self.max_workers),
            ("webhook", &self.webhook),
        ];
        for (name, value) in fields {
            if let Some(v) = value {
                set_option(&mut o, name, v)?;
            }
        }
        Ok(o)
    }
}

/// Sets one submission option from its text (a query parameter or a multipart field); empty
/// text leaves it unset. Unknown names are ignored.
pub fn set_option(o: &mut SubmitOptions, name: &str, text: &str) -> Result<()> {
    let text = text.trim();
    if text.is_empty() {
        return Ok(());
    }
    fn parse<T: std::str::FromStr>(name: &str, text: &str, what: &str) -> Result<T> {
        text.parse::<T>().map_err(|_| {
            ServerError::BadRequest(format!("parameter {name}: {text:?} is not {what}"))
        })
    }
    match name {
        "haltspp" => o.haltspp = Some(parse(name, text, "a number")?),
        "halttime" => o.halttime = Some(parse(name, text, "a number")?),
        "haltthreshold" => o.haltthreshold = Some(parse(name, text, "a number")?),
        "seed" => o.seed = Some(parse(name, text, "an integer from 0 to 2^64-1")?),
        "priority" => o.priority = Some(parse(name, text, "an integer from -2^31 to 2^31-1")?),
        "frame" => o.frame = Some(parse(name, text, "an integer")?),
        "sequence_frame" => o.sequence_frame = Some(parse(name, text, "an integer")?),
        "sequence" => o.sequence = Some(text.to_string()),
        "tags" => o.tags.push(text.to_string()),
        "min_memory_mb" => {
            o.min_memory_mb = Some(parse(name, text, "a whole number of MiB")?);
        }
        "max_workers" => o.max_workers = Some(parse(name, text, "a whole number")?),
        "webhook" => o.webhook = Some(text.to_string()),
        "name" => o.name = Some(text.to_string()),
        "scene" => o.scene = Some(text.to_string()),
        _ => {}
    }
    Ok(())
}

/// Query parameters, with a JSON 400 when they do not parse.
fn query<T>(q: std::result::Result<Query<T>, QueryRejection>) -> Result<T> {
    q.map(|Query(t)| t)
        .map_err(|e| ServerError::BadRequest(e.body_text()))
}

/// Submit a job: a raw .lxs, a .zip or .tar bundle, or multipart/form-data with a `file` part
/// (and optional `haltspp`, `halttime`, `haltthreshold`, `seed`, `priority`, `name`, `scene`,
/// `frame`, `sequence`, `sequence_frame`, `tags`, `min_memory_mb`, `max_workers`, `webhook`
/// fields).
/// Query parameters give the same options. Priorities run from 0 to 100.
#[utoipa::path(post, path = "/api/v1/jobs", params(SubmitQuery),
    request_body(content = Vec<u8>, description = "scene (.lxs), .zip or .tar; or multipart/form-data",
                 content_type = "application/octet-stream"),
    responses((status = 201, body = JobView), (status = 400, body = ErrorBody),
              (status = 413, body = ErrorBody), (status = 415, body = ErrorBody),
              (status = 401, body = ErrorBody)))]
async fn submit_job(
    State(farm): State<AppState>,
    Extension(who): Extension<Identity>,
    q: std::result::Result<Query<SubmitQuery>, QueryRejection>,
    req: Request,
) -> Result<Response> {
    let q = query(q)?;
    let opts = q.options(who.owner())?;
    // An upload announcing more than the limit is refused before its body is read.
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
    let is_multipart = req
        .headers()
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| v.starts_with("multipart/form-data"));
    let (bytes, file_name, opts) = if is_multipart {
        let mp = Multipart::from_request(req, &())
            .await
            .map_err(|e| ServerError::BadRequest(e.to_string()))?;
        read_multipart(mp, opts).await?
    } else {
        let name = q.filename.clone().unwrap_or_else(|| "scene.lxs".into());
        let bytes = Bytes::from_request(req, &())
            .await
            .map_err(|e| match e.status() {
                StatusCode::PAYLOAD_TOO_LARGE => ServerError::TooLarge(e.body_text()),
                _ => ServerError::BadRequest(e.body_text()),
            })?;
        (bytes, name, opts)
    };
    let _unpacking = farm
        .unpack_slots
        .acquire()
        .await
        .map_err(ServerError::internal)?;
    let f = farm.clone();
    let view = blocking(move || {
        let row = f.submit(&bytes, &file_name, &opts)?;
        views::job_view(&f, &row)
    })
    .await?;
    Ok((StatusCode::CREATED, Json(view)).into_response())
}

async fn read_multipart(
    mut mp: Multipart,
    mut opts: SubmitOptions,
) -> Result<(Bytes, String, SubmitOptions)> {
    let bad = |e: axum::extract::multipart::MultipartError| match e.status() {
        StatusCode::PAYLOAD_TOO_LARGE => ServerError::TooLarge(e.body_text()),
        _ => ServerError::BadRequest(e.body_text()),
    };
    let mut file = None;
    while let Some(field) = mp.next_field().await.map_err(bad)? {
        let name = field.name().unwrap_or("").to_string();
        if name == "file" {
            let fname = field.file_name().unwrap_or("scene.lxs").to_string();
            file = Some((field.bytes().await.map_err(bad)?, fname));
            continue;
        }
        let text = field.text().await.map_err(bad)?;
        set_option(&mut opts, &name, &text)?;
    }
    let (bytes, fname) = file
        .ok_or_else(|| ServerError::BadRequest("multipart upload without a `file` part".into()))?;
    Ok((bytes, fname, opts))
}

/// List jobs in scheduling order (priority, then submission).
#[utoipa::path(get, path = "/api/v1/jobs", responses((status = 200, body = Vec<JobView>)))]
async fn list_jobs(State(farm): State<AppState>) -> Result<Json<Vec<JobView>>> {
    Ok(Json(blocking(move || views::job_views(&farm)).await?))
}

/// One job.
#[utoipa::path(get, path = "/api/v1/jobs/{id}", params(("id" = String, Path)),
    responses((status = 200, body = JobView), (status = 404, body = ErrorBody)))]
async fn get_job(State(farm): State<AppState>, Path(id): Path<String>) -> Result<Json<JobView>> {
    Ok(Json(
        blocking(move || views::job_view(&farm, &farm.job_row(&id)?)).await?,
    ))
}

/// Cancel a job (queued or rendering).
#[utoipa::path(delete, path = "/api/v1/jobs/{id}", params(("id" = String, Path)),
    responses((status = 200, body = JobView), (status = 404, body = ErrorBody),
              (status = 409, body = ErrorBody)))]
async fn cancel_job(
    State(farm): State<AppState>,
    Extension(who): Extension<Identity>,
    Path(id): Path<String>,
) -> Result<Json<JobView>> {
    Ok(Json(
        blocking(move || {
            let row = crate::halt::cancel(&farm, &id, &who)?;
            views::job_view(&farm, &row)
        })
        .await?,
    ))
}

/// The job's webhook deliveries: event, hook origin, attempts, last status or error, and
/// whether each was delivered, is pending a retry, or was given up.
#[utoipa::path(get, path = "/api/v1/jobs/{id}/webhooks", params(("id" = String, Path)),
    responses((status = 200, body = Vec<crate::webhooks::WebhookView>),
              (status = 404, body = ErrorBody)))]
async fn job_webhooks(
    State(farm): State<AppState>,
    Path(id): Path<String>,
) -> Result<Json<Vec<crate::webhooks::WebhookView>>> {
    Ok(Json(
        blocking(move || {
            let row = farm.job_row(&id)?;
            let rows = crate::farm::lock(&farm.db).hooks_of_job(&row.id)?;
            Ok(rows.iter().map(crate::webhooks::WebhookView::new).collect())
        })
        .await?,
    ))
}

/// Known workers.
#[utoipa::path(get, path = "/api/v1/workers", responses((status = 200, body = Vec<WorkerView>)))]
async fn list_workers(State(farm): State<AppState>) -> Result<Json<Vec<WorkerView>>> {
    Ok(Json(blocking(move || views::worker_views(&farm)).await?))
}

/// Forgive a quarantined worker now (admin): it takes leases again (its blocks on single
/// jobs stay).
#[utoipa::path(post, path = "/api/v1/workers/{id}/forgive", params(("id" = String, Path)),
    responses((status = 200, body = WorkerView), (status = 404, body = ErrorBody),
              (status = 403, body = ErrorBody)))]
async fn forgive_worker(
    State(farm): State<AppState>,
    Path(id): Path<String>,
) -> Result<Json<WorkerView>> {
    Ok(Json(
        blocking(move || {
            farm.forgive(&id)?;
            views::worker_views(&farm)?
                .into_iter()
                .find(|w| w.id == id)
                .ok_or_else(|| ServerError::NotFound(format!("no worker {id:?}")))
        })
        .await?,
    ))
}

/// A new frame sequence: its name (frames are named `NAME_0001`) and policy.
#[derive(Debug, Default, serde::Deserialize, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct NewSequence {
    #[serde(default)]
    pub name: String,
    /// `spread` (default: workers spread over the unfinished frames) or `earliest` (workers
    /// piled on the earliest unfinished frame).
    #[serde(default)]
    pub policy: String,
}

/// Frame sequences with per-frame state.
#[utoipa::path(get, path = "/api/v1/sequences",
    responses((status = 200, body = Vec<crate::sequence::SequenceView>)))]
async fn list_sequences(
    State(farm): State<AppState>,
) -> Result<Json<Vec<crate::sequence::SequenceView>>> {
    Ok(Json(blocking(move || farm.sequence_views()).await?))
}

/// Create an empty frame sequence; submit its frames to POST /api/v1/jobs with `sequence`
/// and `sequence_frame`.
#[utoipa::path(post, path = "/api/v1/sequences", request_body = NewSequence,
    responses((status = 201, body = crate::sequence::SequenceView),
              (status = 400, body = ErrorBody)))]
async fn create_sequence(
    State(farm): State<AppState>,
    Extension(who): Extension<Identity>,
    body: std::result::Result<Json<NewSequence>, axum::extract::rejection::JsonRejection>,
) -> Result<Response> {
    let Json(n) = body.map_err(|e| ServerError::BadRequest(e.body_text()))?;
    let view = blocking(move || {
        let row = farm.create_sequence(&n.name, &n.policy, &who.owner())?;
        farm.sequence_view(&row.id)
    })
    .await?;
    Ok((StatusCode::CREATED, Json(view)).into_response())
}

/// One frame sequence with per-frame state, spp and output names.
#[utoipa::path(get, path = "/api/v1/sequences/{id}", params(("id" = String, Path)),
    responses((status = 200, body = crate::sequence::SequenceView),
              (status = 404, body = ErrorBody)))]
async fn get_sequence(
    State(farm): State<AppState>,
    Path(id): Path<String>,
) -> Result<Json<crate::sequence::SequenceView>> {
    Ok(Json(blocking(move || farm.sequence_view(&id)).await?))
}

/// Server-Sent Events: a `jobs` event (every job's view, as GET /api/v1/jobs), a `workers`
/// event and a `sequences` event whenever something changed (at most every 250 ms), and a
/// comment every 15 s to keep proxies from closing the stream. Also at `/api/events`.
#[utoipa::path(get, path = "/api/v1/events",
    responses((status = 200, content_type = "text/event-stream", body = String)))]
async fn events(State(farm): State<AppState>) -> Response {
    crate::events::stream(farm).into_response()
}

/// Liveness.
#[utoipa::path(get, path = "/api/v1/healthz", responses((status = 200, body = String)))]
async fn healthz() -> &'static str {
    "ok"
}

/// Prometheus metrics.
#[utoipa::path(get, path = "/api/v1/metrics", responses((status = 200, content_type = "text/plain", body = String)))]
async fn metrics(State(farm): State<AppState>) -> Result<Response> {
    let f = farm.clone();
    let jobs = blocking(move || crate::farm::lock(&f.db).jobs()).await?;
    let states = ["queued", "rendering", "done", "cancelled", "failed"];
    let by_state: Vec<(&str, usize)> = states
        .iter()
        .map(|s| (*s, jobs.iter().filter(|j| j.state.as_str() == *s).count()))
        .collect();
    let (n, lost) = {
        let w = crate::farm::lock(&farm.workers);
        (w.len(), w.values().filter(|w| w.lost).count())
    };
    let mut text = farm.metrics.render(&by_state, n, lost);
    let wanted = crate::schedule::leases_wanted(&jobs, farm.cfg.workers_per_job, |id| {
        crate::farm::lock(&farm.jobs)
            .get(id)
            .is_some_and(|rt| crate::farm::lock(&rt.state).halting.is_some())
    });
    text.push_str(&format!(
        "# HELP luxfarm_leases_wanted Worker leases the unfinished jobs could use now (each job's \
         max_workers, else --workers-per-job); what an autoscaler scales workers on.\n\
         # TYPE luxfarm_leases_wanted gauge\nluxfarm_leases_wanted {wanted}\n"
    ));
    Ok(([(header::CONTENT_TYPE, "text/plain; version=0.0.4")], text).into_response())
}

/// This document.
#[utoipa::path(get, path = "/api/v1/openapi.json", responses((status = 200, body = Object)))]
async fn openapi_json() -> Json<utoipa::openapi::OpenApi> {
    Json(ApiDoc::openapi())
}
