//! What travels between luxfarm's processes, shared by the client, the master and the workers
//! (and by nothing that needs a server: no HTTP, database or async runtime here).
//!
//! - [`codec`]: film deltas on the wire. A worker encodes its session film ([`codec::encode_delta`],
//!   `lxd2`), the master decodes it ([`codec::decode_as`]) and adds it to the job's film;
//!   checkpoints use the raw `lxd1` form ([`codec::encode`], [`codec::decode`]).
//! - [`bundle`]: scene bundles. The client packs a scene with every file it references
//!   ([`bundle::prepare`]); the master unpacks an upload safely ([`bundle::unpack`]), picks the
//!   scene ([`bundle::pick_scene`]) and stores a canonical tar under its hash
//!   ([`bundle::write_canonical_tar`]); a worker checks the tar it fetched against that hash and
//!   unpacks it with the same rules.
//!
//! Errors are [`WireError`] values; nothing read from the network or a file panics.

pub mod bundle;
pub mod codec;
mod error;

pub use error::{Result, WireError};
