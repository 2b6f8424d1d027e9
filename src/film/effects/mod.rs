//! The Film's image effects as LuxRender 1.x's imaging pipeline applies them: bloom and glare
//! on the clamped XYZ image before the tonemapping kernel, vignetting and chromatic aberration
//! on the RGB image after the colour space conversion (and the camera response).
//!
//! Each effect is a pure function over a pixel slice (`[f32; 3]` per pixel, row by row, top
//! row first) with the image's width and height; the settings come from
//! [`crate::film::imaging::Effects`]. `tonemap` calls them in LuxRender's order
//! (bloom, glare, kernel, RGB, camera response, vignetting and aberration, gamma); nothing here
//! knows about films or kernels, so the film layer still imports none of the back end.

pub mod aberration;
pub mod bloom;
pub mod glare;
pub mod vignetting;

/// A pixel image borrowed for an effect.
pub struct Pixels<'a> {
    pub width: usize,
    pub height: usize,
    pub data: &'a mut [[f32; 3]],
}

/// Bilinear lookup of `img` (width `w`, height `h`) at pixel coordinates (x, y), the pixel
/// (i, j) sitting at (i, j); coordinates outside are clamped to the border.
pub(crate) fn bilinear(img: &[[f32; 3]], w: usize, h: usize, x: f32, y: f32) -> [f32; 3] {
    if w == 0 || h == 0 || img.len() < w * h {
        return [0.0; 3];
    }
    let fx = if x.is_finite() { x.max(0.0) } else { 0.0 };
    let fy = if y.is_finite() { y.max(0.0) } else { 0.0 };
    let x1 = (fx.floor() as usize).min(w - 1);
    let y1 = (fy.floor() as usize).min(h - 1);
    let x2 = (x1 + 1).min(w - 1);
    let y2 = (y1 + 1).min(h - 1);
    let tx = (fx - x1 as f32).clamp(0.0, 1.0);
    let ty = (fy - y1 as f32).clamp(0.0, 1.0);
    let mut c = [0.0f32; 3];
    for (wt, i) in [
        ((1.0 - tx) * (1.0 - ty), y1 * w + x1),
        (tx * (1.0 - ty), y1 * w + x2),
        ((1.0 - tx) * ty, y2 * w + x1),
        (tx * ty, y2 * w + x2),
    ] {
        let p = img[i];
        (0..3).for_each(|k| c[k] += wt * p[k]);
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bilinear_interpolates_and_clamps() {
        let img = [[0.0; 3], [1.0; 3], [2.0; 3], [3.0; 3]];
        assert_eq!(bilinear(&img, 2, 2, 0.5, 0.0), [0.5; 3]);
        assert_eq!(bilinear(&img, 2, 2, 0.5, 0.5), [1.5; 3]);
        assert_eq!(bilinear(&img, 2, 2, -4.0, 9.0), [2.0; 3]);
        assert_eq!(bilinear(&img, 2, 2, f32::NAN, 0.0), [0.0; 3]);
    }
}
