//! Connections, before anyone is authenticated: how many are served at once and how long a
//! connection may stay without doing anything.
//!
//! ```text
//! listener --(a permit of --max-connections, else wait in the listen queue)--> accept
//!   --TLS handshake (within --header-timeout)--> HTTP/1.1 or HTTP/2 (h2c or ALPN)
//!   --watchdog--> closed gracefully when no request arrived within --header-timeout of the
//!                 connection's start, or none is in progress for --idle-timeout
//! ```
//!
//! HTTP/1.1 request headers must arrive within `--header-timeout` (hyper's header read
//! timeout). A connection counts as busy while one of its requests is being answered (an
//! upload held back by the master's receive slots included), so only connections that do
//! nothing are closed. Together these bound the file descriptors a client can hold.

use axum::extract::Request;
use axum::Router;
use hyper_util::rt::{TokioExecutor, TokioIo, TokioTimer};
use hyper_util::service::TowerToHyperService;
use std::convert::Infallible;
use std::future::Future;
use std::net::SocketAddr;
use std::pin::Pin;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::Arc;
use std::task::{Context, Poll};
use std::time::{Duration, Instant};
use tokio::net::TcpListener;
use tokio::sync::{watch, Semaphore};

/// The bounds of connections.
#[derive(Clone, Copy, Debug)]
pub struct ConnLimits {
    pub max_connections: usize,
    pub header_timeout: Duration,
    pub idle_timeout: Duration,
}

/// What the watchdog of one connection reads.
struct ConnState {
    start: Instant,
    /// Milliseconds after `start` of the last request start or end.
    last_change_ms: AtomicU64,
    in_flight: AtomicUsize,
    served: AtomicBool,
}

impl ConnState {
    fn touch(&self) {
        let ms = self.start.elapsed().as_millis() as u64;
        self.last_change_ms.store(ms, Ordering::Relaxed);
    }

    /// True when the connection has done nothing for longer than it may.
    fn idle(&self, limits: &ConnLimits) -> bool {
        if self.in_flight.load(Ordering::Relaxed) > 0 {
            return false;
        }
        let now = self.start.elapsed().as_millis() as u64;
        let quiet = Duration::from_millis(now - self.last_change_ms.load(Ordering::Relaxed));
        if self.served.load(Ordering::Relaxed) {
            quiet > limits.idle_timeout
        } else {
            quiet > limits.header_timeout
        }
    }
}

/// Counts a connection's requests in progress.
#[derive(Clone)]
struct Counted {
    inner: Router,
    state: Arc<ConnState>,
}

/// Decrements the in-flight count when a request's answer is ready (or dropped).
struct InFlight(Arc<ConnState>);

impl Drop for InFlight {
    fn drop(&mut self) {
        self.0.in_flight.fetch_sub(1, Ordering::Relaxed);
        self.0.touch();
    }
}

impl tower::Service<Request<hyper::body::Incoming>> for Counted {
    type Response = axum::response::Response;
    type Error = Infallible;
    type Future = Pin<Box<dyn Future<Output = Result<Self::Response, Infallible>> + Send>>;

    fn poll_ready(&mut self, _: &mut Context<'_>) -> Poll<Result<(), Infallible>> {
        Poll::Ready(Ok(()))
    }

    fn call(&mut self, req: Request<hyper::body::Incoming>) -> Self::Future {
        self.state.in_flight.fetch_add(1, Ordering::Relaxed);
        self.state.served.store(true, Ordering::Relaxed);
        self.state.touch();
        let guard = InFlight(self.state.clone());
        let fut = tower::Service::call(&mut self.inner, req.map(axum::body::Body::new));
        Box::pin(async move {
            let _guard = guard;
            fut.await
        })
    }
}

/// Accepts connections until `stop` turns true, serving each with `app`.
pub async fn accept_loop(
    listener: TcpListener,
    app: Router,
    tls: Option<tokio_rustls::TlsAcceptor>,
    limits: ConnLimits,
    mut stop: watch::Receiver<bool>,
) {
    let permits = Arc::new(Semaphore::new(limits.max_connections));
    loop {
        let permit = tokio::select! {
            p = permits.clone().acquire_owned() => match p {
                Ok(p) => p,
                Err(_) => return,
            },
            _ = stop.changed() => return,
        };
        let (stream, peer) = tokio::select! {
            r = listener.accept() => match r {
                Ok(s) => s,
                Err(e) => {
                    tracing::warn!(error = %e, "accept failed");
                    tokio::time::sleep(Duration::from_millis(50)).await;
                    continue;
                }
            },
            _ = stop.changed() => return,
        };
        let _ = stream.set_nodelay(true);
        let app = app.clone();
        let tls = tls.clone();
        tokio::spawn(async move {
            let _permit = permit;
            serve(stream, peer, app, tls, limits).await;
        });
    }
}

/// Serves one connection to its end (or until its watchdog closes it).
async fn serve(
    stream: tokio::net::TcpStream,
    peer: SocketAddr,
    app: Router,
    tls: Option<tokio_rustls::TlsAcceptor>,
    limits: ConnLimits,
) {
    let state = Arc::new(ConnState {
        start: Instant::now(),
        last_change_ms: AtomicU64::new(0),
        in_flight: AtomicUsize::new(0),
        served: AtomicBool::new(false),
    });
    let svc = TowerToHyperService::new(Counted {
        inner: app,
        state: state.clone(),
    });
    let mut builder = hyper_util::server::conn::auto::Builder::new(TokioExecutor::new());
    builder
        .http1()
        .timer(TokioTimer::new())
        .header_read_timeout(limits.header_timeout);
    builder.http2().timer(TokioTimer::new());
    let result = match tls {
        Some(acceptor) => {
            match tokio::time::timeout(limits.header_timeout, acceptor.accept(stream)).await {
                Ok(Ok(s)) => watched(&builder, TokioIo::new(s), svc, &state, &limits).await,
                Ok(Err(e)) => {
                    tracing::debug!(%peer, error = %e, "TLS handshake failed");
                    return;
                }
                Err(_) => {
                    tracing::debug!(%peer, "TLS handshake timed out");
                    return;
                }
            }
        }
        None => watched(&builder, TokioIo::new(stream), svc, &state, &limits).await,
    };
    if let Err(e) = result {
        tracing::debug!(%peer, error = %e, "connection ended with an error");
    }
}

type ConnError = Box<dyn std::error::Error + Send + Sync>;

/// Runs a connection under its watchdog: an idle connection is shut down gracefully.
async fn watched<I>(
    builder: &hyper_util::server::conn::auto::Builder<TokioExecutor>,
    io: I,
    svc: TowerToHyperService<Counted>,
    state: &ConnState,
    limits: &ConnLimits,
) -> Result<(), ConnError>
where
    I: hyper::rt::Read + hyper::rt::Write + Unpin + Send + 'static,
{
    let conn = builder.serve_connection_with_upgrades(io, svc);
    tokio::pin!(conn);
    let check = (limits.header_timeout.min(limits.idle_timeout) / 4).max(Duration::from_millis(50));
    loop {
        tokio::select! {
            r = conn.as_mut() => return r,
            _ = tokio::time::sleep(check) => {
                if state.idle(limits) {
                    conn.as_mut().graceful_shutdown();
                    return conn.await;
                }
            }
        }
    }
}
