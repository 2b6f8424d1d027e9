//! Smits-style RGB-to-spectrum basis for illuminants, as LuxRender uses it (`RGBIllumSPD`):
//! seven spectra (white, cyan, magenta, yellow, red, green, blue), 32 bins from 380 to 720 nm,
//! linearly interpolated, generated for a D65 white point and scaled by 0.86445.
//!
//! An RGB triple becomes `min * white + (mid - min) * secondary + (max - mid) * primary`
//! where the secondary is the mix of the two largest channels and the primary the largest.
#![allow(clippy::excessive_precision)]

/// Basis start/end wavelengths (nm) and bin count.
pub const START: f32 = 380.0;
pub const END: f32 = 720.0;
pub const BINS: usize = 32;
/// LuxRender's global scale of the illuminant basis.
pub const ILLUM_SCALE: f32 = 0.86445;

#[rustfmt::skip]
pub const WHITE: [f32; BINS] = [
    1.156523, 1.156723, 1.156620, 1.155578, 1.156218, 1.156767, 1.156802, 1.156768,
    1.156356, 1.156705, 1.156513, 1.156434, 1.156802, 1.147315, 1.133932, 1.129388,
    1.129052, 1.050486, 1.045970, 0.993667, 0.956017, 0.924675, 0.914999, 0.899395,
    0.895425, 0.888706, 0.882228, 0.879983, 0.876352, 0.880004, 0.880657, 0.883047,
];
#[rustfmt::skip]
pub const CYAN: [f32; BINS] = [
    1.133448, 1.126676, 1.134683, 1.135740, 1.135637, 1.136115, 1.136218, 1.136482,
    1.135511, 1.136406, 1.136036, 1.136012, 1.135427, 1.136310, 1.135545, 1.135373,
    1.134950, 1.111111, 0.905987, 0.611608, 0.295398, 0.095954, -0.011651, -0.012145,
    -0.011148, -0.011998, -0.005051, -0.007998, -0.009472, -0.005533, -0.004543, -0.012541,
];
#[rustfmt::skip]
pub const MAGENTA: [f32; BINS] = [
    1.037189, 1.058754, 1.076727, 1.076271, 1.079529, 1.074364, 1.072703, 1.073245,
    1.082376, 1.084055, 0.956076, 0.551979, 0.084191, 0.000088, -0.002309, -0.001125,
    0.0, -0.000273, 0.014466, 0.258831, 0.529080, 0.909666, 1.069057, 1.088733,
    1.063762, 1.020181, 1.026220, 1.078309, 0.983338, 1.070725, 1.063425, 1.015088,
];
#[rustfmt::skip]
pub const YELLOW: [f32; BINS] = [
    0.002776, 0.003967, -0.000146, 0.000362, -0.000258, -0.000050, -0.000244, -0.000078,
    0.049690, 0.485160, 1.029573, 1.033321, 1.036810, 1.036488, 1.036543, 1.036860,
    1.036565, 1.036394, 1.036721, 1.036524, 1.036153, 1.034879, 1.004273, 0.842185,
    0.737594, 0.658532, 0.605317, 0.595498, 0.594193, 0.565177, 0.560612, 0.582286,
];
#[rustfmt::skip]
pub const RED: [f32; BINS] = [
    0.054711, 0.055609, 0.060756, 0.056233, 0.046170, 0.038013, 0.024424, 0.003898,
    -0.000561, 0.000965, 0.000373, -0.000434, -0.000094, -0.000124, -0.000145, -0.000200,
    -0.000499, 0.027255, 0.160674, 0.350698, 0.573575, 0.763921, 0.891445, 0.963946,
    0.988795, 0.998974, 0.986051, 0.995325, 0.974335, 0.991344, 0.988663, 0.997139,
];
#[rustfmt::skip]
pub const GREEN: [f32; BINS] = [
    0.025168, 0.039427, 0.006206, 0.007112, 0.000218, 0.0, -0.021623, 0.015670,
    0.002802, 0.324948, 1.016492, 1.032948, 1.032159, 1.035867, 1.015124, 1.033808,
    1.037137, 1.036138, 1.022982, 0.969103, -0.005179, 0.001113, 0.006668, 0.000740,
    0.021592, 0.005148, 0.001456, 0.000164, -0.006463, 0.010251, 0.042387, 0.021253,
];
#[rustfmt::skip]
pub const BLUE: [f32; BINS] = [
    1.057049, 1.053847, 1.055049, 1.053041, 1.057993, 1.057844, 1.058313, 1.057971,
    1.056188, 1.057140, 1.042580, 0.326031, -0.001926, -0.001296, -0.001436, -0.001296,
    -0.001923, 0.001262, -0.001610, -0.001303, -0.001767, -0.001233, 0.010317, 0.031285,
    0.088774, 0.138736, 0.155351, 0.148785, 0.166243, 0.169976, 0.157697, 0.190691,
];

/// Value of a basis spectrum at `nm` (zero outside 380–720 nm), without the global scale.
pub fn sample(basis: &[f32; BINS], nm: f32) -> f32 {
    if !(START..=END).contains(&nm) {
        return 0.0;
    }
    let x = (nm - START) / (END - START) * (BINS - 1) as f32;
    let i = (x as usize).min(BINS - 2);
    let t = x - i as f32;
    basis[i] * (1.0 - t) + basis[i + 1] * t
}

/// Smits decomposition of an RGB triple: weights of (white, cyan, magenta, yellow, red, green,
/// blue), in that order. Exactly LuxRender's case analysis.
pub fn decompose(r: f32, g: f32, b: f32) -> [f32; 7] {
    let mut w = [0.0f32; 7];
    if r <= g && r <= b {
        w[0] = r;
        if g <= b {
            w[1] = g - r;
            w[6] = b - g;
        } else {
            w[1] = b - r;
            w[5] = g - b;
        }
    } else if g <= r && g <= b {
        w[0] = g;
        if r <= b {
            w[2] = r - g;
            w[6] = b - r;
        } else {
            w[2] = b - g;
            w[4] = r - b;
        }
    } else {
        w[0] = b;
        if r <= g {
            w[3] = r - b;
            w[5] = g - r;
        } else {
            w[3] = g - b;
            w[4] = r - g;
        }
    }
    w
}

/// The seven basis spectra in the order of [`decompose`].
pub const BASES: [&[f32; BINS]; 7] = [&WHITE, &CYAN, &MAGENTA, &YELLOW, &RED, &GREEN, &BLUE];
