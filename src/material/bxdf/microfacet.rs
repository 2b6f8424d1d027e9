//! Blinn microfacet distribution (exponent `e = 1 / roughness`, LuxRender's metal, shinymetal
//! and roughglass; Ashikhmin–Shirley anisotropic when u and v roughness differ) and a
//! Torrance–Sparrow reflection lobe with a conductor Fresnel term.
//!
//! `D(h) = (e + 2) / (2π) cos^e θh`; half vectors are sampled with density
//! `(e + 1) / (2π) cos^e θh` and `G` is the Torrance–Sparrow shadowing term.

use super::fresnel;
use super::{reflect, same_hemisphere, LocalSample};
use crate::spectrum::Rgb;
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;

/// Blinn distribution, anisotropic (Ashikhmin–Shirley) when the exponents differ:
/// `D(h) = sqrt((ex + 2)(ey + 2)) / 2π · cos θh^(ex cos²φ + ey sin²φ)`.
#[derive(Clone, Copy, Debug)]
pub struct Blinn {
    pub exponent: f32,
    /// Exponent along the shading tangent's normal (y); equal to `exponent` when isotropic.
    pub exponent_y: f32,
}

impl Blinn {
    /// From LuxRender roughness (u = v), clamped to keep the exponent finite.
    pub fn from_roughness(r: f32) -> Blinn {
        Blinn::from_uv(r, r)
    }

    /// From LuxRender `uroughness`/`vroughness`: exponents 1/u along the tangent, 1/v across.
    pub fn from_uv(u: f32, v: f32) -> Blinn {
        let e = |r: f32| (1.0 / r.max(1e-4)).min(1e4);
        Blinn {
            exponent: e(u),
            exponent_y: e(v),
        }
    }

    fn exponent_at(&self, h: Vec3A) -> f32 {
        if self.exponent == self.exponent_y {
            return self.exponent;
        }
        let s2 = 1.0 - h.z * h.z;
        if s2 <= 1e-12 {
            return self.exponent;
        }
        (self.exponent * h.x * h.x + self.exponent_y * h.y * h.y) / s2
    }

    pub fn d(&self, h: Vec3A) -> f32 {
        let c = h.z.abs();
        let norm = ((self.exponent + 2.0) * (self.exponent_y + 2.0)).sqrt();
        norm / (2.0 * PI) * c.powf(self.exponent_at(h))
    }

    /// Density of [`Blinn::sample_h`] over solid angle.
    pub fn pdf_h(&self, h: Vec3A) -> f32 {
        let c = h.z.abs();
        let norm = ((self.exponent + 1.0) * (self.exponent_y + 1.0)).sqrt();
        norm / (2.0 * PI) * c.powf(self.exponent_at(h))
    }

    /// A half vector on the +z hemisphere.
    pub fn sample_h(&self, u: Vec2) -> Vec3A {
        let (ex, ey) = (self.exponent, self.exponent_y);
        let phi = if ex == ey {
            2.0 * PI * u.y
        } else {
            // Quadrant by quadrant inversion of the azimuthal marginal (Ashikhmin–Shirley).
            let q = (u.y * 4.0).min(3.999_999);
            let quadrant = q as u32;
            let t = q - quadrant as f32;
            let first = |t: f32| {
                let ratio = ((ex + 1.0) / (ey + 1.0)).sqrt();
                (ratio * (PI * 0.5 * t).tan()).atan()
            };
            match quadrant {
                0 => first(t),
                1 => PI - first(1.0 - t),
                2 => PI + first(t),
                _ => 2.0 * PI - first(1.0 - t),
            }
        };
        let (sp, cp) = phi.sin_cos();
        let e = ex * cp * cp + ey * sp * sp;
        let cos_t = u.x.powf(1.0 / (e + 1.0));
        let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
        Vec3A::new(sin_t * cp, sin_t * sp, cos_t)
    }

    /// Torrance–Sparrow geometric attenuation.
    pub fn g(&self, wo: Vec3A, wi: Vec3A, h: Vec3A) -> f32 {
        let nh = h.z.abs();
        let (no, ni) = (wo.z.abs(), wi.z.abs());
        let oh = wo.dot(h).abs().max(1e-8);
        let ih = wi.dot(h).abs().max(1e-8);
        (2.0 * nh * no / oh).min(2.0 * nh * ni / ih).min(1.0)
    }
}

/// Glossy conductor reflection: `scale * F(n, k) D G / (4 cos_o cos_i)`.
#[derive(Clone, Copy, Debug)]
pub struct MicrofacetReflection {
    pub scale: Rgb,
    pub n: Rgb,
    pub k: Rgb,
    pub dist: Blinn,
}

impl MicrofacetReflection {
    pub fn f(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        if !same_hemisphere(wo, wi) {
            return Rgb::BLACK;
        }
        let (co, ci) = (wo.z.abs(), wi.z.abs());
        if co == 0.0 || ci == 0.0 {
            return Rgb::BLACK;
        }
        let h = (wo + wi).normalize_or_zero();
        if h == Vec3A::ZERO {
            return Rgb::BLACK;
        }
        let fr = fresnel::conductor(wi.dot(h), self.n, self.k);
        self.scale * fr * (self.dist.d(h) * self.dist.g(wo, wi, h) / (4.0 * co * ci))
    }

    pub fn sample(&self, wo: Vec3A, u2: Vec2) -> Option<LocalSample> {
        let mut h = self.dist.sample_h(u2);
        if wo.z < 0.0 {
            h = -h;
        }
        let wi = reflect(wo, h);
        if !same_hemisphere(wo, wi) {
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

    pub fn pdf(&self, wo: Vec3A, wi: Vec3A) -> f32 {
        if !same_hemisphere(wo, wi) {
            return 0.0;
        }
        let h = (wo + wi).normalize_or_zero();
        let oh = wo.dot(h).abs();
        if h == Vec3A::ZERO || oh == 0.0 {
            return 0.0;
        }
        self.dist.pdf_h(h) / (4.0 * oh)
    }
}
