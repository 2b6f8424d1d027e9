//! Glare: streaks from the brightest parts of the image, as LuxRender 1.x's imaging pipeline
//! draws them.
//!
//! Pixels whose Y (the middle component of the XYZ pixel) is below `glare_threshold` times the
//! image's largest Y are blacked out. For each of `glare_blades` directions, evenly spaced over
//! a full turn, the remaining bright image is rotated into a square of the longer side,
//! blurred along rows with a Gaussian of standard deviation `glare_radius` times the longer
//! side (kernel exp(-x²/σ²), normalised, cut where it falls below 1e-12 or at 4σ), and rotated
//! back; the blades' mean, times `glare_amount`, is added to the image.
//!
//! LuxRender 1.x also has a diffraction glare from pupil and eyelash images (the film's
//! `GlareMap` with `glarepupilfilename`/`glarelashesfilename`). A scene cannot turn it on:
//! the film starts with `GlareMap` false and only LuxRender's GUI sets it, so a scene's
//! glare is always this blade glare, here as there. luxfarm has no GUI toggle and does not
//! compute the diffraction glare (an FLM saved from LuxRender's GUI with it on is
//! tonemapped with the blade glare).

use super::{bilinear, Pixels};
use rayon::prelude::*;

/// Glare settings.
#[derive(Clone, Copy, Debug)]
pub struct Glare {
    pub amount: f32,
    pub radius: f32,
    pub blades: u32,
    pub threshold: f32,
}

/// Largest blade count honoured (each blade costs two rotations and a blur of the image).
pub const MAX_BLADES: u32 = 64;

/// Adds glare in place. Does nothing for a non-positive amount or radius, or no blades.
pub fn apply(img: Pixels<'_>, g: Glare) {
    let (w, h) = (img.width, img.height);
    let blades = g.blades.min(MAX_BLADES);
    let positive = |v: f32| v > 0.0;
    if !positive(g.amount) || !positive(g.radius) || blades == 0 || w == 0 || h == 0 {
        return;
    }
    if img.data.len() != w * h {
        return;
    }
    let max_y = img.data.iter().map(|p| p[1]).fold(0.0f32, f32::max);
    let cut = max_y * g.threshold;
    let bright: Vec<[f32; 3]> = img
        .data
        .iter()
        .map(|&p| if p[1] < cut { [0.0; 3] } else { p })
        .collect();
    let m = w.max(h);
    let sigma = m as f32 * g.radius;
    let kernel = gaussian(sigma);
    let mut glare = vec![[0.0f32; 3]; w * h];
    let (ox, oy) = ((m - w) / 2, (m - h) / 2);
    for b in 0..blades {
        let angle = 2.0 * std::f32::consts::PI * b as f32 / blades as f32;
        let rotated = rotate(&bright, w, h, m, angle);
        let blurred = blur_rows(&rotated, m, &kernel);
        let back = rotate(&blurred, m, m, m, -angle);
        for y in 0..h {
            for x in 0..w {
                let s = back[(y + oy) * m + x + ox];
                let o = &mut glare[y * w + x];
                (0..3).for_each(|k| o[k] += s[k]);
            }
        }
    }
    let scale = g.amount / blades as f32;
    for (p, q) in img.data.iter_mut().zip(&glare) {
        (0..3).for_each(|k| p[k] += scale * q[k]);
    }
}

/// One side of a normalised Gaussian kernel exp(-x²/σ²), x = 0..=radius.
fn gaussian(sigma: f32) -> Vec<f32> {
    let reach = (sigma * 4.0).ceil().clamp(0.0, 1e5) as usize;
    let mut k = vec![1.0f32];
    for x in 1..=reach {
        let v = (-((x * x) as f32) / (sigma * sigma)).exp();
        if v < 1e-12 {
            break;
        }
        k.push(v);
    }
    let sum: f32 = k[0] + 2.0 * k[1..].iter().sum::<f32>();
    k.iter().map(|v| v / sum).collect()
}

/// The image (w x h) rotated by `angle` about its centre into an m x m square, sampled
/// bilinearly (border pixels extend outward).
fn rotate(src: &[[f32; 3]], w: usize, h: usize, m: usize, angle: f32) -> Vec<[f32; 3]> {
    let (s, c) = (-angle).sin_cos();
    let (cx, cy) = (w as f32 * 0.5, h as f32 * 0.5);
    let half = m as f32 * 0.5;
    (0..m * m)
        .into_par_iter()
        .map(|i| {
            let (px, py) = ((i % m) as f32 - half, (i / m) as f32 - half);
            let rx = px * c - py * s + cx;
            let ry = px * s + py * c + cy;
            bilinear(src, w, h, rx, ry)
        })
        .collect()
}

/// Blurs each row of an m x m image with a symmetric kernel (one side given).
fn blur_rows(src: &[[f32; 3]], m: usize, kernel: &[f32]) -> Vec<[f32; 3]> {
    let r = kernel.len().saturating_sub(1);
    (0..m * m)
        .into_par_iter()
        .map(|i| {
            let (x, row) = (i % m, i - i % m);
            let mut o = [0.0f32; 3];
            for j in x.saturating_sub(r)..=(x + r).min(m - 1) {
                let wt = kernel[x.abs_diff(j)];
                let p = src[row + j];
                (0..3).for_each(|k| o[k] += wt * p[k]);
            }
            o
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gaussian_is_normalised() {
        let k = gaussian(2.0);
        assert_eq!(k.len(), 9);
        let sum = k[0] + 2.0 * k[1..].iter().sum::<f32>();
        assert!((sum - 1.0).abs() < 1e-6);
        assert!((k[1] / k[0] - (-0.25f32).exp()).abs() < 1e-6);
    }

    #[test]
    fn one_blade_streaks_along_the_row_only() {
        let (w, h) = (21, 21);
        let mut img = vec![[0.0f32; 3]; w * h];
        img[10 * w + 10] = [1.0, 1.0, 1.0];
        img[3 * w + 3] = [0.1, 0.1, 0.1]; // below the threshold: no glare from it
        let g = Glare {
            amount: 1.0,
            radius: 0.1,
            blades: 1,
            threshold: 0.5,
        };
        apply(
            Pixels {
                width: w,
                height: h,
                data: &mut img,
            },
            g,
        );
        // row 10 is the source blurred (σ = 2.1 pixels), other rows get nothing
        let k = gaussian(2.1);
        assert!(
            (img[10 * w + 12][1] - k[2]).abs() < 1e-5,
            "{:?}",
            img[10 * w + 12]
        );
        assert!((img[10 * w + 10][1] - (1.0 + k[0])).abs() < 1e-5);
        assert!(img[12 * w + 10][1].abs() < 1e-6);
        assert!((img[3 * w + 3][1] - 0.1).abs() < 1e-6);
    }

    #[test]
    fn two_blades_average() {
        let (w, h) = (20, 20);
        let mut img = vec![[0.0f32; 3]; w * h];
        img[10 * w + 10] = [2.0; 3];
        let mut one = img.clone();
        let g = Glare {
            amount: 0.5,
            radius: 0.05,
            blades: 2,
            threshold: 0.0,
        };
        apply(
            Pixels {
                width: w,
                height: h,
                data: &mut img,
            },
            g,
        );
        apply(
            Pixels {
                width: w,
                height: h,
                data: &mut one,
            },
            Glare { blades: 1, ..g },
        );
        // a half turn gives the same horizontal streak, so the mean equals one blade's
        for (a, b) in img.iter().zip(&one) {
            assert!((a[0] - b[0]).abs() < 1e-4, "{a:?} {b:?}");
        }
    }
}
