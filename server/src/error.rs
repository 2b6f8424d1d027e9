//! The master's error type, and its mapping to HTTP (JSON `{"error","detail"}`) and gRPC status.

use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};

/// Everything that can go wrong in the master. Each variant knows its HTTP status and gRPC code.
#[derive(Debug, thiserror::Error)]
pub enum ServerError {
    /// The request is malformed or its content is refused (bad bundle, bad scene, bad override).
    #[error("{0}")]
    BadRequest(String),
    /// The request is well-formed but its content cannot be used (e.g. a sampling map of the
    /// wrong size, or with negative weights).
    #[error("{0}")]
    Unprocessable(String),
    /// The upload is larger than the configured limit.
    #[error("{0}")]
    TooLarge(String),
    /// The upload is not a format the master accepts.
    #[error("{0}")]
    Unsupported(String),
    /// No such job, worker, lease or output.
    #[error("{0}")]
    NotFound(String),
    /// The request conflicts with the current state (e.g. cancelling a finished job).
    #[error("{0}")]
    Conflict(String),
    /// Missing or wrong bearer token.
    #[error("missing or invalid bearer token")]
    Unauthorized,
    /// The caller's role does not allow the request (or the job is another user's).
    #[error("{0}")]
    Forbidden(String),
    /// The output does not exist yet (no samples merged).
    #[error("{0}")]
    NotReady(String),
    /// The caller acted on a previous run of the master (it restarted): start over.
    #[error("{0}")]
    Restarted(String),
    /// The master is shutting down (or otherwise cannot take the request now): retry later.
    #[error("{0}")]
    Unavailable(String),
    /// The store failed (the database file is `farm.sqlite` in the data directory).
    #[error("database farm.sqlite: {0}")]
    Db(#[from] rusqlite::Error),
    #[error("i/o: {0}")]
    Io(#[from] std::io::Error),
    /// A file of the data directory could not be read or written (path relative to it).
    #[error("{path}: {source}")]
    File {
        path: String,
        source: std::io::Error,
    },
    #[error("{0}")]
    Internal(String),
}

impl From<luxfarm_wire::WireError> for ServerError {
    /// A refused bundle or delta is the sender's fault (400, 413, 415); local files are ours.
    fn from(e: luxfarm_wire::WireError) -> ServerError {
        use luxfarm_wire::WireError as W;
        match e {
            W::Delta(_) | W::UnknownEncoding(_) | W::Bundle(_) | W::Scene(_) => {
                ServerError::BadRequest(e.to_string())
            }
            W::SceneParse(inner) => ServerError::BadRequest(inner.to_string()),
            W::TooLarge(m) => ServerError::TooLarge(m),
            W::Unsupported(m) => ServerError::Unsupported(m),
            W::Io(e) => ServerError::Io(e),
            W::File { .. } => ServerError::Internal(e.to_string()),
        }
    }
}

/// Result alias of the master.
pub type Result<T, E = ServerError> = std::result::Result<T, E>;

impl ServerError {
    /// The HTTP status for this error.
    pub fn status(&self) -> StatusCode {
        match self {
            ServerError::BadRequest(_) => StatusCode::BAD_REQUEST,
            ServerError::Unprocessable(_) => StatusCode::UNPROCESSABLE_ENTITY,
            ServerError::TooLarge(_) => StatusCode::PAYLOAD_TOO_LARGE,
            ServerError::Unsupported(_) => StatusCode::UNSUPPORTED_MEDIA_TYPE,
            ServerError::NotFound(_) => StatusCode::NOT_FOUND,
            ServerError::Conflict(_) => StatusCode::CONFLICT,
            ServerError::Unauthorized => StatusCode::UNAUTHORIZED,
            ServerError::Forbidden(_) => StatusCode::FORBIDDEN,
            ServerError::Restarted(_) => StatusCode::CONFLICT,
            ServerError::NotReady(_) | ServerError::Unavailable(_) => {
                StatusCode::SERVICE_UNAVAILABLE
            }
            ServerError::Db(_)
            | ServerError::Io(_)
            | ServerError::File { .. }
            | ServerError::Internal(_) => StatusCode::INTERNAL_SERVER_ERROR,
        }
    }

    /// A short machine-readable name of the error kind (the `error` field of the JSON body).
    pub fn kind(&self) -> &'static str {
        match self {
            ServerError::BadRequest(_) => "bad_request",
            ServerError::Unprocessable(_) => "unprocessable",
            ServerError::TooLarge(_) => "payload_too_large",
            ServerError::Unsupported(_) => "unsupported_media_type",
            ServerError::NotFound(_) => "not_found",
            ServerError::Conflict(_) => "conflict",
            ServerError::Unauthorized => "unauthorized",
            ServerError::Forbidden(_) => "forbidden",
            ServerError::Restarted(_) => "restarted",
            ServerError::NotReady(_) => "not_ready",
            ServerError::Unavailable(_) => "unavailable",
            ServerError::Db(_)
            | ServerError::Io(_)
            | ServerError::File { .. }
            | ServerError::Internal(_) => "internal",
        }
    }

    /// Shorthand for an internal error from anything displayable.
    pub fn internal(e: impl std::fmt::Display) -> ServerError {
        ServerError::Internal(e.to_string())
    }

    /// An I/O error about a file of the data directory, named relative to it.
    pub fn file(path: impl Into<String>) -> impl FnOnce(std::io::Error) -> ServerError {
        let path = path.into();
        move |source| ServerError::File { path, source }
    }
}

/// The JSON body of every REST error.
#[derive(serde::Serialize, utoipa::ToSchema)]
pub struct ErrorBody {
    /// Error kind, e.g. `bad_request`, `not_found`, `unauthorized`.
    pub error: String,
    /// Human-readable detail (for scene errors: file:line:column: message).
    pub detail: String,
}

/// JSON error response with the given status (used by middleware too).
pub fn json_error(status: StatusCode, error: &str, detail: String) -> Response {
    let body = ErrorBody {
        error: error.to_string(),
        detail,
    };
    (status, axum::Json(body)).into_response()
}

impl IntoResponse for ServerError {
    fn into_response(self) -> Response {
        let status = self.status();
        if status.is_server_error() {
            tracing::error!(error = %self, "request failed");
        }
        json_error(status, self.kind(), self.to_string())
    }
}

impl From<ServerError> for tonic::Status {
    fn from(e: ServerError) -> tonic::Status {
        use tonic::Code;
        let code = match &e {
            ServerError::BadRequest(_) | ServerError::Unprocessable(_) => Code::InvalidArgument,
            ServerError::TooLarge(_) => Code::ResourceExhausted,
            ServerError::Unsupported(_) => Code::InvalidArgument,
            ServerError::NotFound(_) => Code::NotFound,
            ServerError::Conflict(_) => Code::FailedPrecondition,
            ServerError::Unauthorized => Code::Unauthenticated,
            ServerError::Forbidden(_) => Code::PermissionDenied,
            ServerError::Restarted(_) => Code::Aborted,
            ServerError::NotReady(_) | ServerError::Unavailable(_) => Code::Unavailable,
            ServerError::Db(_)
            | ServerError::Io(_)
            | ServerError::File { .. }
            | ServerError::Internal(_) => Code::Internal,
        };
        tonic::Status::new(code, e.to_string())
    }
}
