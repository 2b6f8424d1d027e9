//! Film buffers as LuxRender's fleximage keeps them, the Film statement's parameters, FLM v0
//! read/write/merge and film comparison: the first stage of the image back end.
//!
//! - [`Film`]: f64 sums per light group and pixel, f64 sample counts ([`buffer`]).
//! - [`FilmParams`]: the `Film "fleximage"` statement with LuxRender's defaults ([`params`]);
//!   its imaging settings ([`imaging`]: tonemapping, colour space, light groups; read from the
//!   statement by `imaging_params.rs`) and its image outputs' settings ([`image_output`]) are
//!   plain data here.
//! - [`response`]: the `cameraresponse` curves, CRF files or LuxRender's built-in film
//!   presets ([`crf_presets`]).
//! - [`flm`], [`flm_header`]: LuxRender's film file; [`compare`](mod@compare): luxcomp's metrics;
//!   [`outlier`]: k-nearest outlier rejection of samples; [`variance`]: the luminance spread
//!   per pixel that noise-aware sampling builds its map from; [`zbuffer`]: depths.
//!
//! The back end runs one way: `film` -> `tonemap` (film sums to RGB) -> `imageio` (pixel
//! buffers to PNG/TGA/EXR bytes) -> `output` (the files a Film asks for); `halt` decides when
//! a render stops. This module imports none of those modules: the settings they interpret are
//! defined here and read there.

pub mod buffer;
pub mod compare;
pub mod crf_presets;
pub mod effects;
pub mod error;
pub mod image_output;
pub mod imaging;
mod imaging_params;
pub mod outlier;
pub mod params;
pub mod response;
pub mod variance;
pub mod zbuffer;

pub use buffer::{check_size, BufferType, Film, MAX_AXIS, MAX_PIXELS, PIXEL_VALUES};
pub use compare::{block_bias, compare, BlockBias, Comparison};
pub use error::FilmError;
pub use image_output::{Channels, ExrCompression, ImageOutput, ZBufNorm};
pub use imaging::{
    ClampMethod, ColorSpaceParams, Effects, Flavour, GroupParams, Kernel, TonemapParams,
};
pub use outlier::OutlierRejector;
pub use params::FilmParams;
pub use variance::VarianceBuffer;
pub use zbuffer::ZBuffer;
pub mod flm;
pub mod flm_header;

pub use flm::{
    merge_flm, merge_flm_bytes, read_flm, read_flm_file, write_flm, write_flm_file, FlmDelta,
};
pub use flm_header::{FlmHeader, FlmParam, FlmValue};
