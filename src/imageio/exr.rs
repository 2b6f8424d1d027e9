//! OpenEXR output: linear RGB (tonemapped or not), channel sets Y/YA/RGB/RGBA, half or float,
//! optional Z channel, LuxRender's compression choices.

use crate::film::flm::write_atomic;
use crate::film::{Channels, ExrCompression, FilmError};
use ::exr::prelude::*;
use std::path::Path;

/// Linear pixels for an EXR file.
pub struct ExrImage<'a> {
    pub width: u32,
    pub height: u32,
    pub rgb: &'a [[f32; 3]],
    /// Linear luminance per pixel, for Y and YA channel sets.
    pub gray: &'a [f32],
    pub alpha: &'a [f32],
    pub z: Option<&'a [f32]>,
}

fn channel(name: &str, v: Vec<f32>, half: bool) -> AnyChannel<FlatSamples> {
    let samples = if half {
        FlatSamples::F16(v.into_iter().map(f16::from_f32).collect())
    } else {
        FlatSamples::F32(v)
    };
    AnyChannel::new(name, samples)
}

fn compression(c: ExrCompression) -> Compression {
    match c {
        ExrCompression::Rle => Compression::RLE,
        ExrCompression::Piz => Compression::PIZ,
        ExrCompression::Zip => Compression::ZIP16,
        ExrCompression::Pxr24 => Compression::PXR24,
        ExrCompression::None => Compression::Uncompressed,
    }
}

/// Writes an EXR with the channel set; Z is always stored as 32-bit float.
pub fn write_exr(
    path: &Path,
    img: &ExrImage,
    ch: Channels,
    half: bool,
    comp: ExrCompression,
) -> std::result::Result<(), FilmError> {
    let pick = |i: usize| img.rgb.iter().map(|p| p[i]).collect::<Vec<f32>>();
    let mut list: Vec<AnyChannel<FlatSamples>> = Vec::new();
    if ch.is_gray() {
        list.push(channel("Y", img.gray.to_vec(), half));
    } else {
        list.push(channel("R", pick(0), half));
        list.push(channel("G", pick(1), half));
        list.push(channel("B", pick(2), half));
    }
    if ch.has_alpha() {
        list.push(channel("A", img.alpha.to_vec(), half));
    }
    if let Some(z) = img.z {
        list.push(channel("Z", z.to_vec(), false));
    }
    let size = (img.width as usize, img.height as usize);
    let encoding = Encoding {
        compression: compression(comp),
        ..Encoding::default()
    };
    let layer = Layer::new(
        size,
        LayerAttributes::default(),
        encoding,
        AnyChannels::sort(list.into()),
    );
    let image = Image::from_layer(layer);
    write_atomic(path, |w| {
        image.write().to_buffered(w).map_err(|e| FilmError::Image {
            path: path.to_path_buf(),
            message: e.to_string(),
        })
    })
}
