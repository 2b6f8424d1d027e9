//! Connecting to a master: a channel over http:// or https:// (rustls, with an optional extra
//! CA certificate for self-signed masters) and an interceptor adding the bearer token.

use std::path::Path;
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

/// Adds `authorization: Bearer TOKEN` to every call when a token is set.
#[derive(Clone)]
pub struct Auth {
    header: Option<MetadataValue<tonic::metadata::Ascii>>,
}

impl Auth {
    /// An interceptor for `token` (none or empty: no header).
    pub fn new(token: Option<&str>) -> Result<Auth, ConnectError> {
        let header = match token.filter(|t| !t.is_empty()) {
            Some(t) => Some(
                format!("Bearer {t}")
                    .parse()
                    .map_err(|_| ConnectError::Token)?,
            ),
            None => None,
        };
        Ok(Auth { header })
    }
}

impl tonic::service::Interceptor for Auth {
    fn call(&mut self, mut req: Request<()>) -> Result<Request<()>, Status> {
        if let Some(h) = &self.header {
            req.metadata_mut().insert("authorization", h.clone());
        }
        Ok(req)
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
    let ch = endpoint(url, ca_cert)?.connect_lazy();
    Ok(InterceptedService::new(ch, Auth::new(token)?))
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
