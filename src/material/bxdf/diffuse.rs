//! Lambertian and Oren–Nayar reflection (`sigma` in degrees, LuxRender's matte), both
//! cosine-sampled on the side of `wo`.

use super::{cosine_hemisphere, same_hemisphere, LocalSample};
use crate::spectrum::Rgb;
use glam::{Vec2, Vec3A};
use std::f32::consts::FRAC_1_PI;

#[derive(Clone, Copy, Debug)]
pub struct Diffuse {
    pub r: Rgb,
    /// Oren–Nayar A and B; (1, 0) is Lambertian.
    pub a: f32,
    pub b: f32,
}

impl Diffuse {
    pub fn lambert(r: Rgb) -> Diffuse {
        Diffuse { r, a: 1.0, b: 0.0 }
    }

    /// Oren–Nayar with roughness `sigma_deg` (degrees); 0 gives Lambertian.
    pub fn oren_nayar(r: Rgb, sigma_deg: f32) -> Diffuse {
        let s = sigma_deg.to_radians();
        let s2 = s * s;
        Diffuse {
            r,
            a: 1.0 - s2 / (2.0 * (s2 + 0.33)),
            b: 0.45 * s2 / (s2 + 0.09),
        }
    }

    pub fn f(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        if !same_hemisphere(wo, wi) {
            return Rgb::BLACK;
        }
        if self.b == 0.0 {
            return self.r * FRAC_1_PI;
        }
        let sin_i = (1.0 - wi.z * wi.z).max(0.0).sqrt();
        let sin_o = (1.0 - wo.z * wo.z).max(0.0).sqrt();
        let mut max_cos = 0.0;
        if sin_i > 1e-4 && sin_o > 1e-4 {
            let cos_dphi = (wi.x * wo.x + wi.y * wo.y) / (sin_i * sin_o);
            max_cos = cos_dphi.max(0.0);
        }
        let (ci, co) = (wi.z.abs(), wo.z.abs());
        let (sin_a, tan_b) = if ci > co {
            (sin_o, sin_i / ci)
        } else {
            (sin_i, sin_o / co)
        };
        self.r * (FRAC_1_PI * (self.a + self.b * max_cos * sin_a * tan_b))
    }

    pub fn sample(&self, wo: Vec3A, u2: Vec2) -> Option<LocalSample> {
        let mut wi = cosine_hemisphere(u2);
        if wo.z < 0.0 {
            wi.z = -wi.z;
        }
        let pdf = self.pdf(wo, wi);
        if pdf <= 0.0 {
            return None;
        }
        Some(LocalSample {
            wi,
            f: self.f(wo, wi),
            pdf,
            specular: false,
        })
    }

    pub fn pdf(&self, wo: Vec3A, wi: Vec3A) -> f32 {
        if same_hemisphere(wo, wi) {
            wi.z.abs() * FRAC_1_PI
        } else {
            0.0
        }
    }
}
