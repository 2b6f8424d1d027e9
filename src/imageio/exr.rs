//! OpenEXR encoder: linear pixels (tonemapped or not, the caller decides), channel sets
//! Y/YA/RGB/RGBA as half or float, an optional Z channel (always float), and the
//! compressions LuxRender offers.

use super::{ChannelSet, ImageError};
use crate::atomic_write::write_atomic;
use ::exr::prelude::*;
use std::io::{Seek, Write};
use std::path::Path;

/// Linear pixels for an EXR file, row by row, top row first.
pub struct ExrImage<'a> {
    pub width: u32,
    pub height: u32,
    pub rgb: &'a [[f32; 3]],
    /// Linear luminance per pixel, for Y and YA channel sets.
    pub gray: &'a [f32],
    pub alpha: &'a [f32],
    pub z: Option<&'a [f32]>,
}

/// OpenEXR compression.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExrCompression {
    Rle,
    Piz,
    Zip,
    Pxr24,
    None,
}

/// A value as a half float: values beyond the half range (65504; an untonemapped film in
/// LuxRender's units reaches it) saturate instead of becoming infinite, and NaN is written 0.
fn to_half(v: f32) -> f16 {
    if v.is_nan() {
        f16::ZERO
    } else {
        f16::from_f32(v.clamp(f16::MIN.to_f32(), f16::MAX.to_f32()))
    }
}

fn channel(name: &str, v: Vec<f32>, half: bool) -> AnyChannel<FlatSamples> {
    let samples = if half {
        FlatSamples::F16(v.into_iter().map(to_half).collect())
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

/// Every channel the set asks for must hold one value per pixel.
fn check_size(img: &ExrImage, ch: ChannelSet) -> std::result::Result<(), ImageError> {
    let n = img.rgb.len();
    super::check_pixels(img.width, img.height, n).map_err(ImageError::Codec)?;
    let short =
        |name: &str, len: usize| ImageError::Codec(format!("{len} {name} values for {n} pixels"));
    if ch.is_gray() && img.gray.len() != n {
        return Err(short("gray", img.gray.len()));
    }
    if ch.has_alpha() && img.alpha.len() != n {
        return Err(short("alpha", img.alpha.len()));
    }
    match img.z {
        Some(z) if z.len() != n => Err(short("depth", z.len())),
        _ => Ok(()),
    }
}

/// Encodes an EXR with the channel set (half or float samples); Z is always float.
pub fn encode_exr(
    w: impl Write + Seek,
    img: &ExrImage,
    ch: ChannelSet,
    half: bool,
    comp: ExrCompression,
) -> std::result::Result<(), ImageError> {
    check_size(img, ch)?;
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
    Image::from_layer(layer)
        .write()
        .to_buffered(w)
        .map_err(|e| ImageError::Codec(e.to_string()))
}

/// Writes an EXR file atomically (see [`encode_exr`]).
pub fn write_exr(
    path: &Path,
    img: &ExrImage,
    ch: ChannelSet,
    half: bool,
    comp: ExrCompression,
) -> std::result::Result<(), ImageError> {
    write_atomic(path, |w| {
        encode_exr(w, img, ch, half, comp).map_err(|e| e.at(path))
    })
}

#[cfg(test)]
mod tests {

    #[test]
    fn half_samples_saturate_instead_of_overflowing() {
        assert_eq!(to_half(1.0e6), f16::MAX);
        assert_eq!(to_half(-1.0e6), f16::MIN);
        assert_eq!(to_half(f32::INFINITY), f16::MAX);
        assert_eq!(to_half(f32::NAN), f16::ZERO);
        assert_eq!(to_half(0.5), f16::from_f32(0.5));
    }

    use super::*;

    #[test]
    fn channels_round_trip_and_sizes_are_checked() {
        let rgb: Vec<[f32; 3]> = (0..6).map(|i| [i as f32, 0.25, 2.0]).collect();
        let alpha = vec![0.5f32; 6];
        let z = vec![3.0f32; 6];
        let img = ExrImage {
            width: 3,
            height: 2,
            rgb: &rgb,
            gray: &[],
            alpha: &alpha,
            z: Some(&z),
        };
        let mut out = std::io::Cursor::new(Vec::new());
        encode_exr(&mut out, &img, ChannelSet::Rgba, false, ExrCompression::Zip).unwrap();
        let back = ::exr::prelude::read()
            .no_deep_data()
            .largest_resolution_level()
            .all_channels()
            .all_layers()
            .all_attributes()
            .from_buffered(std::io::Cursor::new(out.into_inner()))
            .unwrap();
        let names: Vec<String> = back.layer_data[0]
            .channel_data
            .list
            .iter()
            .map(|c| c.name.to_string())
            .collect();
        assert_eq!(names, ["A", "B", "G", "R", "Z"]);
        let r = &back.layer_data[0].channel_data.list[3].sample_data;
        assert_eq!(r.value_by_flat_index(5).to_f32(), 5.0);
        // a Y image without gray values is refused, not a panic
        let mut out = std::io::Cursor::new(Vec::new());
        assert!(encode_exr(&mut out, &img, ChannelSet::Y, true, ExrCompression::Piz).is_err());
    }
}
