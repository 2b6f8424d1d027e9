//! Fresnel reflectances: dielectric (unpolarised, exact), conductor (complex index n + ik,
//! per channel) and Schlick's approximation, plus LuxRender's approximate conductor index
//! from a reflectance colour (`FresnelApproxEta`/`FresnelApproxK`, used by shinymetal).

use crate::spectrum::Rgb;

/// Reflectance of a dielectric interface for light arriving at `cos_i` (> 0) from a medium of
/// index `eta_i` into `eta_t`.
pub fn dielectric(cos_i: f32, eta_i: f32, eta_t: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin_t = eta_i / eta_t * (1.0 - cos_i * cos_i).max(0.0).sqrt();
    if sin_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin_t * sin_t).max(0.0).sqrt();
    let r_par = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
    let r_perp = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
    0.5 * (r_par * r_par + r_perp * r_perp)
}

/// Reflectance of a conductor of complex index `n + i k` (from air) at `cos_i`.
pub fn conductor(cos_i: f32, n: Rgb, k: Rgb) -> Rgb {
    let c = cos_i.abs().min(1.0);
    let one = |n: f32, k: f32| {
        let c2 = c * c;
        let tmp = (n * n + k * k) * c2;
        let r_par = (tmp - 2.0 * n * c + 1.0) / (tmp + 2.0 * n * c + 1.0);
        let tmp_f = n * n + k * k;
        let r_perp = (tmp_f - 2.0 * n * c + c2) / (tmp_f + 2.0 * n * c + c2);
        0.5 * (r_par + r_perp)
    };
    Rgb::new(one(n.r, k.r), one(n.g, k.g), one(n.b, k.b))
}

/// Schlick's approximation with normal-incidence reflectance `r0`.
pub fn schlick(cos: f32, r0: Rgb) -> Rgb {
    let m = (1.0 - cos.abs().min(1.0)).powi(5);
    r0 + (Rgb::WHITE - r0) * m
}

/// Conductor index (n, k) that reflects `r` at normal incidence (LuxRender's approximation).
pub fn approx_conductor(r: Rgb) -> (Rgb, Rgb) {
    let r = r.map(|v| v.clamp(0.0, 0.999));
    let n = r.map(|v| (1.0 + v.sqrt()) / (1.0 - v.sqrt()));
    let k = r.map(|v| 2.0 * (v / (1.0 - v)).sqrt());
    (n, k)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dielectric_normal_incidence_is_schlick_r0() {
        for n in [1.33f32, 1.5, 2.4] {
            let r0 = ((n - 1.0) / (n + 1.0)).powi(2);
            assert!((dielectric(1.0, 1.0, n) - r0).abs() < 1e-6);
            assert!((dielectric(1.0, n, 1.0) - r0).abs() < 1e-6);
        }
        // Total internal reflection beyond the critical angle.
        assert_eq!(dielectric(0.1, 1.5, 1.0), 1.0);
    }

    #[test]
    fn conductor_with_zero_k_matches_dielectric_and_approx_inverts() {
        let r = conductor(1.0, Rgb::splat(1.5), Rgb::BLACK);
        assert!((r.r - 0.04).abs() < 1e-5);
        // LuxRender's approximation reflects a little more than asked (the k term).
        let target = Rgb::new(0.9, 0.6, 0.2);
        let (n, k) = approx_conductor(target);
        let back = conductor(1.0, n, k);
        for i in 0..3 {
            assert!(
                back[i] >= target[i] && back[i] - target[i] < 0.06,
                "{back:?}"
            );
        }
    }
}
