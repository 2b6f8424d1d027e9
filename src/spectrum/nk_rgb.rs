//! The RGB renderer's reading of an absorbing n, k table (a metal): per channel the (n, k)
//! whose conductor reflectance best reproduces the table's own, computed spectrally.
//!
//! Averaging n and k over each channel's band, the simple reading, does not give the colour
//! the table reflects: reflectance is not linear in n and k, and gold came out about 5 % off
//! per channel. Here, for each of a few incidence angles, the table's reflectance spectrum
//! R(λ, θ) is lit by white light and converted to the renderer's RGB (as any reflectance
//! spectrum is, [`super::xyz::reflectance_xyz`]); each channel then gets the (n, k) that
//! reflects exactly that channel's value at normal incidence and comes closest at the other
//! angles (squared errors weighted by the cosine). The (n, k) are parameterised by normal-incidence reflectance r and edge tint g
//! (Gulbrandsen's mapping, JCGT 3(4), 2014): r is fixed by the normal-incidence target and g
//! is searched over [0, 1].
//!
//! ```text
//! NkTable --R(λ, θ)--> reflectance_xyz --xyz_to_rgb--> targets per channel and angle
//!   --r from θ = 0, g by search--> (n, k) per channel
//! ```

use super::nk::NkTable;
use super::xyz::{reflectance_xyz, xyz_to_rgb};

/// Reflectance of a conductor of complex index `n + i k` (from air) at `cos_i`, unpolarised
/// (the formula the renderer's conductor Fresnel term uses, channel by channel).
pub fn conductor_reflectance(cos_i: f32, n: f32, k: f32) -> f32 {
    let c = cos_i.abs().min(1.0);
    let c2 = c * c;
    let tmp = (n * n + k * k) * c2;
    let r_par = (tmp - 2.0 * n * c + 1.0) / (tmp + 2.0 * n * c + 1.0);
    let tmp_f = n * n + k * k;
    let r_perp = (tmp_f - 2.0 * n * c + c2) / (tmp_f + 2.0 * n * c + c2);
    0.5 * (r_par + r_perp)
}

/// The cosines of incidence the fit compares at; the first (normal incidence) is matched
/// exactly.
const COSINES: [f32; 6] = [1.0, 0.8, 0.6, 0.4, 0.25, 0.1];

/// Steps of the edge tint search over [0, 1].
const G_STEPS: u32 = 400;

/// (n, k) with normal-incidence reflectance `r` (< 1) and edge tint `g` in [0, 1].
fn from_reflectance_and_tint(r: f32, g: f32) -> (f32, f32) {
    let sr = r.sqrt();
    let n = g * (1.0 - r) / (1.0 + r) + (1.0 - g) * (1.0 + sr) / (1.0 - sr);
    let k2 = (r * (n + 1.0) * (n + 1.0) - (n - 1.0) * (n - 1.0)) / (1.0 - r);
    (n, k2.max(0.0).sqrt())
}

/// The table's reflectance in the renderer's RGB at each of [`COSINES`].
fn targets(t: &NkTable) -> [[f32; 3]; COSINES.len()] {
    COSINES.map(|c| spectral_rgb_reflectance(t, c))
}

/// Cosine-weighted squared error of (n, k)'s reflectances against `want` (one per cosine,
/// normal incidence left out: the fit matches it by construction).
fn error(n: f32, k: f32, want: &[f32; COSINES.len()]) -> f32 {
    COSINES[1..]
        .iter()
        .zip(&want[1..])
        .map(|(&c, &w)| c * (conductor_reflectance(c, n, k) - w).powi(2))
        .sum()
}

/// The (n, k) of one channel whose reflectances come closest to `want` (one per cosine)
/// with the normal-incidence one matched.
fn fit_channel(want: [f32; COSINES.len()]) -> (f32, f32) {
    let r = want[0].clamp(0.0, 0.999);
    let at = |g: f32| from_reflectance_and_tint(r, g);
    let best = (0..=G_STEPS)
        .map(|i| i as f32 / G_STEPS as f32)
        .min_by(|&a, &b| {
            let (ea, eb) = (at(a), at(b));
            error(ea.0, ea.1, &want).total_cmp(&error(eb.0, eb.1, &want))
        })
        .unwrap_or(0.0);
    at(best)
}

/// RGB (n, k) of an absorbing table: per channel the fitted (n, k) (see the module
/// documentation), or the given band averages `avg` where those reflect the table's colour
/// more closely over the angles (silver's nearly flat spectrum, where the two-parameter fit
/// trades grazing accuracy for an exact normal incidence).
pub fn fit(t: &NkTable, avg: ([f32; 3], [f32; 3])) -> ([f32; 3], [f32; 3]) {
    let want = targets(t);
    let mut n = [0.0; 3];
    let mut k = [0.0; 3];
    for ch in 0..3 {
        let w = want.map(|w| w[ch]);
        let fitted = fit_channel(w);
        let total = |(n, k): (f32, f32)| {
            let r = w[0].min(0.999);
            error(n, k, &w) + (conductor_reflectance(1.0, n, k) - r).powi(2)
        };
        let averaged = (avg.0[ch], avg.1[ch]);
        (n[ch], k[ch]) = if total(averaged) < total(fitted) {
            averaged
        } else {
            fitted
        };
    }
    (n, k)
}

/// The RGB reflectance of (n, k) per channel at `cos` (tests and benches).
pub fn rgb_reflectance(n: [f32; 3], k: [f32; 3], cos: f32) -> [f32; 3] {
    [0, 1, 2].map(|c| conductor_reflectance(cos, n[c], k[c]))
}

/// The table's own reflectance at `cos` in the renderer's RGB: its reflectance spectrum lit
/// by white light.
pub fn spectral_rgb_reflectance(t: &NkTable, cos: f32) -> [f32; 3] {
    let xyz = reflectance_xyz(|nm| {
        let (n, k) = t.at(nm);
        f64::from(conductor_reflectance(cos, n, k))
    });
    xyz_to_rgb(xyz.map(|v| v as f32)).to_array()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflectance_and_tint_give_the_normal_incidence_reflectance() {
        for r in [0.05f32, 0.5, 0.9] {
            for g in [0.0f32, 0.5, 1.0] {
                let (n, k) = from_reflectance_and_tint(r, g);
                assert!(
                    (conductor_reflectance(1.0, n, k) - r).abs() < 1e-4,
                    "{r} {g}"
                );
            }
        }
    }

    /// A table with constant n and k is reproduced: the fit finds the same reflectances.
    #[test]
    fn a_grey_table_keeps_its_reflectance() {
        let t = NkTable {
            wl: vec![300.0, 900.0],
            n: vec![0.5, 0.5],
            k: vec![3.0, 3.0],
        };
        let (n, k) = fit(&t, ([1.0; 3], [0.0; 3]));
        for c in COSINES {
            let want = conductor_reflectance(c, 0.5, 3.0);
            for got in rgb_reflectance(n, k, c) {
                assert!((got - want).abs() < 0.01, "cos {c}: {got} vs {want}");
            }
        }
    }
}

#[cfg(test)]
mod preset_tests {
    use super::*;

    /// RMS over the channels and [`COSINES`] of (reflectance of (n, k) − the table's own),
    /// each angle weighted by its cosine (what it contributes to reflected irradiance).
    fn weighted_rms(t: &NkTable, n: [f32; 3], k: [f32; 3]) -> f32 {
        let (mut se, mut w) = (0.0f32, 0.0f32);
        for c in COSINES {
            // A saturated colour can leave the gamut (gold's red is 1.01): a Fresnel
            // reflectance stops just below 1.
            let want = spectral_rgb_reflectance(t, c).map(|v| v.min(0.999));
            let got = rgb_reflectance(n, k, c);
            for ch in 0..3 {
                se += c * (got[ch] - want[ch]).powi(2);
                w += c;
            }
        }
        (se / w).sqrt()
    }

    /// The metal presets: the RGB (n, k) reflect the table's spectral RGB colour within 0.01
    /// RMS over the angles, never further than band averages of n and k, which miss gold's and copper's colour by 0.05 and 0.02 RMS.
    #[test]
    fn presets_reflect_their_spectral_colour() {
        for name in ["gold", "copper", "silver", "aluminium", "amorphous carbon"] {
            let t = NkTable::preset(name).unwrap();
            let (n, k) = t.to_rgb();
            let (an, ak) = t.band_averages();
            if name == "gold" || name == "copper" {
                // Fitted: exact at normal incidence.
                let want = spectral_rgb_reflectance(&t, 1.0).map(|v| v.min(0.999));
                let got = rgb_reflectance(n, k, 1.0);
                for ch in 0..3 {
                    assert!(
                        (got[ch] - want[ch]).abs() < 1e-3,
                        "{name}: {got:?} vs {want:?}"
                    );
                }
            }
            let (fitted, averaged) = (weighted_rms(&t, n, k), weighted_rms(&t, an, ak));
            eprintln!("{name}: weighted RMS fitted {fitted:.4}, band averages {averaged:.4}");
            assert!(
                fitted < 0.01 && fitted <= averaged,
                "{name}: {fitted} vs {averaged}"
            );
            if name == "gold" || name == "copper" {
                assert!(averaged > 0.015, "{name}: band averages off by {averaged}");
            }
        }
    }
}
