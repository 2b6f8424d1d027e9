//! Spectral paths for scenes that disperse light, while everything else stays RGB.
//!
//! A path carries RGB throughput until it meets a dispersing surface. There it is given one
//! wavelength λ, drawn uniformly over the CIE 1931 range (360–830 nm), and its throughput is
//! multiplied by the colour weight w(λ): the linear RGB of a unit spectral line at λ (its
//! negative, out-of-gamut components set to 0) over the density of λ, each channel normalised
//! so that E[w(λ)] = (1, 1, 1). White light therefore stays white on average while each path
//! takes the colour of its wavelength; from then on the path keeps λ (every dispersing
//! surface uses it) and its RGB throughput is already that of the line. A path that never
//! meets a dispersing surface is never given a wavelength and renders exactly as in RGB mode.

use crate::spectrum::cie::{cmf, CIE_START, CIE_STEP, CIE_Y};
use crate::spectrum::{xyz_to_rgb, Rgb};
use std::sync::OnceLock;

/// Shortest sampled wavelength (nm).
pub const LAMBDA_MIN: f32 = CIE_START;

/// Longest sampled wavelength (nm).
pub fn lambda_max() -> f32 {
    CIE_START + CIE_STEP * (CIE_Y.len() - 1) as f32
}

/// Per channel, 1 / ∫ rgb_c(λ) dλ over the sampled range (midpoint rule at 1 nm).
fn normalisation() -> Rgb {
    static NORM: OnceLock<Rgb> = OnceLock::new();
    *NORM.get_or_init(|| {
        let (lo, hi) = (LAMBDA_MIN, lambda_max());
        let n = (hi - lo) as usize;
        let mut sum = [0.0f64; 3];
        for i in 0..n {
            let c = line_rgb(lo + i as f32 + 0.5).to_array();
            for (acc, v) in sum.iter_mut().zip(c) {
                *acc += f64::from(v);
            }
        }
        Rgb::from_array(sum.map(|v| if v > 0.0 { (1.0 / v) as f32 } else { 0.0 }))
    })
}

/// Linear RGB of a unit spectral line at `nm`, negative components set to 0.
fn line_rgb(nm: f32) -> Rgb {
    xyz_to_rgb(cmf(nm)).map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 })
}

/// Draws a wavelength from `u` in [0, 1): (λ in nm, the colour weight w(λ)).
pub fn sample_wavelength(u: f32) -> (f32, Rgb) {
    let (lo, hi) = (LAMBDA_MIN, lambda_max());
    let nm = lo + u.clamp(0.0, 1.0) * (hi - lo);
    // w = rgb(λ) / (pdf · ∫rgb) with pdf = 1 / (hi - lo).
    let w = line_rgb(nm) * normalisation() * (hi - lo);
    (nm, w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_average_to_white() {
        let n = 20000;
        let mut sum = Rgb::BLACK;
        for i in 0..n {
            sum += sample_wavelength((i as f32 + 0.5) / n as f32).1;
        }
        let mean = sum / n as f32;
        for c in mean.to_array() {
            assert!((c - 1.0).abs() < 0.01, "{mean:?}");
        }
    }

    #[test]
    fn red_and_blue_lines_take_their_colours() {
        let (_, red) = sample_wavelength((650.0 - LAMBDA_MIN) / (lambda_max() - LAMBDA_MIN));
        let (_, blue) = sample_wavelength((450.0 - LAMBDA_MIN) / (lambda_max() - LAMBDA_MIN));
        assert!(red.r > 5.0 * red.b && red.r > red.g, "{red:?}");
        assert!(blue.b > 5.0 * blue.r && blue.b > blue.g, "{blue:?}");
    }
}
