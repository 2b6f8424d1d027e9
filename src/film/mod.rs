//! Film buffers as LuxRender's fleximage keeps them, FLM v0 read/write, merging, comparison and
//! convergence.
//!
//! - [`Film`]: f64 sums per light group and pixel, f64 sample counts ([`buffer`]).
//! - [`FilmParams`]: the `Film "fleximage"` statement with LuxRender's defaults ([`params`];
//!   its image outputs' settings in [`image_output`]).

pub mod buffer;
pub mod compare;
pub mod convergence;
pub mod error;
pub mod image_output;
pub mod outlier;
pub mod output;
pub mod params;

pub use buffer::{check_size, BufferType, Film, MAX_AXIS, MAX_PIXELS, PIXEL_VALUES};
pub use compare::{compare, Comparison};
pub use convergence::ConvergenceTest;
pub use error::FilmError;
pub use image_output::{Channels, ExrCompression, ImageOutput, ZBufNorm};
pub use outlier::OutlierRejector;
pub use params::FilmParams;
pub mod flm;
pub mod flm_header;

pub use flm::{
    merge_flm, merge_flm_bytes, read_flm, read_flm_file, write_flm, write_flm_file, FlmDelta,
};
pub use flm_header::{FlmHeader, FlmParam, FlmValue};
