//! The wire's error type. Each variant says who is at fault, so the master can map it to a
//! status (a refused bundle or delta is the sender's fault, a full disk is not).

/// Everything that can go wrong encoding, decoding, packing or unpacking.
#[derive(Debug, thiserror::Error)]
pub enum WireError {
    /// A film delta that cannot be read: truncated, malformed, or holding non-finite values.
    #[error("film delta unreadable: {0}")]
    Delta(String),
    /// A delta sent under an encoding name this side does not know.
    #[error("unknown delta encoding {0:?} (expected \"lxd1\" or \"lxd2\")")]
    UnknownEncoding(String),
    /// A bundle refused: an unsafe entry name, a link or device, a malformed archive, or no
    /// scene to render.
    #[error("{0}")]
    Bundle(String),
    /// A bundle larger than the limits allow (entries or unpacked bytes).
    #[error("{0}")]
    TooLarge(String),
    /// An upload in a format that is not accepted (compressed tar, binary data).
    #[error("{0}")]
    Unsupported(String),
    /// A scene that cannot be bundled because it does not parse (the located error is the
    /// source, so a caller that walks the chain prints it once and can tell it is the input's).
    #[error("the scene cannot be bundled")]
    SceneParse(#[source] luxfarm::lxs::LxsError),
    /// A scene that cannot be bundled: a referenced file is missing or outside the scene's
    /// directory.
    #[error("{0}")]
    Scene(String),
    /// A local file that cannot be read while packing.
    #[error("{}: {source}", path.display())]
    File {
        path: std::path::PathBuf,
        source: std::io::Error,
    },
    /// Reading or writing local files.
    #[error("i/o: {0}")]
    Io(#[from] std::io::Error),
}

/// Result alias of the wire crate.
pub type Result<T, E = WireError> = std::result::Result<T, E>;
