//! Vignetting: darkening towards the corners, as LuxRender 1.x applies it to the RGB image.
//!
//! Pixel (x, y) of a w x h image sits at (x/w - 0.5, y/h - 0.5) from the centre in
//! normalised coordinates; with r its distance and t = 1 - 1.42 r, the pixel is multiplied by
//! lerp(t, 1 - scale, 1) = (1 - t)(1 - scale) + t. The centre keeps its value, the corners
//! (r = 0.707) fall to about 1 - scale; a negative scale brightens.

/// The factor for pixel (x, y) of a w x h image.
pub fn factor(x: usize, y: usize, w: usize, h: usize, scale: f32) -> f32 {
    let dx = x as f32 / w as f32 - 0.5;
    let dy = y as f32 / h as f32 - 0.5;
    let t = 1.0 - (dx * dx + dy * dy).sqrt() * 1.42;
    (1.0 - t) * (1.0 - scale) + t
}

/// Multiplies every pixel by its vignetting factor.
pub fn apply(data: &mut [[f32; 3]], w: usize, h: usize, scale: f32) {
    if scale == 0.0 || !scale.is_finite() || w == 0 || h == 0 {
        return;
    }
    for (i, p) in data.iter_mut().enumerate().take(w * h) {
        let f = factor(i % w, i / w, w, h, scale);
        *p = p.map(|c| c * f);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn falloff_at_chosen_pixels() {
        // 10x10, scale 0.4: the centre pixel (5, 5) is at r = 0 -> factor 1
        assert!((factor(5, 5, 10, 10, 0.4) - 1.0).abs() < 1e-6);
        // pixel (0, 5): r = 0.5, t = 0.29, factor = 0.71 * 0.6 + 0.29 = 0.716
        assert!((factor(0, 5, 10, 10, 0.4) - 0.716).abs() < 1e-6);
        // pixel (0, 0): r = sqrt(0.5) = 0.70711, t = -0.0040916, factor = 0.5983634
        assert!((factor(0, 0, 10, 10, 0.4) - 0.598_363_4).abs() < 1e-5);
        let mut img = vec![[2.0f32; 3]; 100];
        apply(&mut img, 10, 10, 0.4);
        assert!((img[5 * 10][0] - 2.0 * 0.716).abs() < 1e-5);
        assert!((img[55][1] - 2.0).abs() < 1e-6);
    }
}
