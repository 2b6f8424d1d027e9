//! The error type of the film layer (Film parameters, films, FLM files, comparisons).

use crate::lxs::Loc;
use std::path::PathBuf;

/// Everything that can go wrong while building, reading, writing or merging a film.
#[derive(Debug, thiserror::Error)]
pub enum FilmError {
    /// A Film parameter with an unusable value (names the scene location).
    #[error("{loc}: {message}")]
    Param { loc: Loc, message: String },
    #[error("I/O error on {path}: {source}")]
    File {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("I/O error: {0}")]
    Io(#[from] std::io::Error),
    /// The gzip stream ended early or is corrupt.
    #[error("FLM data is truncated or its gzip stream is corrupt ({context}): {source}")]
    Corrupt {
        context: &'static str,
        #[source]
        source: std::io::Error,
    },
    #[error("not an FLM file: magic number {found:#010x}, expected 0xcebcd816")]
    BadMagic { found: u32 },
    #[error("unsupported FLM version {found} (only version 0 exists)")]
    BadVersion { found: i32 },
    #[error("FLM header refused: {0}")]
    BadHeader(String),
    #[error("FLM resolution {width}x{height} refused: at most 65536 pixels per axis and 2^28 pixels in all")]
    TooLarge { width: u32, height: u32 },
    #[error("non-finite or negative value in FLM data: group {group}, buffer {buffer}, pixel ({x}, {y})")]
    NonFinite {
        group: usize,
        buffer: usize,
        x: u32,
        y: u32,
    },
    /// A film sum beyond f32's range, which an FLM (f32 sums) cannot hold.
    #[error("film value {value:e} (group {group}, buffer {buffer}, pixel ({x}, {y})) overflows the FLM's f32 sums")]
    Overflow {
        value: f64,
        group: usize,
        buffer: usize,
        x: u32,
        y: u32,
    },
    #[error("films do not match: {0}")]
    Mismatch(String),
    #[error("{0}")]
    Unsupported(String),
}

impl From<crate::atomic_write::FileError> for FilmError {
    fn from(e: crate::atomic_write::FileError) -> FilmError {
        FilmError::File {
            path: e.path,
            source: e.source,
        }
    }
}

impl FilmError {
    /// An I/O error naming the file it happened on.
    pub fn file(path: impl Into<PathBuf>, source: std::io::Error) -> FilmError {
        FilmError::File {
            path: path.into(),
            source,
        }
    }
}
