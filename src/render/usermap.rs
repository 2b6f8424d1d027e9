//! The user sampling map as an image: LuxRender's GUI lets the user paint a per-pixel weight
//! map over the film (`luxSetUserSamplingMap`); luxfarm takes it as an image file of the film
//! buffer's size (the crop window's, when there is one) whose pixels' luminance are the
//! weights. The local CLI reads it from a file (`luxfarm render --sampling-map`), the master
//! from a REST upload; both end in the same [`SamplingMap`].
//!
//! ```text
//! image bytes --probe_size (header only: the size is checked before any pixel is decoded)-->
//!   size == film buffer? --crate::texture::image_io::decode (PNG, JPEG, TGA, HDR, EXR)-->
//!   RGBA texels --luminance Y (CIE, linear values as stored)--> weights
//!   --SamplingMap::from_weights (finite, >= 0, not all zero)--> user map
//! ```
//!
//! The values are used as stored: 8-bit images divided by 255 (no sRGB decoding, as LuxRender
//! reads images), float images (EXR, HDR) as they are. Alpha is ignored.

use crate::sampler::map::{MapError, SamplingMap};
use crate::spectrum::{rgb_to_xyz, Rgb};
use crate::texture::image_io;

/// Why an image cannot be a user sampling map.
#[derive(Debug, thiserror::Error)]
pub enum UserMapError {
    /// Not an image this project reads, or a corrupt one.
    #[error("sampling map image: {0}")]
    Decode(String),
    /// The image is not the film buffer's size.
    #[error(
        "sampling map image is {got_w}x{got_h}, the film is {want_w}x{want_h} (its crop \
         window's size): the map needs one pixel per film pixel"
    )]
    Size {
        got_w: u64,
        got_h: u64,
        want_w: u32,
        want_h: u32,
    },
    /// A weight is negative, NaN or infinite, or all are zero.
    #[error(transparent)]
    Map(#[from] MapError),
}

/// The four bytes OpenEXR files begin with.
const EXR_MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];

/// Whether `bytes` hold an OpenEXR file.
fn is_exr(bytes: &[u8]) -> bool {
    bytes.get(..4) == Some(&EXR_MAGIC[..])
}

/// The size an image declares in its header (nothing decoded).
pub fn probe_size(bytes: &[u8]) -> Result<(u64, u64), UserMapError> {
    if is_exr(bytes) {
        let meta = exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(bytes), false)
            .map_err(|e| UserMapError::Decode(e.to_string()))?;
        let header = meta
            .headers
            .first()
            .ok_or_else(|| UserMapError::Decode("OpenEXR file without a layer".into()))?;
        let size = header.layer_size;
        return Ok((size.width() as u64, size.height() as u64));
    }
    let reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| UserMapError::Decode(e.to_string()))?;
    if reader.format().is_none() {
        return Err(UserMapError::Decode(
            "not an image (PNG, JPEG, TGA, HDR or OpenEXR expected)".into(),
        ));
    }
    let (w, h) = reader
        .into_dimensions()
        .map_err(|e| UserMapError::Decode(e.to_string()))?;
    Ok((u64::from(w), u64::from(h)))
}

/// The per-pixel weights of an image (its luminance) for a `want_w` × `want_h` film buffer.
/// The size is checked from the header before the pixels are decoded.
pub fn weights_from_image(
    bytes: &[u8],
    want_w: u32,
    want_h: u32,
) -> Result<Vec<f32>, UserMapError> {
    let (w, h) = probe_size(bytes)?;
    if (w, h) != (u64::from(want_w), u64::from(want_h)) {
        return Err(UserMapError::Size {
            got_w: w,
            got_h: h,
            want_w,
            want_h,
        });
    }
    // `decode` tells EXR from the other formats by the name's extension.
    let name = if is_exr(bytes) { "map.exr" } else { "map" };
    let img = image_io::decode(bytes, name).map_err(UserMapError::Decode)?;
    if (img.width as u64, img.height as u64) != (w, h) {
        return Err(UserMapError::Decode(format!(
            "the image decoded to {}x{}, its header says {w}x{h}",
            img.width, img.height
        )));
    }
    Ok(img
        .texels
        .iter()
        .map(|&[r, g, b, _]| rgb_to_xyz(Rgb::new(r, g, b))[1])
        .collect())
}

/// The user sampling map of an image for a `w` × `h` film buffer.
pub fn map_from_image(bytes: &[u8], w: u32, h: u32) -> Result<SamplingMap, UserMapError> {
    let weights = weights_from_image(bytes, w, h)?;
    Ok(SamplingMap::from_weights(&weights, w, h)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(w: u32, h: u32, f: impl Fn(u32, u32) -> u8) -> Vec<u8> {
        let img = image::GrayImage::from_fn(w, h, |x, y| image::Luma([f(x, y)]));
        let mut out = std::io::Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Png).unwrap();
        out.into_inner()
    }

    fn exr(w: usize, h: usize, v: impl Fn(usize, usize) -> f32 + Sync) -> Vec<u8> {
        use exr::prelude::*;
        let img = Image::from_channels(
            (w, h),
            SpecificChannels::rgb(|p: Vec2<usize>| {
                let x = v(p.x(), p.y());
                (x, x, x)
            }),
        );
        let mut out = std::io::Cursor::new(Vec::new());
        img.write().to_buffered(&mut out).unwrap();
        out.into_inner()
    }

    #[test]
    fn a_gray_png_gives_its_values_as_weights() {
        let bytes = png(4, 2, |x, _| if x < 2 { 225 } else { 25 });
        let w = weights_from_image(&bytes, 4, 2).unwrap();
        assert!((w[0] / w[3] - 9.0).abs() < 1e-4, "{w:?}");
        let m = map_from_image(&bytes, 4, 2).unwrap();
        assert!((m.density(1, 1) / m.density(2, 1) - 9.0).abs() < 1e-4);
    }

    #[test]
    fn wrong_sizes_name_both_sizes() {
        let e = map_from_image(&png(5, 2, |_, _| 9), 4, 2).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("5x2") && msg.contains("4x2"), "{msg}");
        assert!(matches!(e, UserMapError::Size { got_w: 5, .. }));
    }

    #[test]
    fn exr_weights_are_checked() {
        let bytes = exr(3, 2, |x, y| (x + y) as f32);
        assert!(map_from_image(&bytes, 3, 2).is_ok());
        let neg = exr(3, 2, |x, y| if (x, y) == (2, 1) { -1.0 } else { 1.0 });
        let e = map_from_image(&neg, 3, 2).unwrap_err();
        assert!(e.to_string().contains("(2, 1)"), "{e}");
        let nan = exr(3, 2, |x, _| if x == 1 { f32::NAN } else { 1.0 });
        assert!(matches!(
            map_from_image(&nan, 3, 2),
            Err(UserMapError::Map(MapError::Pixel { x: 1, y: 0, .. }))
        ));
        let zero = exr(3, 2, |_, _| 0.0);
        assert!(matches!(
            map_from_image(&zero, 3, 2),
            Err(UserMapError::Map(MapError::AllZero))
        ));
        assert!(matches!(
            map_from_image(&exr(2, 2, |_, _| 1.0), 3, 2),
            Err(UserMapError::Size { .. })
        ));
    }

    #[test]
    fn garbage_is_a_decode_error() {
        for bytes in [&b""[..], b"not an image at all", &EXR_MAGIC[..]] {
            assert!(matches!(
                map_from_image(bytes, 2, 2),
                Err(UserMapError::Decode(_))
            ));
        }
        // a PNG whose header is cut after its size still fails cleanly
        let mut bytes = png(2, 2, |_, _| 1);
        bytes.truncate(40);
        assert!(map_from_image(&bytes, 2, 2).is_err());
    }
}
