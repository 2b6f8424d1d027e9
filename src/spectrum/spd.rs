//! Sampled spectra: what LuxRender's spectral textures give (`equalenergy`, `gaussian`,
//! `blackbody`, `lampspectrum`, `tabulateddata`) as wavelength (nm) / value pairs with linear
//! interpolation between samples and zero outside them (LuxRender's `IrregularSPD`; a regular
//! grid is the special case). The renderer is RGB: [`Spd::illuminant_rgb`] reads a spectrum as
//! a light (the RGB whose film XYZ is the spectrum's own XYZ) and [`Spd::reflectance_rgb`] as
//! a reflectance under LuxRender's white light. The spectrum itself is kept for spectral
//! rendering.

use super::xyz::{reflectance_xyz, spectrum_xyz, xyz_to_rgb};
use super::Rgb;

/// Most samples a spectrum may have (files are checked against it before allocating).
pub const MAX_SAMPLES: usize = 1 << 16;

/// A spectrum sampled at ascending wavelengths (nm).
#[derive(Clone, Debug, PartialEq)]
pub struct Spd {
    wl: Vec<f32>,
    v: Vec<f32>,
}

impl Spd {
    /// A spectrum from (wavelength, value) samples: finite, wavelengths strictly ascending,
    /// at least one sample, at most [`MAX_SAMPLES`].
    pub fn new(wl: Vec<f32>, v: Vec<f32>) -> Result<Spd, String> {
        if wl.len() != v.len() {
            return Err(format!("{} wavelengths for {} values", wl.len(), v.len()));
        }
        if wl.is_empty() || wl.len() > MAX_SAMPLES {
            return Err(format!(
                "{} samples (1 to {MAX_SAMPLES} are accepted)",
                wl.len()
            ));
        }
        if wl.iter().chain(v.iter()).any(|x| !x.is_finite()) {
            return Err("a sample is not finite".into());
        }
        if wl.windows(2).any(|w| w[1] <= w[0]) {
            return Err("wavelengths must ascend".into());
        }
        Ok(Spd { wl, v })
    }

    /// Samples of `f` every `step` nm from `start` to `end` (inclusive).
    pub fn from_fn(start: f32, end: f32, step: f32, f: impl Fn(f32) -> f32) -> Spd {
        let n = (((end - start) / step).floor() as usize + 1).clamp(1, MAX_SAMPLES);
        let wl: Vec<f32> = (0..n).map(|i| start + step * i as f32).collect();
        let v = wl.iter().map(|&w| f(w)).collect();
        Spd { wl, v }
    }

    /// The same value at every wavelength of the visible range.
    pub fn constant(value: f32) -> Spd {
        Spd {
            wl: vec![380.0, 720.0],
            v: vec![value, value],
        }
    }

    pub fn wavelengths(&self) -> &[f32] {
        &self.wl
    }

    pub fn values(&self) -> &[f32] {
        &self.v
    }

    /// The value at `nm`: linear between samples, zero outside them (a single sample holds
    /// at its wavelength only).
    pub fn sample(&self, nm: f32) -> f32 {
        let (first, last) = match (self.wl.first(), self.wl.last()) {
            (Some(&a), Some(&b)) => (a, b),
            _ => return 0.0,
        };
        if !(nm >= first && nm <= last) {
            return 0.0;
        }
        let i = self.wl.partition_point(|&w| w <= nm);
        if i == 0 {
            return self.v[0];
        }
        if i >= self.wl.len() {
            return self.v[self.v.len() - 1];
        }
        let (w0, w1) = (self.wl[i - 1], self.wl[i]);
        let t = (nm - w0) / (w1 - w0);
        self.v[i - 1] * (1.0 - t) + self.v[i] * t
    }

    /// LuxRender's `BlackbodySPD`: Planck's law at `temperature` kelvin, 256 samples over
    /// 380–720 nm, normalised so that the largest is 1 (black for non-positive temperatures).
    pub fn blackbody(temperature: f32) -> Spd {
        let t = temperature as f64;
        let n = 256;
        let wl: Vec<f32> = (0..n)
            .map(|i| 380.0 + 340.0 * i as f32 / (n - 1) as f32)
            .collect();
        let raw: Vec<f64> = wl
            .iter()
            .map(|&w| {
                if t > 0.0 {
                    super::xyz::planck(w as f64, t)
                } else {
                    0.0
                }
            })
            .collect();
        let max = raw.iter().copied().fold(0.0f64, f64::max);
        let v = raw
            .iter()
            .map(|&x| {
                if max > 0.0 && max.is_finite() {
                    (x / max) as f32
                } else {
                    0.0
                }
            })
            .collect();
        Spd { wl, v }
    }

    /// The spectrum multiplied by `k`.
    pub fn scaled(mut self, k: f32) -> Spd {
        for x in &mut self.v {
            *x *= k;
        }
        self
    }

    /// Film XYZ of the spectrum as emitted light.
    pub fn xyz(&self) -> [f64; 3] {
        spectrum_xyz(|nm| self.sample(nm) as f64)
    }

    /// The RGB a light of this spectrum has in the renderer.
    pub fn illuminant_rgb(&self) -> Rgb {
        xyz_to_rgb(self.xyz().map(|c| c as f32))
    }

    /// The RGB of this spectrum as a reflectance (white light reflected by it).
    pub fn reflectance_rgb(&self) -> Rgb {
        xyz_to_rgb(reflectance_xyz(|nm| self.sample(nm) as f64).map(|c| c as f32))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation_and_limits() {
        let s = Spd::new(vec![400.0, 500.0, 600.0], vec![1.0, 3.0, 2.0]).unwrap();
        assert_eq!(s.sample(400.0), 1.0);
        assert_eq!(s.sample(450.0), 2.0);
        assert_eq!(s.sample(550.0), 2.5);
        assert_eq!(s.sample(600.0), 2.0);
        assert_eq!(s.sample(399.0), 0.0);
        assert_eq!(s.sample(601.0), 0.0);
        assert_eq!(s.sample(f32::NAN), 0.0);
        assert!(Spd::new(vec![500.0, 400.0], vec![1.0, 1.0]).is_err());
        assert!(Spd::new(vec![400.0], vec![1.0, 1.0]).is_err());
        assert!(Spd::new(vec![], vec![]).is_err());
        assert!(Spd::new(vec![400.0, f32::INFINITY], vec![1.0, 1.0]).is_err());
        let f = Spd::from_fn(380.0, 720.0, 10.0, |w| w);
        assert_eq!(f.wavelengths().len(), 35);
        assert_eq!(f.sample(385.0), 385.0);
    }

    #[test]
    fn a_flat_reflectance_is_grey_and_a_flat_light_is_equal_energy_white() {
        let r = Spd::constant(0.5).reflectance_rgb();
        for c in [r.r, r.g, r.b] {
            assert!((c - 0.5).abs() < 0.01, "{r:?}");
        }
        // Equal energy is redder and less blue than the D65-balanced white of RGB (1, 1, 1).
        let e = Spd::constant(1.0).illuminant_rgb();
        assert!(e.r > e.b, "{e:?}");
        // Its luminance: 683 · Σ ȳ (380–720 nm) ≈ 683 · 106.8.
        let y = Spd::constant(1.0).xyz()[1];
        assert!((y / 683.0 - 106.7).abs() < 0.5, "{y}");
    }
}
