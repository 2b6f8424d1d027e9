//! Bloom: the image blended with a blurred copy of itself, as the last LuxRender 1.x releases
//! compute it (`ApplyImagingPipeline` in `core/film.cpp`).
//!
//! The support is `bloom_radius` times the image's longer side (in pixels, truncated); the
//! kernel's half width w is half of it. A pixel at offset d along a row or column (|d| < w)
//! weighs exp(-(z0·|d|/w)²/σ²), z0 = 3.8317 (the first zero of J1) and σ² = 1.698022698724
//! (LuxRender's Gaussian fit of the Airy disc out to z0); the pixel itself weighs 1. The blur
//! is separable: along rows, then along the columns of that result, each pass dividing by the
//! weights that fell inside the image. The result is `lerp(bloom_weight, pixel, blurred)`.
//!
//! LuxRender 1.6's code keeps one working value per column (rows pass) and per row (columns
//! pass) and never clears it, so each blurred pixel also carries its predecessor's blurred
//! value, divided once more by the weights: a geometric tail down the rows and across the
//! columns that brightens flat areas by w'/(w' − 1) per pass, w' the sum of the weights (+3 %
//! overall at 800 pixels, +48 % at 128). LuxCore, its successor, clears the value for every
//! pixel; luxfarm does the same, so the blur keeps the image's energy away from the borders.

use super::Pixels;
use rayon::prelude::*;

/// LuxRender's first zero of J1 and the Gaussian's σ² fitted to the Airy disc.
const Z0: f32 = 3.8317;
const SIGMA2: f32 = 1.698_022_7;

/// Half width in pixels of the bloom kernel for an image (0: no bloom).
pub fn half_width(radius: f32, width: usize, height: usize) -> usize {
    let support = radius * width.max(height) as f32;
    if support.is_finite() && support > 0.0 {
        (support as usize) / 2
    } else {
        0
    }
}

/// The kernel's weights at offsets 0..w (beyond, nothing).
pub fn weights(hw: usize) -> Vec<f32> {
    (0..hw)
        .map(|d| {
            let dist = Z0 * d as f32 / hw as f32;
            if d == 0 {
                1.0
            } else {
                (-dist * dist / SIGMA2).exp()
            }
        })
        .collect()
}

/// Applies bloom in place. Does nothing for a non-positive radius or weight, or a kernel
/// narrower than one pixel.
pub fn apply(img: Pixels<'_>, radius: f32, weight: f32) {
    let (w, h) = (img.width, img.height);
    let hw = half_width(radius, w, h);
    if weight.is_nan() || weight <= 0.0 || hw == 0 || img.data.len() != w * h {
        return;
    }
    let table = weights(hw);
    // Rows pass: column x carries its value down the rows.
    let rows: Vec<Vec<[f32; 3]>> = (0..w)
        .into_par_iter()
        .map(|x| blur_line(h, &table, |y, bx| img.data[y * w + bx], x, w))
        .collect();
    // Columns pass over the rows pass's result: row y carries its value across the columns.
    let cols: Vec<Vec<[f32; 3]>> = (0..h)
        .into_par_iter()
        .map(|y| blur_line(w, &table, |x, by| rows[x][by], y, h))
        .collect();
    for (i, p) in img.data.iter_mut().enumerate() {
        let b = cols[i / w][i % w];
        *p = std::array::from_fn(|k| (1.0 - weight) * p[k] + weight * b[k]);
    }
}

/// One pass for the pixels at position `along` of `steps` successive lines (each `len` long):
/// `at(step, i)` is the pixel at position i of line `step`.
fn blur_line(
    steps: usize,
    table: &[f32],
    at: impl Fn(usize, usize) -> [f32; 3],
    along: usize,
    len: usize,
) -> Vec<[f32; 3]> {
    let hw = table.len();
    let (i0, i1) = (along.saturating_sub(hw), (along + hw).min(len - 1));
    (0..steps)
        .map(|step| {
            let (mut sum, mut sum_wt) = ([0.0f32; 3], 0.0f32);
            for i in i0..=i1 {
                let Some(&wt) = table.get(along.abs_diff(i)) else {
                    continue;
                };
                let p = at(step, i);
                sum_wt += wt;
                (0..3).for_each(|k| sum[k] += wt * p[k]);
            }
            sum.map(|c| c / sum_wt)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bloom(img: &mut [[f32; 3]], w: usize, h: usize, radius: f32, weight: f32) {
        apply(
            Pixels {
                width: w,
                height: h,
                data: img,
            },
            radius,
            weight,
        );
    }

    #[test]
    fn kernel_width_and_weights_by_hand() {
        // support = 0.1 * 64 = 6.4 -> 6 pixels -> half width 3
        assert_eq!(half_width(0.1, 64, 32), 3);
        assert_eq!(half_width(0.0, 64, 32), 0);
        assert_eq!(half_width(f32::NAN, 64, 32), 0);
        // w = 2: offset 1 is at z0/2 = 1.91585: exp(-3.67048/1.69802) = 0.115138
        let t = weights(2);
        assert_eq!(t.len(), 2);
        assert_eq!(t[0], 1.0);
        assert!((t[1] - 0.115_138).abs() < 1e-5, "{t:?}");
    }

    #[test]
    fn rows_then_columns_by_hand() {
        // 3x2 image, radius 1.4 -> support 4 -> w = 2, weights [1, a] with a = 0.115138.
        let a = weights(2)[1];
        let mut img = vec![[0.0f32; 3]; 6];
        img[1] = [1.0; 3]; // (1, 0)
        bloom(&mut img, 3, 2, 1.4, 1.0);
        // Rows pass, row 0: a/(1+a), 1/(1+2a), a/(1+a); row 1 has no light.
        let r0 = [a / (1.0 + a), 1.0 / (1.0 + 2.0 * a), a / (1.0 + a)];
        // Columns pass: each column of two rows, weights 1 and a.
        for (x, r) in r0.iter().enumerate() {
            for (y, own) in [(0, 1.0), (1, a)] {
                let want = own * r / (1.0 + a);
                let got = img[y * 3 + x][0];
                assert!((got - want).abs() < 1e-6, "({x}, {y}): {got} vs {want}");
            }
        }
    }

    #[test]
    fn a_flat_image_stays_flat_and_interior_energy_is_kept() {
        let (w, h) = (40usize, 30usize);
        let mut flat = vec![[2.0f32; 3]; w * h];
        bloom(&mut flat, w, h, 0.3, 0.5);
        assert!(
            flat.iter().all(|p| (p[0] - 2.0).abs() < 1e-5),
            "{:?}",
            flat[0]
        );
        let mut img = vec![[0.0f32; 3]; w * h];
        img[15 * w + 20] = [100.0; 3];
        bloom(&mut img, w, h, 0.3, 0.25);
        let total: f32 = img.iter().map(|p| p[0]).sum();
        assert!((total - 100.0).abs() < 1e-2, "{total}");
        assert!(img[15 * w + 21][0] > 0.0 && img[15 * w + 20][0] < 100.0);
    }

    #[test]
    fn weight_blends_and_no_kernel_changes_nothing() {
        let src = vec![[1.0f32, 4.0, 0.0], [4.0; 3], [0.0; 3]];
        // Half width 1: weights [1]: the blur is the pixel itself.
        let mut img = src.clone();
        bloom(&mut img, 3, 1, 0.7, 0.5);
        assert_eq!(img, src);
        // Support below two pixels: no kernel, nothing changes.
        let mut img = src.clone();
        bloom(&mut img, 3, 1, 0.5, 0.5);
        assert_eq!(img, src);
        // Weight 0: nothing changes.
        let mut img = src.clone();
        bloom(&mut img, 3, 1, 1.0, 0.0);
        assert_eq!(img, src);
    }
}
