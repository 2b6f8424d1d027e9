//! Error of a film against the study's reference, in linear RGB.
//!
//! Data flow: a film (a checkpoint of a local run, a farm's FLM) → its linear RGB (every
//! enabled light group and buffer combined with the scene's group scales:
//! `luxfarm::tonemap::film_xyz`, then the renderer's XYZ→RGB, no tonemapping) → paired with
//! the reference's pixels (optionally shifted by whole rows, as `compare-image --shift-rows`)
//! → RMSE and relative MSE (`luxfarm_bench::image_metrics`, the metrics `bench cornell` and
//! `compare-image` report), and the share of pixels failing Yee's perceptual test
//! (`luxfarm::halt::convergence`, the haltthreshold test) between test and reference.
//!
//! The perceptual test needs display images. Both sides are mapped the same way, from the
//! reference alone: linear RGB scaled so that the reference's mean luminance becomes 0.18,
//! clamped to [0, 1] and gamma 2.2 encoded. The test then measures visible differences of
//! the test from the reference, not from its own previous state.

use luxfarm::film::Film;
use luxfarm::halt::convergence::{yee_compare, YeeParams};
use luxfarm::spectrum::xyz_to_rgb;
use luxfarm::tonemap::{film_xyz, RgbImage, TonemapParams};
use luxfarm_bench::image_metrics::{metrics, row_pairs};

/// Display gamma of the perceptual test's images.
const DISPLAY_GAMMA: f32 = 2.2;
/// The reference's mean luminance on the display scale (middle grey).
const DISPLAY_MEAN: f64 = 0.18;

/// The image every measurement compares with.
pub struct Reference {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<[f32; 3]>,
    /// Display scale of the perceptual test (from the reference's mean luminance).
    scale: f32,
    display: RgbImage,
    /// Test row y - shift is compared with reference row y.
    pub shift_rows: i64,
    /// Where it came from (file, or "made by this study").
    pub source: String,
}

/// The error of one film.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Error {
    pub rmse: f64,
    pub rel_mse: f64,
    /// Share of pixels failing the perceptual test against the reference.
    pub failing: f64,
}

impl Reference {
    pub fn new(
        width: u32,
        height: u32,
        rgb: Vec<[f32; 3]>,
        shift_rows: i64,
        source: String,
    ) -> anyhow::Result<Reference> {
        if rgb.len() != width as usize * height as usize || rgb.is_empty() {
            anyhow::bail!("reference {source}: {width}x{height} image without its pixels");
        }
        if let Some(i) = rgb.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
            anyhow::bail!(
                "reference {source}: pixel ({}, {}) is not finite",
                i % width as usize,
                i / width as usize
            );
        }
        let mean_y: f64 =
            rgb.iter().map(|p| f64::from(luminance(*p))).sum::<f64>() / rgb.len() as f64;
        let scale = if mean_y > 0.0 {
            (DISPLAY_MEAN / mean_y) as f32
        } else {
            1.0
        };
        let display = to_display(width, height, &rgb, scale);
        Ok(Reference {
            width,
            height,
            rgb,
            scale,
            display,
            shift_rows,
            source,
        })
    }

    /// The reference made from a film (a cached or given FLM).
    pub fn from_film(
        film: &Film,
        tonemap: &TonemapParams,
        shift_rows: i64,
        source: String,
    ) -> anyhow::Result<Reference> {
        Reference::new(
            film.width(),
            film.height(),
            linear_rgb(film, tonemap),
            shift_rows,
            source,
        )
    }

    /// The error of `film` (same size as the reference).
    pub fn error(&self, film: &Film, tonemap: &TonemapParams) -> anyhow::Result<Error> {
        if (film.width(), film.height()) != (self.width, self.height) {
            anyhow::bail!(
                "the film is {}x{}, the reference {} is {}x{}",
                film.width(),
                film.height(),
                self.source,
                self.width,
                self.height
            );
        }
        Ok(self.error_rgb(&linear_rgb(film, tonemap)))
    }

    /// The error of a linear RGB image of the reference's size.
    pub fn error_rgb(&self, rgb: &[[f32; 3]]) -> Error {
        let (w, h) = (self.width as usize, self.height as usize);
        // Aligned test image: reference pixel i against test pixel paired with it; pixels
        // without a partner (shifted out) take the reference's own value.
        let mut aligned = self.rgb.clone();
        for (ia, ib) in row_pairs(w, h, self.shift_rows) {
            if let (Some(t), Some(a)) = (rgb.get(ia), aligned.get_mut(ib)) {
                *a = *t;
            }
        }
        let m = metrics(&aligned, &self.rgb);
        let display = to_display(self.width, self.height, &aligned, self.scale);
        let params = YeeParams {
            gamma: DISPLAY_GAMMA,
            ..YeeParams::default()
        };
        let verdicts = yee_compare(&display, &self.display, &params);
        let failing = verdicts.iter().filter(|(_, passes)| !*passes).count() as f64
            / verdicts.len().max(1) as f64;
        Error {
            rmse: m.rmse,
            rel_mse: m.rel_mse,
            failing,
        }
    }
}

/// Linear RGB of a film: every enabled group and buffer, normalised and combined as the
/// imaging pipeline's first step does, in the renderer's RGB.
pub fn linear_rgb(film: &Film, tonemap: &TonemapParams) -> Vec<[f32; 3]> {
    film_xyz(film, tonemap)
        .xyz
        .iter()
        .map(|&p| {
            let c = xyz_to_rgb(p).to_array();
            c.map(|v| if v.is_finite() { v } else { 0.0 })
        })
        .collect()
}

fn luminance(p: [f32; 3]) -> f32 {
    0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]
}

fn to_display(width: u32, height: u32, rgb: &[[f32; 3]], scale: f32) -> RgbImage {
    let inv = 1.0 / DISPLAY_GAMMA;
    RgbImage {
        width,
        height,
        rgb: rgb
            .iter()
            .map(|p| p.map(|c| (c * scale).clamp(0.0, 1.0).powf(inv)))
            .collect(),
        alpha: vec![1.0; rgb.len()],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn noisy(base: &[[f32; 3]], amp: f32, seed: u32) -> Vec<[f32; 3]> {
        // A fixed pseudo-random pattern (xorshift), amplitude `amp`.
        let mut s = seed.max(1);
        base.iter()
            .map(|p| {
                p.map(|c| {
                    s ^= s << 13;
                    s ^= s >> 17;
                    s ^= s << 5;
                    let u = (s as f32 / u32::MAX as f32) * 2.0 - 1.0;
                    (c + amp * u).max(0.0)
                })
            })
            .collect()
    }

    fn gradient(w: u32, h: u32) -> Vec<[f32; 3]> {
        (0..w * h)
            .map(|i| {
                let v = 0.1 + (i % w) as f32 / w as f32;
                [v, 0.5 * v, 0.25]
            })
            .collect()
    }

    #[test]
    fn the_reference_itself_has_no_error_and_noise_has_more_the_louder_it_is() {
        let (w, h) = (32, 24);
        let base = gradient(w, h);
        let r = Reference::new(w, h, base.clone(), 0, "test".into()).unwrap();
        let zero = r.error_rgb(&base);
        assert_eq!(zero.rmse, 0.0);
        assert_eq!(zero.failing, 0.0);
        let small = r.error_rgb(&noisy(&base, 0.01, 7));
        let big = r.error_rgb(&noisy(&base, 0.3, 7));
        assert!(small.rmse > 0.0 && small.rmse < big.rmse);
        assert!(small.rel_mse < big.rel_mse);
        assert!(small.failing <= big.failing && big.failing > 0.5, "{big:?}");
    }

    #[test]
    fn a_row_shift_pairs_test_row_y_minus_one_with_reference_row_y() {
        let (w, h) = (8, 6);
        let base = gradient(w, h);
        let mut shifted = base.clone();
        shifted.rotate_left(w as usize); // test row y holds reference row y + 1
        let r = Reference::new(w, h, base, 1, "test".into()).unwrap();
        assert_eq!(r.error_rgb(&shifted).rmse, 0.0);
    }

    #[test]
    fn references_without_pixels_or_with_nan_are_refused() {
        assert!(Reference::new(2, 2, vec![[0.0; 3]; 3], 0, "x".into()).is_err());
        let mut px = vec![[0.5f32; 3]; 4];
        px[3][1] = f32::NAN;
        let e = Reference::new(2, 2, px, 0, "x".into()).err().unwrap();
        assert!(e.to_string().contains("(1, 1)"), "{e}");
    }
}
