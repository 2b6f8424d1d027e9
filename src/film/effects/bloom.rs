//! Bloom: each pixel is blended with the weighted mean of its neighbours within a radius, as
//! LuxRender 1.x's imaging pipeline does it.
//!
//! The support is `bloom_radius` times the image's longer side (in pixels, truncated); the
//! kernel's half width is half of it. A neighbour at squared pixel distance d² < w² weighs
//! (1 - sqrt(d²)/w)^4; the pixel itself is left out; the neighbours' mean is normalised by the
//! weights that fell inside the image. The result is `lerp(bloom_weight, pixel, mean)`.
//! Away from the borders the kernel's weights sum to the same value for every pixel, so the
//! image's total energy is kept.

use super::Pixels;
use rayon::prelude::*;

/// Half width in pixels of the bloom kernel for an image (0: no bloom).
pub fn half_width(radius: f32, width: usize, height: usize) -> usize {
    let support = radius * width.max(height) as f32;
    if support.is_finite() && support > 0.0 {
        (support as usize) / 2
    } else {
        0
    }
}

/// Applies bloom in place. Does nothing for a non-positive radius or weight, or a kernel
/// narrower than one pixel.
pub fn apply(img: Pixels<'_>, radius: f32, weight: f32) {
    let (w, h) = (img.width, img.height);
    let hw = half_width(radius, w, h);
    if weight.is_nan() || weight <= 0.0 || hw == 0 || img.data.len() != w * h {
        return;
    }
    let hw2 = hw * hw;
    let table: Vec<f32> = (0..hw2)
        .map(|d2| (1.0 - (d2 as f32).sqrt() / hw as f32).max(0.0).powi(4))
        .collect();
    let src: &[[f32; 3]] = img.data;
    let blurred: Vec<[f32; 3]> = (0..w * h)
        .into_par_iter()
        .map(|i| neighbour_mean(src, w, h, i % w, i / w, hw, &table))
        .collect();
    let weight = weight.min(1.0);
    for (p, b) in img.data.iter_mut().zip(&blurred) {
        *p = std::array::from_fn(|k| (1.0 - weight) * p[k] + weight * b[k]);
    }
}

/// Weighted mean of the neighbours of (x, y) within the kernel (the pixel itself excluded).
fn neighbour_mean(
    src: &[[f32; 3]],
    w: usize,
    h: usize,
    x: usize,
    y: usize,
    hw: usize,
    table: &[f32],
) -> [f32; 3] {
    let (x0, x1) = (x.saturating_sub(hw), (x + hw).min(w - 1));
    let (y0, y1) = (y.saturating_sub(hw), (y + hw).min(h - 1));
    let (mut sum, mut sum_wt) = ([0.0f64; 3], 0.0f64);
    for by in y0..=y1 {
        for bx in x0..=x1 {
            if bx == x && by == y {
                continue;
            }
            let d2 = x.abs_diff(bx).pow(2) + y.abs_diff(by).pow(2);
            let Some(&wt) = table.get(d2) else {
                continue;
            };
            let p = src[by * w + bx];
            sum_wt += f64::from(wt);
            (0..3).for_each(|k| sum[k] += f64::from(wt) * f64::from(p[k]));
        }
    }
    if sum_wt > 0.0 {
        sum.map(|c| (c / sum_wt) as f32)
    } else {
        src[y * w + x]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn total(img: &[[f32; 3]]) -> [f64; 3] {
        img.iter().fold([0.0; 3], |mut s, p| {
            (0..3).for_each(|k| s[k] += f64::from(p[k]));
            s
        })
    }

    #[test]
    fn kernel_width_from_radius() {
        // support = 0.1 * 64 = 6.4 -> 6 pixels -> half width 3
        assert_eq!(half_width(0.1, 64, 32), 3);
        assert_eq!(half_width(0.0, 64, 32), 0);
        assert_eq!(half_width(f32::NAN, 64, 32), 0);
    }

    #[test]
    fn interior_energy_is_conserved() {
        let (w, h) = (41usize, 41usize);
        let mut img = vec![[0.0f32; 3]; w * h];
        img[20 * w + 20] = [100.0, 50.0, 25.0];
        img[18 * w + 23] = [10.0, 10.0, 10.0];
        let before = total(&img);
        // support 0.2 * 41 = 8.2 -> 8 -> half width 4: the sources are far from the borders
        apply(
            Pixels {
                width: w,
                height: h,
                data: &mut img,
            },
            0.2,
            0.25,
        );
        let after = total(&img);
        for k in 0..3 {
            assert!(
                (before[k] - after[k]).abs() < 1e-3 * before[k],
                "{before:?} {after:?}"
            );
        }
        // the source keeps 1 - weight of itself; a direct neighbour receives light
        assert!((img[20 * w + 20][0] - 75.0).abs() < 1e-3);
        assert!(img[20 * w + 21][0] > 0.0);
        // beyond the half width nothing arrives
        assert_eq!(img[20 * w + 30], [0.0; 3]);
    }

    #[test]
    fn neighbour_weights_by_hand() {
        // 3x1 image, half width 1: table = [1] (only d² = 0 < 1), so no neighbour is inside
        // the kernel and every pixel keeps its value.
        let mut img = vec![[1.0f32; 3], [4.0; 3], [0.0; 3]];
        apply(
            Pixels {
                width: 3,
                height: 1,
                data: &mut img,
            },
            0.7,
            0.5,
        );
        assert_eq!(img, vec![[1.0f32; 3], [4.0; 3], [0.0; 3]]);
        // 5x1 image, half width 2: d² = 1 weighs (1 - 1/2)^4 = 1/16; pixel 2 sees 1 and 3
        let mut img = vec![[0.0f32; 3], [2.0; 3], [8.0; 3], [4.0; 3], [0.0; 3]];
        apply(
            Pixels {
                width: 5,
                height: 1,
                data: &mut img,
            },
            1.0,
            1.0,
        );
        assert!((img[2][0] - 3.0).abs() < 1e-6, "{:?}", img[2]);
    }
}
