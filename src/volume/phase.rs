//! The Henyey–Greenstein phase function that every scattering medium uses: evaluation and
//! importance sampling for an asymmetry `g` in (-1, 1) (g > 0 scatters forward).
//!
//! Directions are propagation directions: `d_in` is where the light was travelling before the
//! scattering event, `d_out` where it travels after; cos θ = d_in · d_out.

use crate::geometry::frame::coordinate_system;
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;

/// |g| below this is treated as isotropic (the sampling formula divides by g).
const ISOTROPIC: f32 = 1e-3;

/// A Henyey–Greenstein lobe.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HenyeyGreenstein {
    pub g: f32,
}

impl HenyeyGreenstein {
    /// A lobe with `g` clamped into (-0.99, 0.99) (|g| → 1 is a Dirac).
    pub fn new(g: f32) -> HenyeyGreenstein {
        let g = if g.is_finite() { g } else { 0.0 };
        HenyeyGreenstein {
            g: g.clamp(-0.99, 0.99),
        }
    }

    /// Density (per steradian) of scattering by angle θ with cos θ = `cos`.
    pub fn p(&self, cos: f32) -> f32 {
        let g = self.g;
        let denom = 1.0 + g * g - 2.0 * g * cos;
        (1.0 - g * g) / (4.0 * PI * denom * denom.max(1e-12).sqrt())
    }

    /// Density of scattering from propagation direction `d_in` into `d_out` (both unit).
    pub fn eval(&self, d_in: Vec3A, d_out: Vec3A) -> f32 {
        self.p(d_in.dot(d_out))
    }

    /// Samples an outgoing propagation direction for `d_in` (unit); returns it with its
    /// density (which equals the phase value: the sampling is exact).
    pub fn sample(&self, d_in: Vec3A, u: Vec2) -> (Vec3A, f32) {
        let g = self.g;
        let cos = if g.abs() < ISOTROPIC {
            1.0 - 2.0 * u.x
        } else {
            let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u.x);
            ((1.0 + g * g - s * s) / (2.0 * g)).clamp(-1.0, 1.0)
        };
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let (t, b) = coordinate_system(d_in);
        let d = (t * (sin * phi.cos()) + b * (sin * phi.sin()) + d_in * cos).normalize_or_zero();
        (d, self.p(cos))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ p dω over the sphere, by a midpoint rule in cos θ.
    fn integral(g: f32) -> f32 {
        let hg = HenyeyGreenstein::new(g);
        let n = 20000;
        (0..n)
            .map(|i| {
                let c = -1.0 + (i as f32 + 0.5) * 2.0 / n as f32;
                hg.p(c) * 2.0 * PI * (2.0 / n as f32)
            })
            .sum()
    }

    #[test]
    fn normalised_for_several_asymmetries() {
        for g in [-0.7, -0.2, 0.0, 0.3, 0.8] {
            assert!((integral(g) - 1.0).abs() < 1e-2, "g={g}: {}", integral(g));
        }
    }

    #[test]
    fn sampled_mean_cosine_is_g() {
        for g in [-0.5f32, 0.0, 0.6] {
            let hg = HenyeyGreenstein::new(g);
            let d = Vec3A::new(0.0, 0.0, 1.0);
            let n = 64;
            let mut sum = 0.0;
            for i in 0..n {
                for j in 0..n {
                    let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                    let (w, pdf) = hg.sample(d, u);
                    assert!((pdf - hg.eval(d, w)).abs() < 1e-3 * pdf.max(1.0));
                    sum += w.dot(d);
                }
            }
            let mean = sum / (n * n) as f32;
            assert!((mean - g).abs() < 0.02, "g={g}: mean cos {mean}");
        }
    }
}
