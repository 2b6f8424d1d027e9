//! One listening address for gRPC (tonic), REST (axum) and the dashboard: the gRPC services
//! are mounted into the axum router (gRPC requests are routed by their path), a bearer-token
//! layer guards both, and connections are served over HTTP/1.1 and HTTP/2 (h2c, or TLS with
//! ALPN when a certificate is given).

use crate::error::{json_error, Result, ServerError};
use crate::farm::Farm;
use crate::grpc::{JobsService, WorkerService};
use axum::extract::{Request, State};
use axum::http::{header, HeaderValue, StatusCode};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use axum::Router;
use hyper_util::rt::{TokioExecutor, TokioIo};
use hyper_util::service::TowerToHyperService;
use luxfarm_proto as pb;
use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;
use tokio::net::TcpListener;

/// The whole application: REST + gRPC, behind the token check.
pub fn app(farm: Arc<Farm>) -> Router {
    let max = pb::MAX_MESSAGE_BYTES;
    let jobs = pb::jobs_server::JobsServer::new(JobsService(farm.clone()))
        .max_decoding_message_size(max)
        .max_encoding_message_size(max);
    let worker = pb::worker_server::WorkerServer::new(WorkerService(farm.clone()))
        .max_decoding_message_size(max)
        .max_encoding_message_size(max);
    let grpc = tonic::service::Routes::new(jobs)
        .add_service(worker)
        .into_axum_router();
    crate::rest::router(farm.clone())
        .merge(grpc)
        .merge(crate::dashboard::router())
        .fallback(not_found)
        .layer(axum::middleware::from_fn_with_state(farm, auth))
}

async fn not_found() -> Response {
    json_error(StatusCode::NOT_FOUND, "not_found", "no such route".into())
}

/// Constant-time comparison of two byte strings.
fn same(a: &[u8], b: &[u8]) -> bool {
    a.len() == b.len() && a.iter().zip(b).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}

/// Bearer-token check for every route but the health check and the dashboard's static
/// assets. gRPC callers get an UNAUTHENTICATED status, REST callers a 401 JSON error.
async fn auth(State(farm): State<Arc<Farm>>, req: Request, next: Next) -> Response {
    let Some(token) = farm.cfg.token.as_deref().filter(|t| !t.is_empty()) else {
        return next.run(req).await;
    };
    let path = req.uri().path();
    let open = path == "/healthz"
        || path == "/api/v1/healthz"
        || !(path.starts_with("/api/") || path.starts_with("/luxfarm.") || path == "/metrics");
    let given = req
        .headers()
        .get(header::AUTHORIZATION)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.strip_prefix("Bearer "))
        .or_else(|| {
            // Browsers cannot set headers on <img> requests: allow ?token= on GETs.
            req.uri()
                .query()
                .and_then(|q| q.split('&').find_map(|kv| kv.strip_prefix("token=")))
        });
    if open || given.is_some_and(|g| same(g.as_bytes(), token.as_bytes())) {
        return next.run(req).await;
    }
    let grpc = req
        .headers()
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| v.starts_with("application/grpc"));
    if grpc {
        let mut resp = StatusCode::OK.into_response();
        let h = resp.headers_mut();
        h.insert(
            header::CONTENT_TYPE,
            HeaderValue::from_static("application/grpc"),
        );
        h.insert("grpc-status", HeaderValue::from_static("16"));
        h.insert(
            "grpc-message",
            HeaderValue::from_static("missing%20or%20invalid%20bearer%20token"),
        );
        return resp;
    }
    ServerError::Unauthorized.into_response()
}

/// Loads a TLS server configuration (PEM chain and key) with ALPN h2 and http/1.1.
fn tls_config(cert: &std::path::Path, key: &std::path::Path) -> Result<tokio_rustls::TlsAcceptor> {
    use tokio_rustls::rustls::pki_types::pem::PemObject;
    use tokio_rustls::rustls::pki_types::{CertificateDer, PrivateKeyDer};
    let bad = |e: &dyn std::fmt::Display| ServerError::BadRequest(format!("TLS: {e}"));
    let certs: Vec<CertificateDer<'static>> = CertificateDer::pem_file_iter(cert)
        .map_err(|e| bad(&e))?
        .collect::<std::result::Result<_, _>>()
        .map_err(|e| bad(&e))?;
    let key = PrivateKeyDer::from_pem_file(key).map_err(|e| bad(&e))?;
    let provider = Arc::new(tokio_rustls::rustls::crypto::ring::default_provider());
    let mut config = tokio_rustls::rustls::ServerConfig::builder_with_provider(provider)
        .with_safe_default_protocol_versions()
        .map_err(|e| bad(&e))?
        .with_no_client_auth()
        .with_single_cert(certs, key)
        .map_err(|e| bad(&e))?;
    config.alpn_protocols = vec![b"h2".to_vec(), b"http/1.1".to_vec()];
    Ok(tokio_rustls::TlsAcceptor::from(Arc::new(config)))
}

/// A running master: its address, and the handle of its accept loop.
pub struct Running {
    addr: SocketAddr,
    farm: Arc<Farm>,
    task: tokio::task::JoinHandle<()>,
}

impl Running {
    /// The address the master listens on (the port is the bound one when 0 was asked).
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// Stops accepting connections.
    pub fn stop(&self) {
        self.task.abort();
    }

    /// The accept loop, to await (it ends only when stopped or on a fatal error).
    pub(crate) fn task_mut(&mut self) -> &mut tokio::task::JoinHandle<()> {
        &mut self.task
    }

    /// Queues a job from an upload as `POST /jobs` would; returns the job's id.
    pub fn submit(
        &self,
        bytes: &[u8],
        file_name: &str,
        opts: &crate::farm::SubmitOptions,
    ) -> Result<String> {
        Ok(self.farm.submit(bytes, file_name, opts)?.id)
    }

    /// What has been merged into a job (None when the job is not loaded).
    pub fn merge_report(&self, job: &str) -> Option<crate::metrics::MergeReport> {
        self.farm.merge_report(job)
    }
}

/// Opens the store, binds the address and serves until the task is dropped or aborted.
pub async fn start(cfg: crate::config::Config) -> anyhow::Result<Running> {
    cfg.validate().map_err(anyhow::Error::msg)?;
    let tls = match (&cfg.tls_cert, &cfg.tls_key) {
        (Some(c), Some(k)) => Some(tls_config(c, k)?),
        _ => None,
    };
    let listener = TcpListener::bind(cfg.listen).await?;
    let addr = listener.local_addr()?;
    let farm = Farm::open(cfg)?;
    let app = app(farm.clone());
    let ticker = farm.clone();
    tokio::spawn(async move {
        let mut iv = tokio::time::interval(Duration::from_millis(250));
        loop {
            iv.tick().await;
            let f = ticker.clone();
            match tokio::task::spawn_blocking(move || crate::halt::tick(&f)).await {
                Ok(Err(e)) => tracing::error!(error = %e, "tick failed"),
                Err(e) => tracing::error!(error = %e, "tick panicked"),
                Ok(Ok(())) => {}
            }
        }
    });
    let task = tokio::spawn(accept_loop(listener, app, tls));
    Ok(Running { addr, farm, task })
}

async fn accept_loop(listener: TcpListener, app: Router, tls: Option<tokio_rustls::TlsAcceptor>) {
    loop {
        let (stream, peer) = match listener.accept().await {
            Ok(s) => s,
            Err(e) => {
                tracing::warn!(error = %e, "accept failed");
                tokio::time::sleep(Duration::from_millis(50)).await;
                continue;
            }
        };
        let _ = stream.set_nodelay(true);
        let svc = TowerToHyperService::new(app.clone());
        let tls = tls.clone();
        tokio::spawn(async move {
            let builder = hyper_util::server::conn::auto::Builder::new(TokioExecutor::new());
            let result = match tls {
                Some(acceptor) => match acceptor.accept(stream).await {
                    Ok(s) => {
                        builder
                            .serve_connection_with_upgrades(TokioIo::new(s), svc)
                            .await
                    }
                    Err(e) => {
                        tracing::debug!(%peer, error = %e, "TLS handshake failed");
                        return;
                    }
                },
                None => {
                    builder
                        .serve_connection_with_upgrades(TokioIo::new(stream), svc)
                        .await
                }
            };
            if let Err(e) = result {
                tracing::debug!(%peer, error = %e, "connection ended with an error");
            }
        });
    }
}
