//! The RGB renderer's reading of absorbing optical constants n(λ), k(λ) (a metal's n, k
//! table, [`super::nk::NkTable::to_rgb`]): per channel the (n, k)
//! whose conductor reflectance best reproduces the table's own, computed spectrally.
//!
//! Averaging n and k over each channel's band, the simple reading, does not give the colour
//! the table reflects: reflectance is not linear in n and k, and gold came out about 5 % off
//! per channel. Here, for each of a few incidence angles, the table's reflectance spectrum
//! R(λ, θ) is lit by white light and converted to the renderer's RGB (as any reflectance
//! spectrum is, [`super::xyz::reflectance_xyz`]); each channel then gets the (n, k) that
//! reflects exactly that channel's value at normal incidence and comes closest at the other
//! angles (squared errors weighted by the cosine). The (n, k) are parameterised by
//! normal-incidence reflectance r and edge tint g (Gulbrandsen's mapping, JCGT 3(4), 2014):
//! r is fixed by the normal-incidence target and g is searched over [0, 1].
//!
//! ```text
//! n, k (λ) --R(λ, θ)--> reflectance_xyz --xyz_to_rgb--> targets per channel and angle
//!   --r from θ = 0, g by search--> (n, k) per channel
//! ```

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
pub const COSINES: [f32; 6] = [1.0, 0.8, 0.6, 0.4, 0.25, 0.1];

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
fn targets(at: &impl Fn(f32) -> (f32, f32)) -> [[f32; 3]; COSINES.len()] {
    COSINES.map(|c| spectral_rgb_reflectance(at, c))
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
    (0..=G_STEPS)
        .map(|i| from_reflectance_and_tint(r, i as f32 / G_STEPS as f32))
        .map(|(n, k)| (error(n, k, &want), (n, k)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map_or((1.0, 0.0), |(_, nk)| nk)
}

/// RGB (n, k) of absorbing optical constants `at` (n, k per wavelength in nm): per channel the fitted (n, k) (see the module
/// documentation), or the given band averages `avg` where those reflect the table's colour
/// more closely over the angles (silver's nearly flat spectrum, where the two-parameter fit
/// trades grazing accuracy for an exact normal incidence).
pub fn fit(at: impl Fn(f32) -> (f32, f32), avg: ([f32; 3], [f32; 3])) -> ([f32; 3], [f32; 3]) {
    let want = targets(&at);
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

/// The RGB reflectance of (n, k) per channel at `cos`.
#[cfg(test)]
pub(super) fn rgb_reflectance(n: [f32; 3], k: [f32; 3], cos: f32) -> [f32; 3] {
    [0, 1, 2].map(|c| conductor_reflectance(cos, n[c], k[c]))
}

/// The reflectance of the optical constants `at` at `cos` in the renderer's RGB: its reflectance spectrum lit
/// by white light.
pub fn spectral_rgb_reflectance(at: &impl Fn(f32) -> (f32, f32), cos: f32) -> [f32; 3] {
    let xyz = reflectance_xyz(|nm| {
        let (n, k) = at(nm);
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

    /// Constant n and k are reproduced: the fit finds the same reflectances.
    #[test]
    fn a_grey_metal_keeps_its_reflectance() {
        let (n, k) = fit(|_| (0.5, 3.0), ([1.0; 3], [0.0; 3]));
        for c in COSINES {
            let want = conductor_reflectance(c, 0.5, 3.0);
            for got in rgb_reflectance(n, k, c) {
                assert!((got - want).abs() < 0.01, "cos {c}: {got} vs {want}");
            }
        }
    }
}
