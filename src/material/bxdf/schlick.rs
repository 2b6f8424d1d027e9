//! LuxRender's Schlick microfacet model: the `SchlickDistribution` every 1.x glossy material
//! uses (glossy, glossycoating, glossytranslucent, metal, metal2, shinymetal, roughglass,
//! carpaint, glossy_lossy), the Schlick coating layer of `SchlickBSDF` ([`SchlickCoat`]:
//! glossy, glossycoating, glossytranslucent) and glossy's coating over a diffuse base
//! ([`Coating`]).
//!
//! The distribution with roughness `r = u·v` and anisotropy `p` is
//! `D(h) = Z(cos θh) A(φh) / π`, `Z(c) = r / (1 + (r - 1) c²)²`, and
//! `G = G1(cos_o) G1(cos_i)`, `G1(c) = c / (r + (1 - r) c)`. Half vectors are sampled with
//! density `Z(c) c / π` (exact inversion of `Z`, uniform azimuth; LuxRender samples the
//! azimuth from `A` but reports `D` as the density, which is not normalised: here the density
//! is exact and the anisotropy stays in `f`).
//!
//! The coating reflects `S D G / (4 cos_o cos_i) [+ multibounce: S clamp((1 - G) /
//! (4 cos_o cos_i), 0, 1)]` with `S(c) = Ks + (1 - Ks)(1 - c)^5` at `c = |wi·h|`, front side
//! only; what it lets through is absorbed by `A = exp(-Ka d (1/cos_i + 1/cos_o))` (1 when
//! `d = 0`). It is sampled with probability `(1 + S̄(cos_o)) / 2` (front side only).
//! [`Coating`] adds the base `(1 - S) A base_f`; seen from the back only the base reflects.

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
    /// From `uroughness`/`vroughness` clamped to [6e-3, 1], as glossy, glossycoating,
    /// glossytranslucent and roughglass clamp them.
    pub fn from_uv(u: f32, v: f32) -> SchlickDist {
        SchlickDist::unclamped(u.clamp(6e-3, 1.0), v.clamp(6e-3, 1.0))
    }

    /// From `uroughness`/`vroughness` as given (metal, metal2, shinymetal, glossy_lossy), only
    /// kept in [1e-4, 1e3] so that the distribution stays finite.
    pub fn unclamped(u: f32, v: f32) -> SchlickDist {
        let keep = |x: f32| {
            if x.is_finite() {
                x.clamp(1e-4, 1e3)
            } else {
                1.0
            }
        };
        let (u, v) = (keep(u), keep(v));
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

    /// An isotropic distribution of roughness `r` (carpaint's `M²`).
    pub fn isotropic(r: f32) -> SchlickDist {
        SchlickDist {
            roughness: r.clamp(1e-8, 1e6),
            anisotropy: 0.0,
        }
    }

    fn z(&self, c: f32) -> f32 {
        let r = self.roughness;
        let c2 = c * c;
        let d = c2 * r + (1.0 - c2);
        (r / d) / d
    }

    fn a(&self, h: Vec3A) -> f32 {
        if self.anisotropy == 0.0 {
            return 1.0;
        }
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

    /// `G1(cos_o) G1(cos_i)` from the absolute cosines.
    pub fn g(&self, co: f32, ci: f32) -> f32 {
        self.g1(co) * self.g1(ci)
    }

    pub fn pdf_h(&self, h: Vec3A) -> f32 {
        let c = h.z.abs();
        self.z(c) * c / PI
    }

    /// A half vector on the +z hemisphere.
    pub fn sample_h(&self, u: Vec2) -> Vec3A {
        let r = self.roughness;
        let cos2 = u.x / (r * (1.0 - u.x) + u.x).max(1e-30);
        let cos_t = cos2.clamp(0.0, 1.0).sqrt();
        let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        Vec3A::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t)
    }
}

/// The Schlick coating layer of LuxRender's `SchlickBSDF`.
#[derive(Clone, Copy, Debug)]
pub struct SchlickCoat {
    pub ks: Rgb,
    pub ka: Rgb,
    pub depth: f32,
    pub dist: SchlickDist,
    pub multibounce: bool,
}

impl SchlickCoat {
    /// Probability of sampling the coating for `wo` (never on the back side).
    pub fn weight(&self, wo: Vec3A) -> f32 {
        if wo.z > 0.0 {
            0.5 * (1.0 + avg(schlick(wo.z, self.ks)))
        } else {
            0.0
        }
    }

    /// The coating's Fresnel reflectance `S` at `cos`.
    pub fn fresnel(&self, cos: f32) -> Rgb {
        schlick(cos, self.ks)
    }

    /// Transmittance of the coating layer along both directions (absolute cosines).
    pub fn absorption(&self, co: f32, ci: f32) -> Rgb {
        if self.depth <= 0.0 {
            return Rgb::WHITE;
        }
        let k = self.depth * (1.0 / ci.max(1e-4) + 1.0 / co.max(1e-4));
        self.ka.map(|a| (-a * k).exp())
    }

    /// The coating's own reflection (front side, both directions above the surface).
    pub fn f(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        if !(wo.z > 0.0 && wi.z > 0.0) {
            return Rgb::BLACK;
        }
        let (co, ci) = (wo.z, wi.z);
        let h = (wo + wi).normalize_or_zero();
        if h == Vec3A::ZERO {
            return Rgb::BLACK;
        }
        let s = self.fresnel(wi.dot(h));
        let g = self.dist.g(co, ci);
        let mut v = self.dist.d(h) * g / (4.0 * co * ci);
        if self.multibounce {
            v += ((1.0 - g) / (4.0 * co * ci)).clamp(0.0, 1.0);
        }
        s * v
    }

    /// Density of [`Self::sample_wi`].
    pub fn pdf(&self, wo: Vec3A, wi: Vec3A) -> f32 {
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

    /// A reflected direction from a sampled half vector (front side only).
    pub fn sample_wi(&self, wo: Vec3A, u2: Vec2) -> Option<Vec3A> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = reflect(wo, self.dist.sample_h(u2));
        (wi.z > 0.0).then_some(wi)
    }
}

/// Glossy: a Schlick coating over a diffuse base.
#[derive(Clone, Copy, Debug)]
pub struct Coating {
    pub base: Diffuse,
    pub coat: SchlickCoat,
}

impl Coating {
    pub fn f(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        if !same_hemisphere(wo, wi) {
            return Rgb::BLACK;
        }
        if wo.z <= 0.0 {
            return self.base.f(wo, wi);
        }
        let h = (wo + wi).normalize_or_zero();
        if h == Vec3A::ZERO {
            return Rgb::BLACK;
        }
        let s = self.coat.fresnel(wi.dot(h));
        let a = self.coat.absorption(wo.z, wi.z);
        self.coat.f(wo, wi) + (Rgb::WHITE - s) * a * self.base.f(wo, wi)
    }

    pub fn pdf(&self, wo: Vec3A, wi: Vec3A) -> f32 {
        let wc = self.coat.weight(wo);
        wc * self.coat.pdf(wo, wi) + (1.0 - wc) * self.base.pdf(wo, wi)
    }

    pub fn sample(&self, wo: Vec3A, u: f32, u2: Vec2) -> Option<LocalSample> {
        let wc = self.coat.weight(wo);
        let wi = if u < wc {
            self.coat.sample_wi(wo, u2)?
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

/// Glossy with `separable` false: LuxRender's single `SchlickBRDF`, the coating and a
/// Lambertian base in one lobe, `f = (1 - S) A Kd/π + S D G / (4 cos_o cos_i)
/// [+ multibounce: S clamp((1 - G) / (4π cos_o cos_i), 0, 1)]`, the specular part on the
/// front side only. Half of the samples are cosine distributed, half follow the half-vector
/// distribution (mirrored to the side of `wo`).
#[derive(Clone, Copy, Debug)]
pub struct SchlickBrdf {
    pub kd: Rgb,
    pub coat: SchlickCoat,
}

impl SchlickBrdf {
    pub fn f(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        if !same_hemisphere(wo, wi) {
            return Rgb::BLACK;
        }
        let (co, ci) = (wo.z.abs(), wi.z.abs());
        let a = self.coat.absorption(co, ci);
        let diffuse = a * self.kd * std::f32::consts::FRAC_1_PI;
        if self.coat.ks.is_black() {
            return diffuse;
        }
        let h = (wo + wi).normalize_or_zero();
        if h == Vec3A::ZERO {
            return Rgb::BLACK;
        }
        let s = self.coat.fresnel(wi.dot(h));
        let mut out = diffuse * (Rgb::WHITE - s);
        if wo.z > 0.0 && wi.z > 0.0 {
            let g = self.coat.dist.g(co, ci);
            let mut v = self.coat.dist.d(h) * g / (4.0 * co * ci);
            if self.coat.multibounce {
                v += ((1.0 - g) / (4.0 * PI * co * ci)).clamp(0.0, 1.0);
            }
            out += s * v;
        }
        out
    }

    pub fn pdf(&self, wo: Vec3A, wi: Vec3A) -> f32 {
        if !same_hemisphere(wo, wi) {
            return 0.0;
        }
        let h = (wo + wi).normalize_or_zero();
        let oh = wo.dot(h).abs();
        let spec = if h != Vec3A::ZERO && oh > 0.0 {
            self.coat.dist.pdf_h(h) / (4.0 * oh)
        } else {
            0.0
        };
        0.5 * (wi.z.abs() / PI + spec)
    }

    pub fn sample(&self, wo: Vec3A, u: f32, u2: Vec2) -> Option<LocalSample> {
        let wi = if u < 0.5 {
            let mut wi = super::cosine_hemisphere(u2);
            if wo.z < 0.0 {
                wi.z = -wi.z;
            }
            wi
        } else {
            let mut h = self.coat.dist.sample_h(u2);
            if wo.z < 0.0 {
                h.z = -h.z;
            }
            reflect(wo, h)
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
