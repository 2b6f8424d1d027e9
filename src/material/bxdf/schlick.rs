//! LuxRender's glossy model: a Schlick microfacet coating over a diffuse base (`SchlickBSDF`
//! with a `SchlickDistribution`, `FresnelSlick` and an optional absorbing layer).
//!
//! With `S(c) = Ks + (1 - Ks)(1 - c)^5` evaluated at `c = |wi·h|`:
//! `f = S D G / (4 cos_o cos_i) [+ multibounce: S clamp((1 - G) / (4 cos_o cos_i), 0, 1)]
//!      + (1 - S) A base_f`, where `A = exp(-Ka d (1/cos_i + 1/cos_o))` is the absorption of a
//! coating of depth `d` (1 when `d = 0`). Seen from the back only the base reflects.
//! The Schlick distribution with roughness `r = u·v` and anisotropy `p` is
//! `D(h) = Z(cos θh) A(φh) / π`, `Z(c) = r / (1 + (r - 1) c²)²`, and
//! `G = G1(cos_o) G1(cos_i)`, `G1(c) = c / (r + (1 - r) c)`.
//! The coating is sampled with probability `(1 + S̄(cos_o)) / 2` (front side only), half
//! vectors with density `Z(c) c / π` (exact inversion of `Z`, uniform azimuth); the base is
//! cosine sampled. The returned pdf is the mixture of both.

use super::diffuse::Diffuse;
use super::fresnel::schlick;
use super::{avg, reflect, same_hemisphere, LocalSample};
use crate::spectrum::Rgb;
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug)]
pub struct SchlickDist {
    pub roughness: f32,
    pub anisotropy: f32,
}

impl SchlickDist {
    /// From LuxRender's `uroughness`/`vroughness` (each clamped to [6e-3, 1]).
    pub fn from_uv(u: f32, v: f32) -> SchlickDist {
        let u = u.clamp(6e-3, 1.0);
        let v = v.clamp(6e-3, 1.0);
        let (u2, v2) = (u * u, v * v);
        let anisotropy = if u2 < v2 {
            1.0 - u2 / v2
        } else {
            v2 / u2 - 1.0
        };
        SchlickDist {
            roughness: u * v,
            anisotropy,
        }
    }

    fn z(&self, c: f32) -> f32 {
        let r = self.roughness;
        let d = 1.0 + (r - 1.0) * c * c;
        r / (d * d)
    }

    fn a(&self, h: Vec3A) -> f32 {
        let len = (h.x * h.x + h.y * h.y).sqrt();
        if len <= 0.0 {
            return 1.0;
        }
        let w = if self.anisotropy > 0.0 { h.x } else { h.y } / len;
        let p = 1.0 - self.anisotropy.abs();
        (p / (p * p + w * w * (1.0 - p * p))).sqrt()
    }

    pub fn d(&self, h: Vec3A) -> f32 {
        self.z(h.z.abs()) * self.a(h) / PI
    }

    pub fn g1(&self, c: f32) -> f32 {
        let r = self.roughness;
        c / (c * (1.0 - r) + r)
    }

    pub fn pdf_h(&self, h: Vec3A) -> f32 {
        let c = h.z.abs();
        self.z(c) * c / PI
    }

    pub fn sample_h(&self, u: Vec2) -> Vec3A {
        let r = self.roughness;
        let cos2 = u.x / (r * (1.0 - u.x) + u.x).max(1e-12);
        let cos_t = cos2.clamp(0.0, 1.0).sqrt();
        let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        Vec3A::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t)
    }
}

#[derive(Clone, Copy, Debug)]
pub struct Coating {
    pub base: Diffuse,
    pub ks: Rgb,
    pub ka: Rgb,
    pub depth: f32,
    pub dist: SchlickDist,
    pub multibounce: bool,
}

impl Coating {
    fn coating_weight(&self, wo: Vec3A) -> f32 {
        if wo.z > 0.0 {
            0.5 * (1.0 + avg(schlick(wo.z, self.ks)))
        } else {
            0.0
        }
    }

    fn absorption(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        if self.depth <= 0.0 {
            return Rgb::WHITE;
        }
        let k = self.depth * (1.0 / wi.z.abs().max(1e-4) + 1.0 / wo.z.abs().max(1e-4));
        self.ka.map(|a| (-a * k).exp())
    }

    pub fn f(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        if !same_hemisphere(wo, wi) {
            return Rgb::BLACK;
        }
        if wo.z <= 0.0 {
            return self.base.f(wo, wi);
        }
        let (co, ci) = (wo.z, wi.z);
        let h = (wo + wi).normalize_or_zero();
        if h == Vec3A::ZERO {
            return Rgb::BLACK;
        }
        let s = schlick(wi.dot(h), self.ks);
        let g = self.dist.g1(co) * self.dist.g1(ci);
        let mut spec = self.dist.d(h) * g / (4.0 * co * ci);
        if self.multibounce {
            spec += ((1.0 - g) / (4.0 * co * ci)).clamp(0.0, 1.0);
        }
        s * spec + (Rgb::WHITE - s) * self.absorption(wo, wi) * self.base.f(wo, wi)
    }

    fn coating_pdf(&self, wo: Vec3A, wi: Vec3A) -> f32 {
        if !(wo.z > 0.0 && wi.z > 0.0) {
            return 0.0;
        }
        let h = (wo + wi).normalize_or_zero();
        let oh = wo.dot(h);
        if h == Vec3A::ZERO || oh <= 0.0 {
            return 0.0;
        }
        self.dist.pdf_h(h) / (4.0 * oh)
    }

    pub fn pdf(&self, wo: Vec3A, wi: Vec3A) -> f32 {
        let wc = self.coating_weight(wo);
        wc * self.coating_pdf(wo, wi) + (1.0 - wc) * self.base.pdf(wo, wi)
    }

    pub fn sample(&self, wo: Vec3A, u: f32, u2: Vec2) -> Option<LocalSample> {
        let wc = self.coating_weight(wo);
        let wi = if u < wc {
            let h = self.dist.sample_h(u2);
            let wi = reflect(wo, h);
            if wi.z <= 0.0 {
                return None;
            }
            wi
        } else {
            self.base.sample(wo, u2)?.wi
        };
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
