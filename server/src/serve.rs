//! One listening address for gRPC (tonic), REST (axum) and the dashboard: the gRPC services
//! are mounted into the axum router (gRPC requests are routed by their path), an identity
//! layer guards both, and connections are served over HTTP/1.1 and HTTP/2 (h2c, or TLS with
//! ALPN when a certificate is given) under the limits of `conn`.
//!
//! ```text
//! request --identify (bearer token; ?token= only on GET of images and films)--> Identity
//!   --authorize by route (role; worker calls only with a worker's credential)--> handler
//! ```
//!
//! Answers are JSON `{"error","detail"}` for REST (405 and 414 included) and gRPC statuses for
//! gRPC (an unknown service is UNIMPLEMENTED, a request that does not decode
//! INVALID_ARGUMENT). Shutting down drains: no new leases or uploads, in-flight uploads are
//! merged, every job is checkpointed.

use crate::auth::Identity;
use crate::conn::{accept_loop, ConnLimits};
use crate::error::{json_error, Result, ServerError};
use crate::farm::Farm;
use crate::grpc::{AdminService, JobsService, WorkerService};
use axum::extract::{Request, State};
use axum::http::{header, HeaderValue, Method, StatusCode};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use axum::Router;
use luxfarm_proto as pb;
use std::net::SocketAddr;
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::Duration;
use tokio::net::TcpListener;

/// Longest request target (path and query) accepted.
const MAX_URI: usize = 8 * 1024;

/// The whole application: REST + gRPC + dashboard, behind the identity layer.
pub fn app(farm: Arc<Farm>) -> Router {
    let max = pb::MAX_MESSAGE_BYTES;
    let jobs = pb::jobs_server::JobsServer::new(JobsService(farm.clone()))
        .max_decoding_message_size(max)
        .max_encoding_message_size(max);
    let worker = pb::worker_server::WorkerServer::new(WorkerService(farm.clone()))
        .max_decoding_message_size(max)
        .max_encoding_message_size(max);
    let admin = pb::admin_server::AdminServer::new(AdminService(farm.clone()));
    let grpc = tonic::service::Routes::new(jobs)
        .add_service(worker)
        .add_service(admin)
        .into_axum_router()
        .layer(axum::middleware::map_response(client_faults));
    crate::rest::router(farm.clone())
        .merge(grpc)
        .merge(crate::dashboard::router())
        .fallback(not_found)
        .layer(axum::middleware::from_fn_with_state(farm, guard))
}

fn is_grpc(req: &Request) -> bool {
    req.headers()
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| v.starts_with("application/grpc"))
}

/// A gRPC answer carrying only a status.
fn grpc_status(code: tonic::Code, message: &str) -> Response {
    let mut resp = StatusCode::OK.into_response();
    let h = resp.headers_mut();
    h.insert(
        header::CONTENT_TYPE,
        HeaderValue::from_static("application/grpc"),
    );
    h.insert("grpc-status", HeaderValue::from(code as i32));
    let encoded: String = message
        .bytes()
        .map(|b| {
            if b.is_ascii_alphanumeric() || b"-_.~:/".contains(&b) {
                (b as char).to_string()
            } else {
                format!("%{b:02X}")
            }
        })
        .collect();
    if let Ok(v) = HeaderValue::from_str(&encoded) {
        h.insert("grpc-message", v);
    }
    resp
}

async fn not_found(req: Request) -> Response {
    if is_grpc(&req) {
        return grpc_status(
            tonic::Code::Unimplemented,
            &format!("no such gRPC method {}", req.uri().path()),
        );
    }
    json_error(StatusCode::NOT_FOUND, "not_found", "no such route".into())
}

/// A request gRPC could not decode is the client's fault: INVALID_ARGUMENT, not INTERNAL.
async fn client_faults(mut resp: Response) -> Response {
    let h = resp.headers_mut();
    let internal = h.get("grpc-status").is_some_and(|v| v.as_bytes() == b"13");
    let decoding = h.get("grpc-message").is_some_and(|v| {
        let m = v.as_bytes();
        [
            &b"failed%20to%20decode"[..],
            b"protocol%20error",
            b"Unexpected%20EOF",
        ]
        .iter()
        .any(|p| m.starts_with(p))
    });
    if internal && decoding {
        h.insert(
            "grpc-status",
            HeaderValue::from(tonic::Code::InvalidArgument as i32),
        );
    }
    resp
}

/// What a route needs of the caller.
#[derive(Debug, PartialEq, Eq)]
enum Need {
    Nothing,
    Read,
    Submit,
    Admin,
    Register,
    Worker,
}

/// The need of a request, by method and path.
fn need(method: &Method, path: &str) -> Need {
    if path == "/healthz" || path == "/api/v1/healthz" {
        return Need::Nothing;
    }
    if let Some(rpc) = path.strip_prefix("/luxfarm.v1.") {
        return match rpc {
            "Worker/Register" => Need::Register,
            r if r.starts_with("Worker/") => Need::Worker,
            r if r.starts_with("Admin/") => Need::Admin,
            "Jobs/Submit" | "Jobs/CancelJob" | "Jobs/CreateSequence" => Need::Submit,
            _ => Need::Read,
        };
    }
    if !(path.starts_with("/api/") || path == "/metrics") {
        return Need::Nothing; // the dashboard's static page and assets
    }
    if path.starts_with("/api/v1/tokens")
        || (path.starts_with("/api/v1/workers/") && path.ends_with("/forgive"))
    {
        return Need::Admin;
    }
    match *method {
        Method::GET | Method::HEAD => Need::Read,
        _ => Need::Submit,
    }
}

/// True for the downloads a link may carry a `?token=` for (GET of images and films), and the
/// event stream (a browser's EventSource cannot send headers).
fn link_download(method: &Method, path: &str) -> bool {
    let download = path.starts_with("/api/v1/jobs/")
        && ["/preview.png", "/image.png", "/image.exr", "/film.flm"]
            .iter()
            .any(|s| path.ends_with(s));
    let events = path == "/api/events" || path == "/api/v1/events";
    *method == Method::GET && (download || events)
}

/// The bearer token of a request.
fn bearer(req: &Request) -> Option<String> {
    let header = req
        .headers()
        .get(header::AUTHORIZATION)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.strip_prefix("Bearer "))
        .map(str::to_string);
    header.or_else(|| {
        if !link_download(req.method(), req.uri().path()) {
            return None;
        }
        req.uri()
            .query()?
            .split('&')
            .find_map(|kv| kv.strip_prefix("token="))
            .map(str::to_string)
    })
}

/// Identifies the caller, checks the route's need, and passes the identity on to handlers.
async fn guard(State(farm): State<Arc<Farm>>, mut req: Request, next: Next) -> Response {
    let grpc = is_grpc(&req);
    let refuse = |e: ServerError| {
        if grpc {
            let status: tonic::Status = e.into();
            grpc_status(status.code(), status.message())
        } else {
            e.into_response()
        }
    };
    if req.uri().to_string().len() > MAX_URI {
        return json_error(
            StatusCode::URI_TOO_LONG,
            "uri_too_long",
            format!("the request target is longer than {MAX_URI} bytes"),
        );
    }
    let need = need(req.method(), req.uri().path());
    if need == Need::Nothing {
        return next.run(req).await;
    }
    let token = bearer(&req);
    let f = farm.clone();
    let who = tokio::task::spawn_blocking(move || match f.identify(token.as_deref())? {
        Some(id) => Ok(id),
        None => f.anonymous(),
    })
    .await
    .map_err(ServerError::internal)
    .and_then(|r| r);
    let who = match who {
        Ok(w) => w,
        Err(e) => return refuse(e),
    };
    let allowed = match need {
        Need::Nothing => true,
        Need::Read => who.can_read(),
        Need::Submit => who.can_submit(),
        Need::Admin => who.is_admin(),
        Need::Register => who.can_register(),
        Need::Worker => matches!(who, Identity::Worker(_)),
    };
    if !allowed {
        let why = match need {
            Need::Worker => "worker calls need the worker's own credential: register first",
            Need::Register => "registering a worker needs a token of role worker or admin",
            Need::Admin => "this needs an admin token",
            Need::Submit => "this needs a token of role submitter or admin",
            _ => "this needs a token of role viewer, submitter or admin",
        };
        return refuse(ServerError::Forbidden(why.into()));
    }
    req.extensions_mut().insert(who);
    next.run(req).await
}

/// Loads a TLS server configuration (PEM chain and key) with ALPN h2 and http/1.1; errors
/// say which file and what to do.
fn tls_config(cert: &std::path::Path, key: &std::path::Path) -> Result<tokio_rustls::TlsAcceptor> {
    use tokio_rustls::rustls::pki_types::pem::PemObject;
    use tokio_rustls::rustls::pki_types::{CertificateDer, PrivateKeyDer};
    let fix = "give --tls-cert a PEM certificate chain and --tls-key its PEM private key";
    let bad = |what: &std::path::Path, e: &dyn std::fmt::Display| {
        ServerError::BadRequest(format!("TLS: {}: {e} ({fix})", what.display()))
    };
    let certs: Vec<CertificateDer<'static>> = CertificateDer::pem_file_iter(cert)
        .map_err(|e| bad(cert, &e))?
        .collect::<std::result::Result<_, _>>()
        .map_err(|e| bad(cert, &e))?;
    if certs.is_empty() {
        return Err(bad(cert, &"no certificate in the file"));
    }
    let key_der = PrivateKeyDer::from_pem_file(key).map_err(|e| bad(key, &e))?;
    let provider = Arc::new(tokio_rustls::rustls::crypto::ring::default_provider());
    let mut config = tokio_rustls::rustls::ServerConfig::builder_with_provider(provider)
        .with_safe_default_protocol_versions()
        .map_err(|e| ServerError::BadRequest(format!("TLS: {e}")))?
        .with_no_client_auth()
        .with_single_cert(certs, key_der)
        .map_err(|e| {
            ServerError::BadRequest(format!(
                "TLS: {} and {} do not make a usable pair: {e} ({fix})",
                cert.display(),
                key.display()
            ))
        })?;
    config.alpn_protocols = vec![b"h2".to_vec(), b"http/1.1".to_vec()];
    Ok(tokio_rustls::TlsAcceptor::from(Arc::new(config)))
}

/// A running master: its address, and the handle of its accept loop.
pub struct Running {
    addr: SocketAddr,
    farm: Arc<Farm>,
    task: tokio::task::JoinHandle<()>,
    stop: tokio::sync::watch::Sender<bool>,
}

impl Running {
    /// The address the master listens on (the port is the bound one when 0 was asked).
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// Stops accepting connections.
    pub fn stop(&self) {
        let _ = self.stop.send(true);
        self.task.abort();
    }

    /// The accept loop, to await (it ends only when stopped or on a fatal error).
    pub(crate) fn task_mut(&mut self) -> &mut tokio::task::JoinHandle<()> {
        &mut self.task
    }

    /// Shuts down in order: no new connections, leases or uploads; waits (at most `wait`)
    /// for the uploads in flight to be merged; checkpoints every job. Returns the number of
    /// checkpoints that failed.
    pub async fn drain(&self, wait: Duration) -> usize {
        self.farm.draining.store(true, Ordering::SeqCst);
        let _ = self.stop.send(true);
        self.farm.work_available.notify_waiters();
        let all = u32::try_from(4 * self.farm.cores).unwrap_or(u32::MAX);
        match tokio::time::timeout(wait, self.farm.receive_slots.acquire_many(all)).await {
            Ok(_) => tracing::info!("uploads in flight merged"),
            Err(_) => tracing::warn!("uploads still in flight after the drain's wait"),
        }
        let farm = self.farm.clone();
        let failed = tokio::task::spawn_blocking(move || crate::halt::checkpoint_all(&farm))
            .await
            .unwrap_or(1);
        self.task.abort();
        failed
    }

    /// Queues a job from an upload as `POST /jobs` would; returns the job's id.
    pub fn submit(
        &self,
        bytes: &[u8],
        file_name: &str,
        opts: &crate::admission::SubmitOptions,
    ) -> Result<String> {
        Ok(self.farm.submit(bytes, file_name, opts)?.id)
    }

    /// What has been merged into a job (None when the job is not loaded).
    pub fn merge_report(&self, job: &str) -> Option<crate::metrics::MergeReport> {
        self.farm.merge_report(job)
    }
}

/// Opens the store, binds the address and serves until stopped.
pub async fn start(cfg: crate::config::Config) -> anyhow::Result<Running> {
    cfg.validate().map_err(anyhow::Error::msg)?;
    let tls = match (&cfg.tls_cert, &cfg.tls_key) {
        (Some(c), Some(k)) => Some(tls_config(c, k)?),
        _ => None,
    };
    let limits = ConnLimits {
        max_connections: cfg.max_connections,
        header_timeout: Duration::from_secs_f64(cfg.header_timeout),
        idle_timeout: Duration::from_secs_f64(cfg.idle_timeout),
    };
    let hooks = crate::webhooks::Settings::from_config(&cfg)?;
    let listener = TcpListener::bind(cfg.listen).await?;
    let addr = listener.local_addr()?;
    let farm = tokio::task::spawn_blocking(move || Farm::open(cfg)).await??;
    crate::webhooks::spawn(farm.clone(), hooks)?;
    let app = app(farm.clone());
    let ticker = farm.clone();
    tokio::spawn(async move {
        let mut iv = tokio::time::interval(Duration::from_millis(250));
        // A tick that ran long (a large film's convergence test) is not followed by a burst.
        iv.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
        loop {
            iv.tick().await;
            let f = ticker.clone();
            let upkeep = move || {
                let r = crate::halt::tick(&f);
                crate::analysis::tick(&f);
                r
            };
            match tokio::task::spawn_blocking(upkeep).await {
                Ok(Err(e)) => tracing::error!(error = %e, "tick failed"),
                Err(e) => tracing::error!(error = %e, "tick panicked"),
                Ok(Ok(())) => {}
            }
        }
    });
    let (stop, stopped) = tokio::sync::watch::channel(false);
    let task = tokio::spawn(accept_loop(listener, app, tls, limits, stopped));
    Ok(Running {
        addr,
        farm,
        task,
        stop,
    })
}
