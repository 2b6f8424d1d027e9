//! The gRPC services (`luxfarm.v1.Jobs` for clients, `luxfarm.v1.Worker` for workers,
//! `luxfarm.v1.Admin` for tokens) over the shared [`Farm`]. The caller's [`Identity`] comes
//! from the request's extensions (set by the identity layer in `serve`): worker calls act for
//! the authenticated worker whatever worker id a message names.

use crate::admission::SubmitOptions;
use crate::auth::Identity;
use crate::error::ServerError;
use crate::farm::Farm;
use crate::output::tonemap::TonemapOverride;
use crate::views;
use luxfarm_proto as pb;
use std::pin::Pin;
use std::sync::Arc;
use std::time::Duration;
use tokio_stream::{Stream, StreamExt};
use tonic::{Request, Response, Status, Streaming};

/// The caller's identity (the identity layer always sets one on guarded routes).
fn identity<T>(req: &Request<T>) -> Result<Identity, Status> {
    req.extensions()
        .get::<Identity>()
        .cloned()
        .ok_or_else(|| Status::unauthenticated("missing or invalid bearer token"))
}

/// The authenticated worker's id.
fn worker_id<T>(req: &Request<T>) -> Result<String, Status> {
    Ok(identity(req)?.worker()?.to_string())
}

/// A stream item, with a request that could not be decoded reported as the client's fault.
fn item<T>(r: Option<Result<T, Status>>) -> Result<Option<T>, Status> {
    match r {
        Some(Err(s)) if s.code() == tonic::Code::Internal => {
            Err(Status::invalid_argument(s.message().to_string()))
        }
        other => other.transpose(),
    }
}

type BoxStream<T> = Pin<Box<dyn Stream<Item = Result<T, Status>> + Send>>;

/// Runs blocking work (file I/O, film decoding and merging) off the async threads.
async fn blocking<T: Send + 'static>(
    f: impl FnOnce() -> Result<T, ServerError> + Send + 'static,
) -> Result<T, Status> {
    tokio::task::spawn_blocking(f)
        .await
        .map_err(|e| Status::internal(e.to_string()))?
        .map_err(Status::from)
}

/// Splits bytes into a stream of chunks.
fn chunk_stream(bytes: Vec<u8>) -> BoxStream<pb::DataChunk> {
    let chunks: Vec<Result<pb::DataChunk, Status>> = bytes
        .chunks(pb::CHUNK_BYTES)
        .map(|c| Ok(pb::DataChunk { data: c.to_vec() }))
        .collect();
    Box::pin(tokio_stream::iter(chunks))
}

/// The client-facing service.
pub struct JobsService(pub Arc<Farm>);

#[tonic::async_trait]
impl pb::jobs_server::Jobs for JobsService {
    async fn submit(
        &self,
        req: Request<Streaming<pb::SubmitChunk>>,
    ) -> Result<Response<pb::JobInfo>, Status> {
        let who = identity(&req)?;
        let mut stream = req.into_inner();
        let mut header = None;
        let mut data = Vec::new();
        let limit = self.0.cfg.max_upload;
        while let Some(chunk) = item(stream.next().await)? {
            match chunk.part {
                Some(pb::submit_chunk::Part::Header(h)) => header = Some(h),
                Some(pb::submit_chunk::Part::Data(d)) => {
                    if (data.len() + d.len()) as u64 > limit {
                        return Err(ServerError::TooLarge(format!(
                            "upload exceeds the limit of {limit} bytes"
                        ))
                        .into());
                    }
                    data.extend_from_slice(&d);
                }
                None => {}
            }
        }
        let h = header.ok_or_else(|| Status::invalid_argument("missing submit header"))?;
        let opts = SubmitOptions {
            name: Some(h.name),
            haltspp: h.haltspp,
            halttime: h.halttime,
            haltthreshold: h.haltthreshold,
            seed: h.seed,
            priority: h.priority,
            scene: Some(h.scene),
            frame: h.frame,
            owner: who.owner(),
            sequence: Some(h.sequence),
            sequence_frame: h.sequence_frame,
            tags: h.tags,
            min_memory_mb: h.min_memory_mb,
            max_workers: h.max_workers,
            webhook: Some(h.webhook).filter(|u| !u.is_empty()),
        };
        let _unpacking = self
            .0
            .unpack_slots
            .acquire()
            .await
            .map_err(|e| Status::internal(e.to_string()))?;
        let farm = self.0.clone();
        let view = blocking(move || {
            let row = farm.submit(&data, &h.file_name, &opts)?;
            views::job_view(&farm, &row)
        })
        .await?;
        Ok(Response::new(view.into()))
    }

    async fn list_jobs(
        &self,
        _: Request<pb::ListJobsRequest>,
    ) -> Result<Response<pb::ListJobsReply>, Status> {
        let jobs = views::job_views(&self.0)?;
        Ok(Response::new(pb::ListJobsReply {
            jobs: jobs.into_iter().map(Into::into).collect(),
        }))
    }

    async fn get_job(&self, req: Request<pb::JobRef>) -> Result<Response<pb::JobInfo>, Status> {
        let row = self.0.job_row(&req.into_inner().id)?;
        Ok(Response::new(views::job_view(&self.0, &row)?.into()))
    }

    async fn cancel_job(&self, req: Request<pb::JobRef>) -> Result<Response<pb::JobInfo>, Status> {
        let who = identity(&req)?;
        let farm = self.0.clone();
        let id = req.into_inner().id;
        let view = blocking(move || {
            let row = crate::halt::cancel(&farm, &id, &who)?;
            views::job_view(&farm, &row)
        })
        .await?;
        Ok(Response::new(view.into()))
    }

    async fn create_sequence(
        &self,
        req: Request<pb::CreateSequenceRequest>,
    ) -> Result<Response<pb::SequenceInfo>, Status> {
        let who = identity(&req)?;
        let r = req.into_inner();
        let farm = self.0.clone();
        let row = blocking(move || farm.create_sequence(&r.name, &r.policy, &who.owner())).await?;
        Ok(Response::new(pb::SequenceInfo {
            id: row.id,
            name: row.name,
            policy: row.policy,
        }))
    }

    type WatchStream = BoxStream<pb::JobInfo>;

    async fn watch(&self, req: Request<pb::JobRef>) -> Result<Response<Self::WatchStream>, Status> {
        let id = req.into_inner().id;
        self.0.job_row(&id)?;
        let farm = self.0.clone();
        let (tx, rx) = tokio::sync::mpsc::channel(4);
        tokio::spawn(async move {
            let mut changed = farm.changed.subscribe();
            loop {
                let view = farm
                    .job_row(&id)
                    .and_then(|row| views::job_view(&farm, &row))
                    .map_err(Status::from);
                let done = view.as_ref().map_or(true, |v| v.state.is_final());
                if tx.send(view.map(Into::into)).await.is_err() || done {
                    break;
                }
                let _ = tokio::time::timeout(Duration::from_secs(1), changed.changed()).await;
                tokio::time::sleep(Duration::from_millis(200)).await;
            }
        });
        Ok(Response::new(Box::pin(
            tokio_stream::wrappers::ReceiverStream::new(rx),
        )))
    }

    type FetchStream = BoxStream<pb::DataChunk>;

    async fn fetch(
        &self,
        req: Request<pb::FetchRequest>,
    ) -> Result<Response<Self::FetchStream>, Status> {
        let r = req.into_inner();
        let (size, tm) = fetch_options(&r)?;
        let farm = self.0.clone();
        let bytes =
            blocking(move || crate::output::render_with(&farm, &r.id, &r.format, size, &tm))
                .await?;
        Ok(Response::new(chunk_stream(bytes.bytes)))
    }

    async fn list_workers(
        &self,
        _: Request<pb::ListWorkersRequest>,
    ) -> Result<Response<pb::ListWorkersReply>, Status> {
        let farm = self.0.clone();
        let workers = blocking(move || views::worker_views(&farm)).await?;
        Ok(Response::new(pb::ListWorkersReply {
            workers: workers.into_iter().map(Into::into).collect(),
        }))
    }
}

/// A fetch's PNG size and tonemapping, validated as REST's image.png query is (errors name
/// the parameter); they apply to PNGs only.
fn fetch_options(r: &pb::FetchRequest) -> Result<(Option<u32>, TonemapOverride), ServerError> {
    if r.format != "png" && (r.max_size > 0 || !r.tonemap.is_empty()) {
        return Err(ServerError::BadRequest(format!(
            "max_size and tonemap apply to png only, not {:?}",
            r.format
        )));
    }
    let params = r
        .tonemap
        .iter()
        .filter(|(k, _)| k.as_str() != "kernel")
        .map(|(k, v)| (k.as_str(), Some(v.as_str())));
    let tm = TonemapOverride::parse(r.tonemap.get("kernel").map(String::as_str), params)?;
    Ok(((r.max_size > 0).then_some(r.max_size), tm))
}

/// The worker-facing service.
pub struct WorkerService(pub Arc<Farm>);

#[tonic::async_trait]
impl pb::worker_server::Worker for WorkerService {
    async fn register(
        &self,
        req: Request<pb::RegisterRequest>,
    ) -> Result<Response<pb::RegisterReply>, Status> {
        let r = req.into_inner();
        let farm = self.0.clone();
        let reply = blocking(move || farm.register(&r)).await?;
        Ok(Response::new(reply))
    }

    async fn next_assignment(
        &self,
        req: Request<pb::NextRequest>,
    ) -> Result<Response<pb::NextReply>, Status> {
        let worker = worker_id(&req)?;
        let deadline = tokio::time::Instant::now() + Duration::from_secs(5);
        loop {
            let notified = self.0.work_available.notified();
            let farm = self.0.clone();
            let w = worker.clone();
            let assignment = blocking(move || farm.assign(&w)).await?;
            if assignment.is_some() || tokio::time::Instant::now() >= deadline {
                return Ok(Response::new(pb::NextReply { assignment }));
            }
            let _ = tokio::time::timeout_at(deadline, notified).await;
        }
    }

    type FetchBundleStream = BoxStream<pb::DataChunk>;

    async fn fetch_bundle(
        &self,
        req: Request<pb::BundleRequest>,
    ) -> Result<Response<Self::FetchBundleStream>, Status> {
        worker_id(&req)?;
        let hash = req.into_inner().hash;
        if !luxfarm_wire::bundle::is_hash(&hash) {
            return Err(Status::invalid_argument("not a bundle hash"));
        }
        let path = self.0.bundle_path(&hash);
        let bytes = tokio::fs::read(&path)
            .await
            .map_err(|_| Status::not_found(format!("no bundle {hash}")))?;
        Ok(Response::new(chunk_stream(bytes)))
    }

    async fn upload_delta(
        &self,
        req: Request<Streaming<pb::UploadChunk>>,
    ) -> Result<Response<pb::UploadAck>, Status> {
        let worker = worker_id(&req)?;
        let mut stream = req.into_inner();
        // The header comes first and is checked (lease held, job open, size bounded) before
        // a byte of the body is read.
        let h = match item(stream.next().await)?.and_then(|c| c.part) {
            Some(pb::upload_chunk::Part::Header(h)) => h,
            _ => return Err(Status::invalid_argument("an upload starts with its header")),
        };
        let (farm, w, hh) = (self.0.clone(), worker.clone(), h.clone());
        blocking(move || farm.check_upload(&w, &hh)).await?;
        let size =
            usize::try_from(h.size).map_err(|_| Status::resource_exhausted("delta too large"))?;
        let _receiving = self
            .0
            .receive_slots
            .acquire()
            .await
            .map_err(|e| Status::internal(e.to_string()))?;
        // A kept buffer (`scratch`): no fresh pages per upload.
        let mut data = self.0.received.take(size);
        while let Some(chunk) = item(stream.next().await)? {
            match chunk.part {
                Some(pb::upload_chunk::Part::Data(d)) => {
                    if data.len() + d.len() > size {
                        return Err(Status::invalid_argument(format!(
                            "the delta is longer than the {size} bytes its header announced"
                        )));
                    }
                    data.extend_from_slice(&d);
                }
                Some(pb::upload_chunk::Part::Header(_)) => {
                    return Err(Status::invalid_argument("an upload has one header"))
                }
                None => {}
            }
        }
        if data.len() != size {
            return Err(Status::invalid_argument(format!(
                "the delta has {} bytes, its header announced {size}",
                data.len()
            )));
        }
        let farm = self.0.clone();
        let span = tracing::info_span!("upload", lease = %h.lease_id, seq = h.seq);
        let _slot = self
            .0
            .merge_slots
            .acquire()
            .await
            .map_err(|e| Status::internal(e.to_string()))?;
        let ack = blocking(move || {
            let _e = span.enter();
            let ack = farm.upload(&worker, &h, &data);
            farm.received.give_back(data);
            ack
        })
        .await?;
        Ok(Response::new(ack))
    }

    async fn heartbeat(
        &self,
        req: Request<pb::HeartbeatRequest>,
    ) -> Result<Response<pb::HeartbeatReply>, Status> {
        let worker = worker_id(&req)?;
        let r = req.into_inner();
        let farm = self.0.clone();
        let reply = blocking(move || Ok(farm.heartbeat(&worker, &r))).await?;
        Ok(Response::new(reply))
    }

    async fn report_failure(
        &self,
        req: Request<pb::FailureReport>,
    ) -> Result<Response<pb::FailureAck>, Status> {
        let worker = worker_id(&req)?;
        let r = req.into_inner();
        let farm = self.0.clone();
        blocking(move || farm.lease_failed(&worker, &r.lease_id, &r.reason)).await?;
        Ok(Response::new(pb::FailureAck {}))
    }
}

/// The admin service: user tokens.
pub struct AdminService(pub Arc<Farm>);

fn token_info(t: crate::db::TokenRow) -> pb::TokenInfo {
    pb::TokenInfo {
        id: t.id,
        name: t.name,
        role: t.role,
        created_ms: t.created_ms,
        revoked_ms: t.revoked_ms,
    }
}

#[tonic::async_trait]
impl pb::admin_server::Admin for AdminService {
    async fn add_token(
        &self,
        req: Request<pb::AddTokenRequest>,
    ) -> Result<Response<pb::AddTokenReply>, Status> {
        let r = req.into_inner();
        let farm = self.0.clone();
        let (row, token) = blocking(move || farm.add_token(&r.name, &r.role)).await?;
        Ok(Response::new(pb::AddTokenReply {
            info: Some(token_info(row)),
            token,
        }))
    }

    async fn list_tokens(
        &self,
        _: Request<pb::ListTokensRequest>,
    ) -> Result<Response<pb::ListTokensReply>, Status> {
        let farm = self.0.clone();
        let rows = blocking(move || farm.tokens()).await?;
        Ok(Response::new(pb::ListTokensReply {
            tokens: rows.into_iter().map(token_info).collect(),
        }))
    }

    async fn revoke_token(
        &self,
        req: Request<pb::RevokeTokenRequest>,
    ) -> Result<Response<pb::TokenInfo>, Status> {
        let id = req.into_inner().id;
        let farm = self.0.clone();
        let row = blocking(move || farm.revoke_token(&id)).await?;
        Ok(Response::new(token_info(row)))
    }
}
