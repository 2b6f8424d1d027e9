//! Data tables of the sun and sky lights (the same values LuxRender 1.x uses).
//!
//! - Absorption coefficients of the atmosphere for the sun's transmittance, as tabulated in
//!   Preetham, Shirley & Smits, "A Practical Analytic Model for Daylight" (SIGGRAPH 1999),
//!   after Iqbal, "An Introduction to Solar Radiation" (1983): ozone `k_o` (p. 127), uniformly
//!   mixed gases `k_g` and water vapour `k_wa` (p. 130), in cm⁻¹, at irregular wavelengths.
//!   LuxRender reads 64 ozone pairs (its amplitude table has a 65th, unused value).
//! - The sun's spectral radiance outside the atmosphere, 380–750 nm every 10 nm, in
//!   W·m⁻²·sr⁻¹·nm⁻¹ (LuxRender's `sun_solAmplitudes`).
//! - The CIE daylight basis functions S0, S1, S2 (CIE 15, D-illuminant components),
//!   300–830 nm every 10 nm, from which a sky chromaticity (x, y) becomes a spectrum.
#![allow(clippy::excessive_precision)]

/// Wavelengths (nm) of the ozone absorption table.
#[rustfmt::skip]
pub const OZONE_NM: [f32; 64] = [
    300.0, 305.0, 310.0, 315.0, 320.0, 325.0, 330.0, 335.0, 340.0, 345.0, 350.0, 355.0,
    445.0, 450.0, 455.0, 460.0, 465.0, 470.0, 475.0, 480.0, 485.0, 490.0, 495.0,
    500.0, 505.0, 510.0, 515.0, 520.0, 525.0, 530.0, 535.0, 540.0, 545.0,
    550.0, 555.0, 560.0, 565.0, 570.0, 575.0, 580.0, 585.0, 590.0, 595.0,
    600.0, 605.0, 610.0, 620.0, 630.0, 640.0, 650.0, 660.0, 670.0, 680.0, 690.0,
    700.0, 710.0, 720.0, 730.0, 740.0, 750.0, 760.0, 770.0, 780.0, 790.0,
];

/// Ozone absorption coefficient k_o (cm⁻¹) at [`OZONE_NM`].
#[rustfmt::skip]
pub const OZONE_K: [f32; 64] = [
    10.0, 4.8, 2.7, 1.35, 0.8, 0.380, 0.160, 0.075, 0.04, 0.019, 0.007, 0.0,
    0.003, 0.003, 0.004, 0.006, 0.008, 0.009, 0.012, 0.014, 0.017, 0.021, 0.025,
    0.03, 0.035, 0.04, 0.045, 0.048, 0.057, 0.063, 0.07, 0.075, 0.08,
    0.085, 0.095, 0.103, 0.110, 0.12, 0.122, 0.12, 0.118, 0.115, 0.12,
    0.125, 0.130, 0.12, 0.105, 0.09, 0.079, 0.067, 0.057, 0.048, 0.036, 0.028,
    0.023, 0.018, 0.014, 0.011, 0.010, 0.009, 0.007, 0.004, 0.0, 0.0,
];

/// Wavelengths (nm) of the mixed-gases absorption table.
pub const GAS_NM: [f32; 4] = [759.0, 760.0, 770.0, 771.0];
/// Uniformly mixed gases absorption coefficient k_g (cm⁻¹) at [`GAS_NM`].
pub const GAS_K: [f32; 4] = [0.0, 3.0, 0.210, 0.0];

/// Wavelengths (nm) of the water-vapour absorption table.
#[rustfmt::skip]
pub const WATER_NM: [f32; 13] = [
    689.0, 690.0, 700.0, 710.0, 720.0, 730.0, 740.0, 750.0, 760.0, 770.0, 780.0, 790.0, 800.0,
];
/// Water vapour absorption coefficient k_wa (cm⁻¹) at [`WATER_NM`].
#[rustfmt::skip]
pub const WATER_K: [f32; 13] = [
    0.0, 0.160e-1, 0.240e-1, 0.125e-1, 0.100e+1, 0.870, 0.610e-1, 0.100e-2, 0.100e-4,
    0.100e-4, 0.600e-3, 0.175e-1, 0.360e-1,
];

/// First wavelength (nm) of [`SOLAR_RADIANCE`].
pub const SOLAR_START: f32 = 380.0;
/// Last wavelength (nm) of [`SOLAR_RADIANCE`] (38 values, 10 nm apart).
pub const SOLAR_END: f32 = 750.0;
/// Extraterrestrial spectral radiance of the sun (W·m⁻²·sr⁻¹·nm⁻¹), 380–750 nm by 10 nm.
#[rustfmt::skip]
pub const SOLAR_RADIANCE: [f32; 38] = [
    16550.0, 16230.0, 21120.0, 25880.0, 25820.0, 24230.0, 26760.0, 29660.0, 30540.0, 30060.0,
    30660.0, 28830.0, 28710.0, 27820.0, 27100.0, 27230.0, 26360.0, 25500.0, 25060.0, 25310.0,
    25350.0, 25130.0, 24630.0, 24170.0, 23680.0, 23210.0, 22820.0, 22340.0, 21970.0, 21530.0,
    21100.0, 20730.0, 20240.0, 19870.0, 19430.0, 19070.0, 18630.0, 18260.0,
];

/// First wavelength (nm) of the daylight basis tables.
pub const DAYLIGHT_START: f32 = 300.0;
/// Last wavelength (nm) of the daylight basis tables (54 values, 10 nm apart).
pub const DAYLIGHT_END: f32 = 830.0;

/// CIE daylight component S0 (mean daylight), 300–830 nm by 10 nm.
#[rustfmt::skip]
pub const DAYLIGHT_S0: [f32; 54] = [
    0.04, 6.0, 29.6, 55.3, 57.3, 61.8, 61.5, 68.8, 63.4, 65.8,
    94.8, 104.8, 105.9, 96.8, 113.9, 125.6, 125.5, 121.3, 121.3, 113.5,
    113.1, 110.8, 106.5, 108.8, 105.3, 104.4, 100.0, 96.0, 95.1, 89.1,
    90.5, 90.3, 88.4, 84.0, 85.1, 81.9, 82.6, 84.9, 81.3, 71.9,
    74.3, 76.4, 63.3, 71.7, 77.0, 65.2, 47.7, 68.6, 65.0, 66.0,
    61.0, 53.3, 58.9, 61.9,
];

/// CIE daylight component S1 (yellow–blue variation).
#[rustfmt::skip]
pub const DAYLIGHT_S1: [f32; 54] = [
    0.02, 4.5, 22.4, 42.0, 40.6, 41.6, 38.0, 42.4, 38.5, 35.0,
    43.4, 46.3, 43.9, 37.1, 36.7, 35.9, 32.6, 27.9, 24.3, 20.1,
    16.2, 13.2, 8.6, 6.1, 4.2, 1.9, 0.0, -1.6, -3.5, -3.5,
    -5.8, -7.2, -8.6, -9.5, -10.9, -10.7, -12.0, -14.0, -13.6, -12.0,
    -13.3, -12.9, -10.6, -11.6, -12.2, -10.2, -7.8, -11.2, -10.4, -10.6,
    -9.7, -8.3, -9.3, -9.8,
];

/// CIE daylight component S2 (pink–green variation).
#[rustfmt::skip]
pub const DAYLIGHT_S2: [f32; 54] = [
    0.0, 2.0, 4.0, 8.5, 7.8, 6.7, 5.3, 6.1, 3.0, 1.2,
    -1.1, -0.5, -0.7, -1.2, -2.6, -2.9, -2.8, -2.6, -2.6, -1.8,
    -1.5, -1.3, -1.2, -1.0, -0.5, -0.3, 0.0, 0.2, 0.5, 2.1,
    3.2, 4.1, 4.7, 5.1, 6.7, 7.3, 8.6, 9.8, 10.2, 8.3,
    9.6, 8.5, 7.0, 7.6, 8.0, 6.7, 5.2, 7.4, 6.8, 7.0,
    6.4, 5.5, 6.1, 6.5,
];

/// Linear interpolation in a table sampled evenly from `start` to `end` (zero outside, as
/// LuxRender's regular spectra are).
pub fn sample_regular(table: &[f32], start: f32, end: f32, nm: f32) -> f32 {
    let n = table.len();
    if n < 2 || !(start..=end).contains(&nm) {
        return 0.0;
    }
    let x = (nm - start) / (end - start) * (n - 1) as f32;
    let i = (x as usize).min(n - 2);
    let t = x - i as f32;
    match (table.get(i), table.get(i + 1)) {
        (Some(a), Some(b)) => a * (1.0 - t) + b * t,
        _ => 0.0,
    }
}

/// Linear interpolation in a table given at increasing wavelengths `nms` (zero outside).
pub fn sample_irregular(nms: &[f32], values: &[f32], nm: f32) -> f32 {
    let (Some(&first), Some(&last)) = (nms.first(), nms.last()) else {
        return 0.0;
    };
    if !(first..=last).contains(&nm) {
        return 0.0;
    }
    let k = nms.partition_point(|&w| w < nm);
    match (nms.get(k), values.get(k)) {
        (Some(&w), Some(&v)) if w == nm || k == 0 => v,
        (Some(&w1), Some(&v1)) => match (nms.get(k - 1), values.get(k - 1)) {
            (Some(&w0), Some(&v0)) => v0 + (v1 - v0) * (nm - w0) / (w1 - w0),
            _ => 0.0,
        },
        _ => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation() {
        assert_eq!(
            sample_regular(&SOLAR_RADIANCE, SOLAR_START, SOLAR_END, 380.0),
            16550.0
        );
        assert_eq!(
            sample_regular(&SOLAR_RADIANCE, SOLAR_START, SOLAR_END, 750.0),
            18260.0
        );
        assert_eq!(
            sample_regular(&SOLAR_RADIANCE, SOLAR_START, SOLAR_END, 375.0),
            0.0
        );
        let mid = sample_regular(&SOLAR_RADIANCE, SOLAR_START, SOLAR_END, 385.0);
        assert!((mid - 16390.0).abs() < 1e-2, "{mid}");
        assert_eq!(sample_irregular(&OZONE_NM, &OZONE_K, 550.0), 0.085);
        // Between 355 (0.0) and 445 (0.003).
        let v = sample_irregular(&OZONE_NM, &OZONE_K, 400.0);
        assert!((v - 0.0015).abs() < 1e-6, "{v}");
        assert!((sample_irregular(&OZONE_NM, &OZONE_K, 615.0) - 0.1125).abs() < 1e-6);
        assert_eq!(sample_irregular(&GAS_NM, &GAS_K, 700.0), 0.0);
        assert_eq!(sample_irregular(&WATER_NM, &WATER_K, 300.0), 0.0);
        assert_eq!(sample_irregular(&OZONE_NM, &OZONE_K, 300.0), 10.0);
    }
}
