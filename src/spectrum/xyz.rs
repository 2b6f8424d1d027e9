//! RGB to CIE XYZ as LuxRender's colour pipeline produces it, and blackbody colours.
//!
//! ## How LuxRender turns a scene colour into film XYZ (LuxRender 1.x sources)
//!
//! 1. A `color` of a light (`L` of area lights, point/spot `L`, ...) becomes an `RGBIllumSPD`:
//!    the Smits decomposition (see [`super::smits`]) over the seven 32-bin illuminant basis
//!    spectra generated for a **D65 white point**, times `illumrgb2spect_scale = 0.86445`,
//!    clamped at zero. Reflectances use a second basis (`RGBReflSPD`, equal-energy white,
//!    scale 0.94112876, so that white reflects 0.9994 at every wavelength).
//! 2. Rendering is spectral: a path's value at each sampled wavelength is the illuminant SPD
//!    times the reflectance SPDs. Wavelengths are stratified uniformly over 380–720 nm.
//! 3. `SWCSpectrum::ToXYZ` weights each wavelength sample with the CIE 1931 matching functions
//!    scaled by `683 * (720 - 380) / WAVELENGTH_SAMPLES` (the `spd_ciex/y/z` of
//!    `SpectrumWavelengths`), i.e. the film receives the estimate of
//!    `XYZ = 683 lm/W * ∫_380^720 S(λ) [x̄ ȳ z̄](λ) dλ`, with **no division by the ȳ
//!    integral**. `SPD::Y()` (used by light power normalisation) is the same sum at 1 nm steps:
//!    `683 * Σ S(λ) ȳ(λ)`.
//!
//! The renderer here is RGB and multiplies light and reflectance RGBs channel by channel, so an
//! RGB value reaching the film mixes both. [`rgb_to_xyz`] reads it as **a reflectance (Smits
//! reflectance basis) lit by the white illuminant** (`RGBIllumSPD(1,1,1)`):
//! `XYZ(rgb) = 683 Σ_λ 0.86445 W_illum(λ) · 0.94112876 R_refl(rgb)(λ) · cmf(λ)` (1 nm steps,
//! 380–720 nm). Each of the seven reflectance basis spectra is integrated once under the white
//! illuminant and an RGB triple is converted with the same Smits case analysis, so:
//! - grey lights (nearly all scenes) on any chain of reflections see the saturated reflectance
//!   spectra LuxRender would use (exact for one bounce: a `Kd (0.37, 0, 0)` cube under a
//!   6500 K light is 7% brighter in Y and 23% bluer in Z than reading the same RGB as an
//!   illuminant), and grey values are within 0.06% of the illuminant basis;
//! - a saturated *light* colour seen directly differs from LuxRender's `RGBIllumSPD` of that
//!   colour by the difference between the two bases (use [`illuminant_xyz`] for the exact
//!   illuminant value, e.g. to normalise light power).
//!
//! Not reproduced: LuxRender's clamp of negative SPD samples (only saturated colours whose
//! basis mix dips below zero, by at most ~1%). White `(1,1,1)` gives Y ≈ 6.7e4.
//!
//! [`blackbody`] returns the illuminant RGB whose XYZ equals that of LuxRender's
//! `BlackbodySPD(T)`: Planck's law sampled at 256 points over 380–720 nm and normalised so that
//! its largest sample is 1.

use super::smits;
use super::Rgb;
use glam::{DMat3, DVec3};
use std::sync::OnceLock;

/// LuxRender's luminous efficacy factor applied when converting spectra to XYZ.
pub const LUMENS_PER_WATT: f64 = 683.0;

/// XYZ of each reflectance basis spectrum (white, cyan, magenta, yellow, red, green, blue)
/// under the white illuminant.
fn basis_xyz() -> &'static [DVec3; 7] {
    static TABLE: OnceLock<[DVec3; 7]> = OnceLock::new();
    TABLE.get_or_init(|| {
        let mut out = [DVec3::ZERO; 7];
        for (k, basis) in smits::REFL_BASES.iter().enumerate() {
            out[k] = integrate(|nm| {
                let white = smits::sample(&smits::WHITE, nm) as f64 * smits::ILLUM_SCALE as f64;
                white * smits::sample(basis, nm) as f64 * smits::REFL_SCALE as f64
            });
        }
        out
    })
}

/// `683 * Σ_{λ=380..720 nm, 1 nm} s(λ) cmf(λ)`.
fn integrate(s: impl Fn(f32) -> f64) -> DVec3 {
    let mut acc = DVec3::ZERO;
    for nm in 380..=720 {
        let c = super::cie::cmf(nm as f32);
        let v = s(nm as f32);
        acc += DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64) * v;
    }
    acc * LUMENS_PER_WATT
}

/// XYZ of each illuminant basis spectrum.
fn illum_basis_xyz() -> &'static [DVec3; 7] {
    static TABLE: OnceLock<[DVec3; 7]> = OnceLock::new();
    TABLE.get_or_init(|| {
        let mut out = [DVec3::ZERO; 7];
        for (k, basis) in smits::BASES.iter().enumerate() {
            out[k] = integrate(|nm| smits::sample(basis, nm) as f64 * smits::ILLUM_SCALE as f64);
        }
        out
    })
}

fn combine(c: Rgb, t: &[DVec3; 7]) -> [f32; 3] {
    let w = smits::decompose(c.r, c.g, c.b);
    let mut acc = DVec3::ZERO;
    for (wk, xyz) in w.iter().zip(t.iter()) {
        if *wk != 0.0 {
            acc += *xyz * *wk as f64;
        }
    }
    [acc.x as f32, acc.y as f32, acc.z as f32]
}

/// XYZ of a spectrum given as a function of wavelength (nm), as LuxRender integrates it
/// (`683 Σ s(λ) cmf(λ)`, 380–720 nm in 1 nm steps).
pub fn spectrum_xyz(s: impl Fn(f32) -> f64) -> [f64; 3] {
    integrate(s).to_array()
}

/// XYZ of a reflectance spectrum lit by the white illuminant (LuxRender's
/// `RGBIllumSPD(1, 1, 1)`): what a white light reflected by it gives on the film.
pub fn reflectance_xyz(r: impl Fn(f32) -> f64) -> [f64; 3] {
    integrate(|nm| {
        let white = smits::sample(&smits::WHITE, nm) as f64 * smits::ILLUM_SCALE as f64;
        white * r(nm)
    })
    .to_array()
}

/// Film XYZ of a radiance RGB (see the module documentation).
pub fn rgb_to_xyz(c: Rgb) -> [f32; 3] {
    combine(c, basis_xyz())
}

/// XYZ of LuxRender's `RGBIllumSPD(c)`: a light colour as LuxRender's lights emit it.
pub fn illuminant_xyz(c: Rgb) -> [f32; 3] {
    combine(c, illum_basis_xyz())
}

/// Luminance Y (cd/m² scale, LuxRender's `SPD::Y`) of a light colour: the value LuxRender
/// divides by when it normalises light power.
pub fn illuminant_y(c: Rgb) -> f32 {
    illuminant_xyz(c)[1]
}

/// The inverse of [`rgb_to_xyz`]: the illuminant RGB with this XYZ. The Smits map is linear in
/// each of the six orderings of the channels; the ordering whose solution is consistent wins.
/// Colours outside the basis gamut get the least inconsistent solution, clamped at zero.
pub fn xyz_to_rgb(xyz: [f32; 3]) -> Rgb {
    let t = basis_xyz();
    let target = DVec3::new(xyz[0] as f64, xyz[1] as f64, xyz[2] as f64);
    let (white, cyan, magenta, yellow, red, green, blue) =
        (t[0], t[1], t[2], t[3], t[4], t[5], t[6]);
    // (min, mid, max) channel indices with the secondary and primary spectra of that ordering.
    let orders: [([usize; 3], DVec3, DVec3); 6] = [
        ([0, 1, 2], cyan, blue),
        ([0, 2, 1], cyan, green),
        ([1, 0, 2], magenta, blue),
        ([1, 2, 0], magenta, red),
        ([2, 0, 1], yellow, green),
        ([2, 1, 0], yellow, red),
    ];
    let mut best: Option<(f64, [f64; 3])> = None;
    for (idx, sec, prim) in orders {
        let mut cols = [DVec3::ZERO; 3];
        cols[idx[0]] = white - sec;
        cols[idx[1]] = sec - prim;
        cols[idx[2]] = prim;
        let m = DMat3::from_cols(cols[0], cols[1], cols[2]);
        if m.determinant().abs() < 1e-12 {
            continue;
        }
        let s = m.inverse() * target;
        let v = [s.x, s.y, s.z];
        let scale = v.iter().fold(1e-9f64, |a, b| a.max(b.abs()));
        let violation =
            ((v[idx[0]] - v[idx[1]]).max(0.0) + (v[idx[1]] - v[idx[2]]).max(0.0)) / scale;
        if best.is_none_or(|(bv, _)| violation < bv) {
            best = Some((violation, v));
        }
    }
    match best {
        Some((_, v)) => Rgb::new(v[0] as f32, v[1] as f32, v[2] as f32).clamp_zero(),
        None => Rgb::BLACK,
    }
}

/// Planck's law as LuxRender's `BlackbodySPD` evaluates it (arbitrary units), `nm` in nm.
pub(crate) fn planck(nm: f64, temperature: f64) -> f64 {
    let w = nm * 1e-9;
    0.4e-9 * (3.74183e-16 * w.powi(-5)) / ((1.4388e-2 / (w * temperature)).exp() - 1.0)
}

/// Illuminant RGB of LuxRender's blackbody spectrum at `temperature` kelvin, normalised so
/// that the spectrum's largest sample over 380–720 nm is 1. Non-positive or non-finite
/// temperatures give black.
pub fn blackbody(temperature: f32) -> Rgb {
    xyz_to_rgb(blackbody_xyz(temperature))
}

/// XYZ of the blackbody spectrum itself (for tests and light normalisation).
pub fn blackbody_xyz(temperature: f32) -> [f32; 3] {
    if !(temperature.is_finite() && temperature > 0.0) {
        return [0.0; 3];
    }
    let t = temperature as f64;
    let n = 256;
    let max = (0..n)
        .map(|i| planck(380.0 + 340.0 * i as f64 / (n - 1) as f64, t))
        .fold(0.0f64, f64::max);
    if !(max > 0.0 && max.is_finite()) {
        return [0.0; 3];
    }
    let xyz = integrate(|nm| planck(nm as f64, t) / max);
    [xyz.x as f32, xyz.y as f32, xyz.z as f32]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn white_matches_luxrender_rgbillum_spd() {
        // Independent check: build RGBIllumSPD(1,1,1) = 0.86445 * white basis and integrate.
        let direct = integrate(|nm| smits::sample(&smits::WHITE, nm) as f64 * 0.86445);
        assert!((illuminant_y(Rgb::WHITE) as f64 - direct.y).abs() / direct.y < 1e-5);
        // A white reflector under it: within 0.1% (LuxRender's white reflects 0.9994).
        let xyz = rgb_to_xyz(Rgb::WHITE);
        for i in 0..3 {
            let d = [direct.x, direct.y, direct.z][i];
            assert!(
                (xyz[i] as f64 - d).abs() / d < 1e-3,
                "{xyz:?} vs {direct:?}"
            );
        }
        // Value derived from LuxRender's tables: Y ~ 683 * 0.86445 * ∫ white ȳ ≈ 7.1e4, and the
        // chromaticity is D65's (the basis was generated for it): x=0.3127, y=0.3290.
        let sum = (xyz[0] + xyz[1] + xyz[2]) as f64;
        let (x, y) = (xyz[0] as f64 / sum, xyz[1] as f64 / sum);
        assert!((x - 0.3127).abs() < 0.004, "x {x}");
        assert!((y - 0.3290).abs() < 0.004, "y {y}");
        assert!(xyz[1] > 6.5e4 && xyz[1] < 7.5e4, "Y {}", xyz[1]);
    }

    /// A saturated reflectance under a (near-white) light: the spectral product LuxRender
    /// integrates, against our RGB product.
    #[test]
    fn saturated_reflectance_matches_the_spectral_product() {
        let t = 6500.0f64;
        let max = (0..256)
            .map(|i| planck(380.0 + 340.0 * i as f64 / 255.0, t))
            .fold(0.0f64, f64::max);
        let kd = Rgb::new(0.374624, 0.0, 0.0);
        let w = smits::decompose(kd.r, kd.g, kd.b);
        let spectral = integrate(|nm| {
            let refl: f64 = w
                .iter()
                .zip(smits::REFL_BASES.iter())
                .map(|(wk, b)| *wk as f64 * smits::sample(b, nm) as f64)
                .sum();
            planck(nm as f64, t) / max * refl.max(0.0) * smits::REFL_SCALE as f64
        });
        let ours = rgb_to_xyz(blackbody(6500.0) * kd);
        for (o, s) in ours.iter().zip([spectral.x, spectral.y, spectral.z]) {
            assert!((*o as f64 - s).abs() / s < 0.05, "{ours:?} vs {spectral:?}");
        }
    }

    /// The TestSuite's directlighting scene lights a Kd 0.3746 plane with a 6500 K blackbody
    /// point light (gain 1); its LuxRender reference film peaks at Y = 96.1 where
    /// Kd/π·cosθ/r² = 1.488e-3, i.e. an intensity of Y ≈ 6.46e4: the 683 lm/W scale and
    /// max-normalised blackbody reproduce it.
    #[test]
    fn blackbody_luminance_matches_luxrender_reference_scale() {
        let y = blackbody_xyz(6500.0)[1];
        assert!((y - 64_600.0).abs() < 0.01 * 64_600.0, "{y}");
        let y_rgb = rgb_to_xyz(blackbody(6500.0))[1];
        assert!((y_rgb - y).abs() < 1e-3 * y);
    }

    #[test]
    fn rgb_to_xyz_is_linear_for_greys_and_zero_for_black() {
        assert_eq!(rgb_to_xyz(Rgb::BLACK), [0.0; 3]);
        let a = rgb_to_xyz(Rgb::splat(0.25));
        let b = rgb_to_xyz(Rgb::WHITE);
        for i in 0..3 {
            assert!((a[i] * 4.0 - b[i]).abs() < 1e-2 * b[i]);
        }
    }

    #[test]
    fn xyz_to_rgb_inverts_rgb_to_xyz() {
        for c in [
            Rgb::new(0.2, 0.5, 0.9),
            Rgb::new(0.9, 0.1, 0.4),
            Rgb::new(0.3, 0.3, 0.3),
            Rgb::new(0.7, 0.6, 0.1),
        ] {
            let back = xyz_to_rgb(rgb_to_xyz(c));
            for i in 0..3 {
                assert!((back[i] - c[i]).abs() < 1e-3, "{c:?} -> {back:?}");
            }
        }
    }

    #[test]
    fn blackbody_6500_is_near_white_and_red_at_low_temperature() {
        let c = blackbody(6500.0);
        let xyz = rgb_to_xyz(c);
        let bb = blackbody_xyz(6500.0);
        assert!((illuminant_y(c) - bb[1]).abs() < 0.01 * bb[1]);
        for i in 0..3 {
            assert!((xyz[i] - bb[i]).abs() < 1e-3 * bb[1], "{xyz:?} vs {bb:?}");
        }
        assert!(c.r > 0.8 && c.g > 0.8 && c.b > 0.8, "{c:?}");
        let warm = blackbody(2000.0);
        assert!(warm.r > warm.g && warm.g > warm.b, "{warm:?}");
        assert_eq!(blackbody(-1.0), Rgb::BLACK);
    }
}
