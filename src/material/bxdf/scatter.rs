//! LuxRender's `SchlickScatter`, the BSDF of the scatter material: the surface scatters like a
//! volume, in every direction, with Schlick's phase function
//! `p(θ) = (1 - k²) / (4π (1 + k cos θ)²)`, `k = g (1.55 - 0.55 g²)` per channel and θ the
//! angle between `wo` and `wi` (so positive g scatters forward, through the surface).
//!
//! LuxRender's value has no cosine factor; with this renderer's convention (the integrator
//! multiplies `f` by |cos θi|) `f = Kd p / |cos θi|`, so that `f |cos θi| / pdf = Kd` for
//! grey `g`. Directions are sampled exactly from the phase function of the average `k`,
//! which is also the pdf.

use super::{avg, LocalSample};
use crate::spectrum::Rgb;
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug)]
pub struct SchlickScatter {
    pub r: Rgb,
    /// Schlick's k per channel.
    pub k: Rgb,
}

/// Schlick's phase function for `k` at cos θ between `wo` and `wi`.
fn phase(k: f32, cos: f32) -> f32 {
    let d = 1.0 + k * cos;
    (1.0 - k * k) / (4.0 * PI * d * d)
}

impl SchlickScatter {
    /// From the material's `Kd` and asymmetry `g` (each channel clamped to [-1, 1]).
    pub fn new(r: Rgb, g: Rgb) -> SchlickScatter {
        let g = g.map(|x| x.clamp(-1.0, 1.0));
        SchlickScatter {
            r,
            k: g.map(|x| x * (1.55 - 0.55 * x * x)),
        }
    }

    pub fn f(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        let ci = wi.z.abs();
        if ci == 0.0 {
            return Rgb::BLACK;
        }
        let c = wo.dot(wi);
        self.r * Rgb::new(phase(self.k.r, c), phase(self.k.g, c), phase(self.k.b, c)) / ci
    }

    pub fn pdf(&self, wo: Vec3A, wi: Vec3A) -> f32 {
        phase(avg(self.k), wo.dot(wi))
    }

    pub fn sample(&self, wo: Vec3A, u2: Vec2) -> Option<LocalSample> {
        let k = avg(self.k);
        // Inverse of the phase function's cdf in cos θ (with the sign of wo reversed).
        let cos = -(2.0 * u2.x + k - 1.0) / (2.0 * k * u2.x - k + 1.0);
        let cos = cos.clamp(-1.0, 1.0);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let phi = 2.0 * PI * u2.y;
        let x = wo.any_orthonormal_vector();
        let y = wo.cross(x);
        let wi = (x * (sin * phi.cos()) + y * (sin * phi.sin()) + wo * cos).normalize_or_zero();
        if wi == Vec3A::ZERO {
            return None;
        }
        let pdf = self.pdf(wo, wi);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        Some(LocalSample {
            wi,
            f: self.f(wo, wi),
            pdf,
            specular: false,
        })
    }
}
