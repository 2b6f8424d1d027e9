//! Fresnel reflectances: dielectric (unpolarised, exact), conductor (complex index n + ik,
//! per channel), Schlick's approximation, LuxRender's approximate conductor index from a
//! reflectance colour (`FresnelApproxEta`/`FresnelApproxK`, used by shinymetal), and
//! LuxRender's general Fresnel term ([`FresnelGeneral`]: a dielectric, conductor or full
//! complex interface chosen from n and k, as metal2, shinymetal and the media of glass2 use it).

use crate::spectrum::nk_rgb::conductor_reflectance;
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
    let one = |n, k| conductor_reflectance(cos_i, n, k);
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

/// Which of LuxRender's Fresnel formulas a [`FresnelGeneral`] uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FresnelModel {
    /// k negligible: the exact dielectric formula (both sides of the interface).
    Dielectric,
    /// n ≤ k everywhere: the conductor formula, front side only.
    Conductor,
    /// The full complex-index formula (both sides).
    Full,
}

/// LuxRender's `FresnelGeneral`: an interface of relative complex index `eta + i k`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FresnelGeneral {
    pub model: FresnelModel,
    pub eta: Rgb,
    pub k: Rgb,
}

impl FresnelGeneral {
    /// The model LuxRender picks for (eta, k) (`AUTO_FRESNEL`): dielectric when eta > 10 k in
    /// every channel, conductor when eta ≤ k in every channel, full otherwise.
    pub fn auto(eta: Rgb, k: Rgb) -> FresnelGeneral {
        let all = |f: &dyn Fn(f32, f32) -> bool| (0..3).all(|i| f(eta[i], k[i]));
        let model = if all(&|e, k| e > 10.0 * k) {
            FresnelModel::Dielectric
        } else if all(&|e, k| e <= k) {
            FresnelModel::Conductor
        } else {
            FresnelModel::Full
        };
        FresnelGeneral { model, eta, k }
    }

    /// A constant `float fresnel` value: a dielectric of that index (LuxRender's constant
    /// fresnel texture).
    pub fn dielectric(eta: f32) -> FresnelGeneral {
        FresnelGeneral {
            model: FresnelModel::Dielectric,
            eta: Rgb::splat(eta),
            k: Rgb::BLACK,
        }
    }

    /// Reflectance for light arriving at signed `cos_i` (negative: from the inside).
    pub fn eval(&self, cos_i: f32) -> Rgb {
        let cos_i = cos_i.clamp(-1.0, 1.0);
        if self.model == FresnelModel::Conductor {
            return if cos_i > 0.0 {
                conductor(cos_i, self.eta, self.k)
            } else {
                Rgb::BLACK
            };
        }
        let mut out = [0.0f32; 3];
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.channel(cos_i, self.eta[i], self.k[i]);
        }
        let v = Rgb::from_array(out);
        if v.is_finite() {
            v.map(|x| x.clamp(0.0, 1.0))
        } else {
            Rgb::BLACK
        }
    }

    fn channel(&self, cos_i: f32, eta: f32, k: f32) -> f32 {
        let mut sin2_t = (1.0 - cos_i * cos_i).max(0.0);
        if cos_i > 0.0 {
            sin2_t /= eta * eta;
        } else {
            sin2_t *= eta * eta;
        }
        let cos2_t = 1.0 - sin2_t.clamp(0.0, 1.0);
        let c = cos_i.abs();
        match (self.model, cos_i > 0.0) {
            (FresnelModel::Dielectric, true) => fr_dielectric(c, cos2_t.sqrt(), eta),
            (FresnelModel::Dielectric, false) => fr_dielectric(c, cos2_t.sqrt(), 1.0 / eta),
            (_, front) => {
                let a = 2.0 * k * k * sin2_t.clamp(0.0, 1.0);
                let cos_t = ((cos2_t + (cos2_t * cos2_t + a * a).sqrt()) * 0.5).sqrt();
                if front {
                    fr_full(c, cos_t, eta, k)
                } else {
                    let d2 = eta * eta + k * k;
                    fr_full(c, cos_t, eta / d2, -k / d2)
                }
            }
        }
    }
}

/// Dielectric reflectance from both cosines and the relative index (LuxRender's `FrDiel2`).
fn fr_dielectric(cos_i: f32, cos_t: f32, eta: f32) -> f32 {
    let par = (cos_t - eta * cos_i) / (cos_t + eta * cos_i);
    let perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (par * par + perp * perp)
}

/// Reflectance of a complex interface (LuxRender's `FrFull`).
fn fr_full(cos_i: f32, cos_t: f32, eta: f32, k: f32) -> f32 {
    let nk = eta * eta + k * k;
    let cross = 2.0 * cos_i * cos_t * eta;
    let tmp = nk * cos_i * cos_i + cos_t * cos_t;
    let par = (tmp - cross) / (tmp + cross);
    let tmp_f = nk * cos_t * cos_t + cos_i * cos_i;
    let perp = (tmp_f - cross) / (tmp_f + cross);
    0.5 * (par + perp)
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

    #[test]
    fn general_fresnel_agrees_with_the_exact_formulas() {
        // Dielectric model: the exact formula from both sides, TIR inside.
        let g = FresnelGeneral::dielectric(1.5);
        for c in [1.0f32, 0.8, 0.3, 0.05] {
            assert!((g.eval(c).r - dielectric(c, 1.0, 1.5)).abs() < 1e-5, "{c}");
            assert!((g.eval(-c).g - dielectric(c, 1.5, 1.0)).abs() < 1e-5, "{c}");
        }
        assert_eq!(g.eval(-0.1), Rgb::WHITE);
        // Auto model choice: 5 + 0i is dielectric, gold-like n < k conductor, else full.
        assert_eq!(
            FresnelGeneral::auto(Rgb::splat(5.0), Rgb::BLACK).model,
            FresnelModel::Dielectric
        );
        let mixed = FresnelGeneral::auto(Rgb::new(0.2, 0.4, 2.5), Rgb::new(3.0, 2.4, 1.9));
        assert_eq!(mixed.model, FresnelModel::Full);
        let cond = FresnelGeneral::auto(Rgb::splat(0.2), Rgb::splat(3.0));
        assert_eq!(cond.model, FresnelModel::Conductor);
        assert_eq!(cond.eval(-0.5), Rgb::BLACK);
        // The full formula reduces to the conductor one at normal incidence.
        let full = FresnelGeneral {
            model: FresnelModel::Full,
            ..cond
        };
        let a = full.eval(1.0);
        let b = conductor(1.0, cond.eta, cond.k);
        assert!((a.r - b.r).abs() < 1e-5, "{a:?} {b:?}");
        // At grazing angles everything reflects.
        assert!(full.eval(1e-4).r > 0.99);
        // Hand value: n = 1.5, k = 0.408 (shinymetal's Ks 0.04) reflects 0.04 + k term.
        let (n, k) = approx_conductor(Rgb::splat(0.04));
        let s = FresnelGeneral::auto(n, k);
        assert_eq!(s.model, FresnelModel::Full);
        let want = ((1.5f32 - 1.0).powi(2) + k.r * k.r) / ((1.5f32 + 1.0).powi(2) + k.r * k.r);
        assert!(
            (s.eval(1.0).r - want).abs() < 1e-4,
            "{:?} {want}",
            s.eval(1.0)
        );
    }
}
