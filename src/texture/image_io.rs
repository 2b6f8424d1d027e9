//! Image files for `imagemap` and `normalmap`: PNG, JPEG, TGA and HDR through the `image`
//! crate, OpenEXR through the `exr` crate, as RGBA f32 texels (row 0 at the top of the image).
//! 8-bit images are divided by 255 (16-bit by 65535), as LuxRender stores them; the textures
//! apply `gain` and `gamma` to the filtered value. Each file is loaded once per [`ImageCache`],
//! and each filtered form of it (see [`super::mipmap`]) built once.
//!
//! Scene images are read through the scene's [`SceneFiles`] (confined to the bundle on a
//! farm) and decoded from memory; the decoders' allocations are bounded ([`MAX_TEXELS`]).

use super::mipmap::{FilterType, MipMap, Wrap};
use crate::fileio::SceneFiles;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Most texels an image may decode to (2 GiB of RGBA f32): a small file declaring a huge
/// image is refused before the texels are allocated.
pub const MAX_TEXELS: u64 = 1 << 27;

/// Decoded texels.
#[derive(Debug)]
pub struct ImageData {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<[f32; 4]>,
}

impl ImageData {
    /// Texel (x, y) with y = 0 the top row; callers keep indices in range.
    pub fn texel(&self, x: usize, y: usize) -> [f32; 4] {
        self.texels
            .get(y * self.width + x)
            .copied()
            .unwrap_or([0.0; 4])
    }
}

/// Loaded images and the lookup structures built from them.
#[derive(Default)]
pub struct ImageCache {
    images: HashMap<PathBuf, Arc<ImageData>>,
    maps: HashMap<(PathBuf, FilterType, Wrap, u32, usize), Arc<MipMap>>,
}

impl ImageCache {
    /// Number of distinct image files loaded.
    pub fn len(&self) -> usize {
        self.images.len()
    }

    pub fn is_empty(&self) -> bool {
        self.images.is_empty()
    }

    /// The image the scene names `name` (opened through `files`), loading it on first use.
    /// Errors give the reason (the caller names the file).
    pub fn get(&mut self, files: &SceneFiles, name: &str) -> Result<Arc<ImageData>, String> {
        let path = files.resolve(name).map_err(|e| e.reason())?;
        if let Some(img) = self.images.get(&path) {
            return Ok(img.clone());
        }
        let bytes = files.read(name).map_err(|e| e.reason())?;
        let img = decode(&bytes, name)?;
        tracing::info!("loaded image {name} ({}x{})", img.width, img.height);
        let img = Arc::new(img);
        self.images.insert(path, img.clone());
        Ok(img)
    }

    /// The image the scene names `name` prepared for lookups with `filter` and `wrap`
    /// (without its `discard` finest pyramid levels), built once.
    #[allow(clippy::too_many_arguments)]
    pub fn mipmap(
        &mut self,
        files: &SceneFiles,
        name: &str,
        filter: FilterType,
        wrap: Wrap,
        max_anisotropy: f32,
        discard: usize,
    ) -> Result<Arc<MipMap>, String> {
        let path = files.resolve(name).map_err(|e| e.reason())?;
        let key = (path, filter, wrap, max_anisotropy.to_bits(), discard);
        if let Some(m) = self.maps.get(&key) {
            return Ok(m.clone());
        }
        let img = self.get(files, name)?;
        let mut m = MipMap::new(
            img.width,
            img.height,
            &img.texels,
            filter,
            wrap,
            max_anisotropy,
        );
        m.discard_levels(discard);
        let m = Arc::new(m);
        self.maps.insert(key, m.clone());
        Ok(m)
    }
}

/// An image as linear RGB texels (alpha dropped), row 0 at the top.
pub type RgbImage = (usize, usize, Vec<crate::spectrum::Rgb>);

fn to_rgb(img: ImageData) -> RgbImage {
    let px = img
        .texels
        .iter()
        .map(|&[r, g, b, _]| crate::spectrum::Rgb::new(r, g, b))
        .collect();
    (img.width, img.height, px)
}

/// Decodes an image file as linear RGB texels (alpha dropped), row 0 at the top: what image
/// comparison and benchmarks read (local files of the user). Errors name the file.
pub fn load_rgb(path: &Path) -> Result<RgbImage, String> {
    let img = load(path).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(to_rgb(img))
}

/// The image a scene names `name` (an environment map), opened through the scene's `files`,
/// as linear RGB texels. Errors name the file as the scene wrote it.
pub fn load_scene_rgb(files: &SceneFiles, name: &str) -> Result<RgbImage, String> {
    let bytes = files.read(name).map_err(|e| e.to_string())?;
    let img = decode(&bytes, name).map_err(|e| format!("\"{name}\": {e}"))?;
    Ok(to_rgb(img))
}

/// Decodes an image file by its extension.
pub fn load(path: &Path) -> Result<ImageData, String> {
    let bytes = std::fs::read(path).map_err(|e| e.to_string())?;
    decode(&bytes, &path.to_string_lossy())
}

/// Decodes image bytes; `name`'s extension tells EXR from the formats `image` guesses.
pub fn decode(bytes: &[u8], name: &str) -> Result<ImageData, String> {
    let ext = Path::new(name)
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    let img = if ext == "exr" {
        decode_exr(bytes)?
    } else {
        decode_other(bytes)?
    };
    if img.width == 0 || img.height == 0 {
        return Err("image has no pixels".into());
    }
    Ok(img)
}

/// Refuses a declared size above [`MAX_TEXELS`].
fn check_texels(width: usize, height: usize) -> Result<(), String> {
    let texels = (width as u64).saturating_mul(height as u64);
    if texels > MAX_TEXELS {
        return Err(format!(
            "a {width}x{height} image is larger than the limit of {MAX_TEXELS} texels"
        ));
    }
    Ok(())
}

fn decode_exr(bytes: &[u8]) -> Result<ImageData, String> {
    use exr::prelude::*;
    // The header first: its size is checked before any texel is allocated.
    let meta = exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(bytes), false)
        .map_err(|e| e.to_string())?;
    for header in &meta.headers {
        let size = header.layer_size;
        check_texels(size.width(), size.height())?;
    }
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |res: Vec2<usize>, _channels: &RgbaChannels| {
                (res.width(), vec![[0.0f32; 4]; res.width() * res.height()])
            },
            |storage: &mut (usize, Vec<[f32; 4]>),
             pos: Vec2<usize>,
             (r, g, b, a): (f32, f32, f32, f32)| {
                let w = storage.0;
                if let Some(t) = storage.1.get_mut(pos.y() * w + pos.x()) {
                    *t = [r, g, b, a];
                }
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes))
        .map_err(|e| e.to_string())?;
    let size = image.layer_data.size;
    let (_, texels) = image.layer_data.channel_data.pixels;
    Ok(ImageData {
        width: size.width(),
        height: size.height(),
        texels,
    })
}

fn decode_other(bytes: &[u8]) -> Result<ImageData, String> {
    let reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| e.to_string())?;
    let (w, h) = reader.into_dimensions().map_err(|e| e.to_string())?;
    check_texels(w as usize, h as usize)?;
    let img = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| e.to_string())?
        .decode()
        .map_err(|e| e.to_string())?;
    let rgba = img.to_rgba32f();
    let (w, h) = (rgba.width() as usize, rgba.height() as usize);
    let texels = rgba.pixels().map(|p| p.0).collect();
    Ok(ImageData {
        width: w,
        height: h,
        texels,
    })
}
