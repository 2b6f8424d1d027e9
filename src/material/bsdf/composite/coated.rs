//! glossycoating's BSDF, LuxRender's `SchlickBSDF` over an arbitrary base BSDF: a Schlick
//! coating ([`SchlickCoat`]) in the coating's shading frame over the base material's own
//! BSDF (with its own bump and frame).
//!
//! With the geometric normal deciding the side (as LuxRender does):
//! - reflection on the front (`wo` above the coating's shading plane):
//!   `coat(wo, wi) + A (1 - S(|wi·h|)) base(wo, wi)`, `h` the half vector;
//! - reflection on the back: the base alone;
//! - transmission: `A sqrt(1 - S(|wo·h'|)) base(wo, wi)` with `h'` the half vector of `wo` and
//!   the mirror image of `wi` (LuxRender's heuristic, so that a sheet coated on both faces is
//!   filtered by 1 - S like a reflection).
//!
//! The coating is sampled with its weight ([`SchlickCoat::weight`]), the base otherwise; the
//! pdf is the mixture. A specular base sample keeps its delta, scaled by the coating's factor.

use super::ONE_MINUS_EPSILON;
use crate::material::bsdf::{Bsdf, BsdfSample};
use crate::material::bxdf::schlick::SchlickCoat;
use crate::spectrum::Rgb;
use glam::{Vec2, Vec3A};

#[derive(Clone, Debug)]
pub struct Coated {
    pub coat: SchlickCoat,
    pub base: Bsdf,
}

impl Coated {
    /// The factor the coating puts on the base for the pair (local directions), and whether
    /// the pair is a front-side reflection (where the coating itself reflects).
    fn base_factor(&self, wo: Vec3A, wi: Vec3A, reflection: bool) -> (Rgb, bool) {
        let a = self.coat.absorption(wo.z.abs(), wi.z.abs());
        if reflection {
            if wo.z <= 0.0 {
                return (Rgb::WHITE, false);
            }
            let h = (wo + wi).normalize_or_zero();
            let s = self.coat.fresnel(wi.dot(h).abs());
            (a * (Rgb::WHITE - s), true)
        } else {
            let h = Vec3A::new(wo.x + wi.x, wo.y + wi.y, wo.z - wi.z).normalize_or_zero();
            let s = self.coat.fresnel(wo.dot(h).abs());
            (a * (Rgb::WHITE - s).map(|x| x.max(0.0).sqrt()), false)
        }
    }

    /// Reflection (+1), transmission (-1) or neither (0) by the geometric normal.
    fn side(parent: &Bsdf, wo: Vec3A, wi: Vec3A) -> f32 {
        let (a, b) = (wo.dot(parent.ng), wi.dot(parent.ng));
        if a == 0.0 || b == 0.0 {
            0.0
        } else if a * b > 0.0 {
            1.0
        } else {
            -1.0
        }
    }

    pub fn f(&self, parent: &Bsdf, wo_w: Vec3A, wi_w: Vec3A) -> Rgb {
        let side = Self::side(parent, wo_w, wi_w);
        if side == 0.0 {
            return Rgb::BLACK;
        }
        let (wo, wi) = (parent.frame.to_local(wo_w), parent.frame.to_local(wi_w));
        let (factor, front) = self.base_factor(wo, wi, side > 0.0);
        let base = factor * self.base.f(wo_w, wi_w);
        if front {
            self.coat.f(wo, wi) + base
        } else {
            base
        }
    }

    pub fn pdf(&self, parent: &Bsdf, wo_w: Vec3A, wi_w: Vec3A) -> f32 {
        let (wo, wi) = (parent.frame.to_local(wo_w), parent.frame.to_local(wi_w));
        let wc = self.coat.weight(wo);
        wc * self.coat.pdf(wo, wi) + (1.0 - wc) * self.base.pdf(wo_w, wi_w)
    }

    pub fn sample_f(&self, parent: &Bsdf, wo_w: Vec3A, u: f32, u2: Vec2) -> Option<BsdfSample> {
        let wo = parent.frame.to_local(wo_w);
        let wc = self.coat.weight(wo);
        let wi_w = if u < wc {
            parent.frame.to_world(self.coat.sample_wi(wo, u2)?)
        } else {
            let v = ((u - wc) / (1.0 - wc)).clamp(0.0, ONE_MINUS_EPSILON);
            let s = self.base.sample_f(wo_w, v, u2)?;
            if s.specular {
                let side = Self::side(parent, wo_w, s.wi);
                if side == 0.0 {
                    return None;
                }
                let wi = parent.frame.to_local(s.wi);
                let (factor, _) = self.base_factor(wo, wi, side > 0.0);
                return Some(BsdfSample {
                    wi: s.wi,
                    f: s.f * factor,
                    pdf: s.pdf * (1.0 - wc),
                    specular: true,
                });
            }
            s.wi
        };
        let pdf = self.pdf(parent, wo_w, wi_w);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi: wi_w,
            f: self.f(parent, wo_w, wi_w),
            pdf,
            specular: false,
        })
    }
}
