//! Image files for `imagemap` and `normalmap`: PNG, JPEG, TGA and HDR through the `image`
//! crate, OpenEXR through the `exr` crate, as RGBA f32 texels (row 0 at the top of the image).
//! 8-bit images are divided by 255 (16-bit by 65535), as LuxRender stores them; the textures
//! apply `gain` and `gamma` to the filtered value. Each file is loaded once per [`ImageCache`],
//! and each filtered form of it (see [`super::mipmap`]) built once.

use super::mipmap::{FilterType, MipMap, Wrap};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

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

    /// The image at `path`, loading it on first use.
    pub fn get(&mut self, path: &Path) -> Result<Arc<ImageData>, String> {
        if let Some(img) = self.images.get(path) {
            return Ok(img.clone());
        }
        let img = load(path)?;
        tracing::info!(
            "loaded image {} ({}x{})",
            path.display(),
            img.width,
            img.height
        );
        let img = Arc::new(img);
        self.images.insert(path.to_path_buf(), img.clone());
        Ok(img)
    }

    /// The image at `path` prepared for lookups with `filter` and `wrap` (without its
    /// `discard` finest pyramid levels), built once.
    pub fn mipmap(
        &mut self,
        path: &Path,
        filter: FilterType,
        wrap: Wrap,
        max_anisotropy: f32,
        discard: usize,
    ) -> Result<Arc<MipMap>, String> {
        let key = (
            path.to_path_buf(),
            filter,
            wrap,
            max_anisotropy.to_bits(),
            discard,
        );
        if let Some(m) = self.maps.get(&key) {
            return Ok(m.clone());
        }
        let img = self.get(path)?;
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

/// Decodes an image file as linear RGB texels (alpha dropped), row 0 at the top: what lights,
/// image comparison and benchmarks read. Errors name the file.
pub fn load_rgb(path: &Path) -> Result<(usize, usize, Vec<crate::spectrum::Rgb>), String> {
    let img = load(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let px = img
        .texels
        .iter()
        .map(|&[r, g, b, _]| crate::spectrum::Rgb::new(r, g, b))
        .collect();
    Ok((img.width, img.height, px))
}

/// Decodes an image file by its extension.
pub fn load(path: &Path) -> Result<ImageData, String> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    let img = if ext == "exr" {
        load_exr(path)?
    } else {
        load_other(path)?
    };
    if img.width == 0 || img.height == 0 {
        return Err("image has no pixels".into());
    }
    Ok(img)
}

fn load_exr(path: &Path) -> Result<ImageData, String> {
    use exr::prelude::*;
    let image = read_first_rgba_layer_from_file(
        path,
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
    .map_err(|e| e.to_string())?;
    let size = image.layer_data.size;
    let (_, texels) = image.layer_data.channel_data.pixels;
    Ok(ImageData {
        width: size.width(),
        height: size.height(),
        texels,
    })
}

fn load_other(path: &Path) -> Result<ImageData, String> {
    let img = image::ImageReader::open(path)
        .map_err(|e| e.to_string())?
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
