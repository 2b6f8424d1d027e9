//! Image outputs: PNG (8/16 bit), TGA and OpenEXR (half/float), with LuxRender's channel sets
//! (Y, YA, RGB, RGBA) and quantisation. Files are written atomically (temporary + rename).

pub mod exr;
pub mod ldr;

pub use self::exr::{write_exr, ExrImage};
pub use ldr::{write_png, write_tga, LdrImage};
