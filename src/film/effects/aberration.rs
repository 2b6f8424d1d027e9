//! Chromatic aberration, as LuxRender 1.x applies it to the RGB image: red and blue are taken
//! from a point pushed outward from the centre, green from a point pulled inward.
//!
//! Pixel (x, y) of a w x h image sits at offset (dx, dy) = (x/w - 0.5, y/h - 0.5), at
//! distance r from the centre; red and blue are read (bilinearly) at
//! (0.5 + dx (1 + r·amount)) · (w, h), green at (0.5 + dx (1 - r·amount)) · (w, h).

use super::bilinear;

/// Returns the aberrated image of `src` (w x h).
pub fn apply(src: &[[f32; 3]], w: usize, h: usize, amount: f32) -> Vec<[f32; 3]> {
    if amount.is_nan() || amount <= 0.0 || !amount.is_finite() || src.len() != w * h {
        return src.to_vec();
    }
    (0..w * h)
        .map(|i| {
            let dx = (i % w) as f32 / w as f32 - 0.5;
            let dy = (i / w) as f32 / h as f32 - 0.5;
            let r = (dx * dx + dy * dy).sqrt();
            let at = |s: f32| {
                let x = (0.5 + dx * (1.0 + s * r * amount)) * w as f32;
                let y = (0.5 + dy * (1.0 + s * r * amount)) * h as f32;
                bilinear(src, w, h, x, y)
            };
            let (rb, g) = (at(1.0), at(-1.0));
            [rb[0], g[1], rb[2]]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn channels_shift_apart() {
        // 10x1 ramp, amount 0.5: pixel 0 has dx = -0.5, dy = -0.5, r = 0.70711;
        // red/blue at x = (0.5 - 0.5 * 1.35355) * 10 = -1.77 -> clamped to 0;
        // pixel 8: dx = 0.3, r = sqrt(0.34) = 0.58310; red at (0.5 + 0.3 * 1.29155) * 10
        // = 8.87465, green at (0.5 + 0.3 * 0.70845) * 10 = 7.12535
        let src: Vec<[f32; 3]> = (0..10).map(|i| [i as f32; 3]).collect();
        let out = apply(&src, 10, 1, 0.5);
        assert!((out[8][0] - 8.874_65).abs() < 1e-4, "{:?}", out[8]);
        assert!((out[8][2] - 8.874_65).abs() < 1e-4);
        assert!((out[8][1] - 7.125_35).abs() < 1e-4);
        assert_eq!(out[0][0], 0.0);
        assert_eq!(apply(&src, 10, 1, 0.0), src);
    }
}
