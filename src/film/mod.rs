//! Film buffers as LuxRender's fleximage keeps them, FLM v0 read/write, merging, comparison and
//! convergence.
//!
//! - [`Film`]: f64 sums per light group and pixel, f64 sample counts ([`buffer`]).
//! - [`FilmParams`]: the `Film "fleximage"` statement with LuxRender's defaults ([`params`]).

pub mod buffer;
pub mod error;
pub mod params;

pub use buffer::{check_size, BufferType, Film, MAX_AXIS, MAX_PIXELS, PIXEL_VALUES};
pub use error::FilmError;
pub use params::{Channels, ExrCompression, FilmParams, ImageOutput, ZBufNorm};
