//! The image files the texture cases read, generated into the output directory before the
//! cases run, so both renderers read the same bytes:
//!
//! - [`COLOUR`]: 64×64 8-bit RGB, red rising to the right, green rising downwards, a blue disc
//!   in the lower left (no symmetry, so a flipped or mirrored lookup shows);
//! - [`HEIGHT`]: 64×64 16-bit grey height field, a smooth pattern of bumps (`bump_height`);
//! - [`NORMALS`]: 64×64 8-bit RGB tangent-space normal map of the same height field, encoded
//!   as (n + 1) / 2 per component, green the slope towards the image's top.

use anyhow::Context;
use std::f32::consts::TAU;
use std::path::Path;

pub const COLOUR: &str = "colour.png";
pub const HEIGHT: &str = "height.png";
pub const NORMALS: &str = "normals.png";
const SIZE: u32 = 64;

/// The height field in [0, 1] at pixel (x, y) (y down), periodic over the image.
pub fn bump_height(x: f32, y: f32) -> f32 {
    let s = SIZE as f32;
    0.5 + 0.25 * (TAU * 2.0 * x / s).sin() * (TAU * 3.0 * y / s).cos()
        + 0.2 * (TAU * (x + 2.0 * y) / s).sin()
}

/// The unit normal of the height field scaled by `k` at pixel (x, y), in the image's frame
/// (x right, y up the image, z out of it).
fn normal(x: f32, y: f32, k: f32) -> [f32; 3] {
    let e = 0.5;
    let dx = (bump_height(x + e, y) - bump_height(x - e, y)) / (2.0 * e);
    // The image's y runs down; "up the image" is −y.
    let dy = -(bump_height(x, y + e) - bump_height(x, y - e)) / (2.0 * e);
    let n = [-k * dx, -k * dy, 1.0];
    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    n.map(|c| c / l)
}

fn to8(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// Writes the three images into `dir`.
pub fn write_all(dir: &Path) -> anyhow::Result<()> {
    let colour = image::RgbImage::from_fn(SIZE, SIZE, |x, y| {
        let (fx, fy) = (x as f32, y as f32);
        let d = ((fx - 18.0).powi(2) + (fy - 44.0).powi(2)).sqrt();
        let b = if d < 10.0 { 0.9 } else { 0.15 };
        image::Rgb([to8(fx / 63.0), to8(fy / 63.0), to8(b)])
    });
    let path = dir.join(COLOUR);
    colour
        .save(&path)
        .with_context(|| format!("writing {}", path.display()))?;
    let height = image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_fn(SIZE, SIZE, |x, y| {
        let h = bump_height(x as f32, y as f32).clamp(0.0, 1.0);
        image::Luma([(h * 65535.0).round() as u16])
    });
    let path = dir.join(HEIGHT);
    height
        .save(&path)
        .with_context(|| format!("writing {}", path.display()))?;
    let normals = image::RgbImage::from_fn(SIZE, SIZE, |x, y| {
        let n = normal(x as f32, y as f32, 4.0);
        image::Rgb(n.map(|c| to8(0.5 * (c + 1.0))))
    });
    let path = dir.join(NORMALS);
    normals
        .save(&path)
        .with_context(|| format!("writing {}", path.display()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn height_stays_in_the_unit_range_and_normals_are_unit() {
        for y in 0..SIZE {
            for x in 0..SIZE {
                let h = bump_height(x as f32, y as f32);
                assert!((0.0..=1.0).contains(&h), "{h}");
                let n = normal(x as f32, y as f32, 4.0);
                let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                assert!((l - 1.0).abs() < 1e-5 && n[2] > 0.0);
            }
        }
    }

    #[test]
    fn the_images_are_written() {
        let d = tempfile::tempdir().unwrap();
        write_all(d.path()).unwrap();
        for f in [COLOUR, HEIGHT, NORMALS] {
            let img = image::open(d.path().join(f)).unwrap();
            assert_eq!((img.width(), img.height()), (SIZE, SIZE));
        }
    }
}
