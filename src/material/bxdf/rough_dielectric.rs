//! Rough dielectric (LuxRender's roughglass) with LuxRender 1.x's Schlick distribution
//! ([`SchlickDist`]): microfacet reflection and refraction after Walter et al. 2007. Reflection is chosen with probability proportional
//! to `F·avg(Kr)` against `(1 - F)·avg(Kt)` at the sampled half vector; `pdf` recomputes the
//! same choice from the half vector of the pair, so sampling and evaluation agree.

use super::fresnel;
use super::schlick::SchlickDist;
use super::{avg, reflect, refract, same_hemisphere, LocalSample};
use crate::spectrum::Rgb;
use glam::{Vec2, Vec3A};

#[derive(Clone, Copy, Debug)]
pub struct RoughDielectric {
    pub kr: Rgb,
    pub kt: Rgb,
    pub eta: f32,
    pub dist: SchlickDist,
}

impl RoughDielectric {
    /// (index on wo's side, index on the other side).
    fn etas(&self, wo: Vec3A) -> (f32, f32) {
        if wo.z > 0.0 {
            (1.0, self.eta)
        } else {
            (self.eta, 1.0)
        }
    }

    /// Half vector of a pair (pointing to +z) and whether it is a reflection.
    fn half(&self, wo: Vec3A, wi: Vec3A) -> Option<(Vec3A, bool)> {
        let reflection = same_hemisphere(wo, wi);
        let (eo, ei) = self.etas(wo);
        let h = if reflection {
            wo + wi
        } else {
            wo * eo + wi * ei
        };
        let mut h = h.normalize_or_zero();
        if h == Vec3A::ZERO {
            return None;
        }
        if h.z < 0.0 {
            h = -h;
        }
        Some((h, reflection))
    }

    fn reflect_prob(&self, fr: f32) -> f32 {
        let wr = fr * avg(self.kr);
        let wt = (1.0 - fr) * avg(self.kt);
        if wr + wt <= 0.0 {
            0.0
        } else {
            wr / (wr + wt)
        }
    }

    pub fn f(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        let (co, ci) = (wo.z.abs(), wi.z.abs());
        if co == 0.0 || ci == 0.0 {
            return Rgb::BLACK;
        }
        let Some((h, reflection)) = self.half(wo, wi) else {
            return Rgb::BLACK;
        };
        let (eo, ei) = self.etas(wo);
        let oh = wo.dot(h);
        let fr = fresnel::dielectric(oh.abs(), eo, ei);
        let d = self.dist.d(h);
        let g = self.dist.g(co, ci);
        if reflection {
            return self.kr * (fr * d * g / (4.0 * co * ci));
        }
        let ih = wi.dot(h);
        if oh * ih >= 0.0 {
            return Rgb::BLACK;
        }
        let denom = eo * oh + ei * ih;
        if denom == 0.0 {
            return Rgb::BLACK;
        }
        // Radiance form: scaled by (eo/ei)^2 when crossing into the other medium.
        let v = (1.0 - fr) * d * g * ei * ei * (oh * ih).abs() / (co * ci * denom * denom);
        self.kt * (v * (eo * eo) / (ei * ei))
    }

    pub fn pdf(&self, wo: Vec3A, wi: Vec3A) -> f32 {
        let Some((h, reflection)) = self.half(wo, wi) else {
            return 0.0;
        };
        let (eo, ei) = self.etas(wo);
        let oh = wo.dot(h);
        let fr = fresnel::dielectric(oh.abs(), eo, ei);
        let pr = self.reflect_prob(fr);
        let ph = self.dist.pdf_h(h);
        if reflection {
            return pr * ph / (4.0 * oh.abs().max(1e-8));
        }
        let ih = wi.dot(h);
        if oh * ih >= 0.0 {
            return 0.0;
        }
        let denom = eo * oh + ei * ih;
        if denom == 0.0 {
            return 0.0;
        }
        (1.0 - pr) * ph * ei * ei * ih.abs() / (denom * denom)
    }

    pub fn sample(&self, wo: Vec3A, u: f32, u2: Vec2) -> Option<LocalSample> {
        if wo.z == 0.0 {
            return None;
        }
        let h = self.dist.sample_h(u2);
        let (eo, ei) = self.etas(wo);
        let hs = if wo.z > 0.0 { h } else { -h };
        let oh = wo.dot(hs);
        if oh <= 0.0 {
            return None;
        }
        let fr = fresnel::dielectric(oh, eo, ei);
        let pr = self.reflect_prob(fr);
        let wi = if u < pr {
            reflect(wo, hs)
        } else {
            refract(wo, hs, eo / ei)?
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
