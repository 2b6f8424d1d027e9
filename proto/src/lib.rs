//! The gRPC contract between luxfarm clients, the master and workers, generated from
//! `proto/luxfarm.proto` at build time (protox + tonic-prost-build, no system protoc).

#![allow(clippy::all, clippy::pedantic, missing_docs)]

/// Package `luxfarm.v1`: the `Jobs` and `Worker` services and their messages.
pub mod v1 {
    tonic::include_proto!("luxfarm.v1");
}

pub use v1::*;

/// Largest gRPC message the farm sends or accepts (bytes). Bundles and films travel in chunks
/// well below this.
pub const MAX_MESSAGE_BYTES: usize = 16 * 1024 * 1024;

/// Size of the chunks bundles, films and outputs are streamed in (bytes).
pub const CHUNK_BYTES: usize = 1024 * 1024;

/// The version of the worker protocol (registration, assignments, uploads, heartbeats) this
/// build speaks. Worker and master exchange it at registration and refuse a different one.
/// 2: worker credentials, durable sequence numbers, sample budgets.
/// 3: a noise-aware job's deltas carry each pixel's variance sums (`VAR1` section), from
/// which the master builds the sampling map; a master or worker of version 2 would refuse or
/// drop them.
pub const PROTOCOL_VERSION: u32 = 3;

/// This build's version (the luxfarm release), shown when versions disagree.
pub const BUILD: &str = env!("CARGO_PKG_VERSION");

pub mod connect;
