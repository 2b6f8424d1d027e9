//! Connecting to a master: a channel over http:// or https:// (rustls, with an optional extra
//! CA certificate for a private CA) and an interceptor adding the bearer token (which a worker
//! replaces with its own credential once registered). TLS failures are explained
//! ([`explain`]): what went wrong with the certificate and what to do.

use std::path::Path;
use std::sync::{Arc, RwLock};
use std::time::Duration;
use tonic::metadata::MetadataValue;
use tonic::service::interceptor::InterceptedService;
use tonic::transport::{Certificate, Channel, ClientTlsConfig, Endpoint};
use tonic::{Request, Status};

/// Errors while setting up a connection.
#[derive(Debug, thiserror::Error)]
pub enum ConnectError {
    #[error("invalid master URL {0:?}: {1}")]
    Url(String, String),
    #[error("reading CA certificate {0}: {1}")]
    Ca(String, std::io::Error),
    #[error("TLS setup: {0}")]
    Tls(tonic::transport::Error),
    #[error("invalid token (must be visible ASCII)")]
    Token,
}

/// An endpoint for `url`, lazily connected (the first call connects; reconnects are automatic).
pub fn endpoint(url: &str, ca_cert: Option<&Path>) -> Result<Endpoint, ConnectError> {
    let mut ep = Endpoint::from_shared(url.to_string())
        .map_err(|e| ConnectError::Url(url.to_string(), e.to_string()))?
        .connect_timeout(Duration::from_secs(3))
        .tcp_nodelay(true)
        .http2_keep_alive_interval(Duration::from_secs(20))
        .keep_alive_while_idle(true);
    if url.starts_with("https://") {
        let mut tls = ClientTlsConfig::new().with_enabled_roots();
        if let Some(ca) = ca_cert {
            let pem =
                std::fs::read(ca).map_err(|e| ConnectError::Ca(ca.display().to_string(), e))?;
            tls = tls.ca_certificate(Certificate::from_pem(pem));
        }
        ep = ep.tls_config(tls).map_err(ConnectError::Tls)?;
    }
    Ok(ep)
}

/// Adds `authorization: Bearer TOKEN` to every call when a token is set. Clones share the
/// token: [`Auth::set`] changes it for all of them.
#[derive(Clone)]
pub struct Auth {
    header: Arc<RwLock<Option<MetadataValue<tonic::metadata::Ascii>>>>,
}

fn bearer(
    token: Option<&str>,
) -> Result<Option<MetadataValue<tonic::metadata::Ascii>>, ConnectError> {
    match token.filter(|t| !t.is_empty()) {
        Some(t) => Ok(Some(
            format!("Bearer {t}")
                .parse()
                .map_err(|_| ConnectError::Token)?,
        )),
        None => Ok(None),
    }
}

impl Auth {
    /// An interceptor for `token` (none or empty: no header).
    pub fn new(token: Option<&str>) -> Result<Auth, ConnectError> {
        Ok(Auth {
            header: Arc::new(RwLock::new(bearer(token)?)),
        })
    }

    /// Replaces the token of this interceptor and of its clones.
    pub fn set(&self, token: Option<&str>) -> Result<(), ConnectError> {
        let h = bearer(token)?;
        *self.header.write().unwrap_or_else(|p| p.into_inner()) = h;
        Ok(())
    }
}

impl tonic::service::Interceptor for Auth {
    fn call(&mut self, mut req: Request<()>) -> Result<Request<()>, Status> {
        let header = self
            .header
            .read()
            .unwrap_or_else(|p| p.into_inner())
            .clone();
        if let Some(h) = header {
            req.metadata_mut().insert("authorization", h);
        }
        Ok(req)
    }
}

/// A failed call explained: certificate errors say what to do, others are shown as they are.
pub fn explain(s: &Status) -> String {
    let mut text = s.message().to_string();
    let mut source = std::error::Error::source(s);
    while let Some(e) = source {
        text.push_str(": ");
        text.push_str(&e.to_string());
        source = e.source();
    }
    let hint = if text.contains("CaUsedAsEndEntity") {
        Some(
            "the master's certificate is a CA certificate (basicConstraints CA:TRUE, what \
             `openssl req -x509` makes by default) used as a server certificate: make it with \
             `-addext basicConstraints=critical,CA:FALSE`, or sign a server certificate with \
             a CA and pass the CA with --ca-cert",
        )
    } else if text.contains("UnknownIssuer") {
        Some(
            "the master's certificate is signed by a CA this client does not trust: pass that \
             CA with --ca-cert (the ca.crt `luxfarm certs` made, or the self-signed \
             certificate itself)",
        )
    } else if text.contains("NotValidForName") {
        Some(
            "the master's certificate does not name the host in --master: make its certificate \
             with that name in subjectAltName (`luxfarm certs --force --name HOST ...` keeps the \
             CA), or reach the master by a name it holds",
        )
    } else if text.contains("Expired") {
        Some("the master's certificate has expired: give the master a new one")
    } else {
        None
    };
    match hint {
        Some(h) => format!("{text} ({h})"),
        None => text,
    }
}

/// A channel with the token interceptor.
pub type AuthChannel = InterceptedService<Channel, Auth>;

/// A lazily connected, authenticated channel to the master at `url`.
pub fn channel(
    url: &str,
    token: Option<&str>,
    ca_cert: Option<&Path>,
) -> Result<AuthChannel, ConnectError> {
    channel_with(url, Auth::new(token)?, ca_cert)
}

/// A lazily connected channel to the master at `url` with a given (shared) interceptor.
pub fn channel_with(
    url: &str,
    auth: Auth,
    ca_cert: Option<&Path>,
) -> Result<AuthChannel, ConnectError> {
    let ch = endpoint(url, ca_cert)?.connect_lazy();
    Ok(InterceptedService::new(ch, auth))
}

/// A Jobs client over an authenticated channel.
pub fn jobs_client(ch: AuthChannel) -> crate::jobs_client::JobsClient<AuthChannel> {
    crate::jobs_client::JobsClient::new(ch)
        .max_decoding_message_size(crate::MAX_MESSAGE_BYTES)
        .max_encoding_message_size(crate::MAX_MESSAGE_BYTES)
}

/// A Worker client over an authenticated channel.
pub fn worker_client(ch: AuthChannel) -> crate::worker_client::WorkerClient<AuthChannel> {
    crate::worker_client::WorkerClient::new(ch)
        .max_decoding_message_size(crate::MAX_MESSAGE_BYTES)
        .max_encoding_message_size(crate::MAX_MESSAGE_BYTES)
}
