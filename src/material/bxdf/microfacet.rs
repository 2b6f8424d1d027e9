//! Glossy microfacet reflection as LuxRender 1.x's `MicrofacetReflection` with its Schlick
//! distribution (metal, metal2, shinymetal): `f = scale · F(wi·h) · D(h) G / (4 cos_o cos_i)`
//! with the half vector `h` taken on the +z side, `D` and `G` from [`SchlickDist`].
//!
//! The Fresnel term is either a conductor of index n + ik evaluated at |wi·h| (LuxRender's
//! `FresnelConductor`, the metal material) or a [`FresnelGeneral`] evaluated at the signed
//! wi·h (metal2 and shinymetal; a back-side hit then sees the inside of the interface).
//! Half vectors are sampled with [`SchlickDist::sample_h`] and the pdf is
//! `pdf_h(h) / (4 |wo·h|)` for any pair on the same side.

use super::fresnel::{conductor, FresnelGeneral};
use super::schlick::SchlickDist;
use super::{reflect, same_hemisphere, LocalSample};
use crate::spectrum::Rgb;
use glam::{Vec2, Vec3A};

/// The Fresnel term of a microfacet lobe.
#[derive(Clone, Copy, Debug)]
pub enum Fresnel {
    /// Conductor of complex index n + ik, symmetric in the sign of the cosine.
    Conductor { n: Rgb, k: Rgb },
    /// LuxRender's general interface (signed cosine).
    General(FresnelGeneral),
}

impl Fresnel {
    pub fn eval(&self, cos: f32) -> Rgb {
        match self {
            Fresnel::Conductor { n, k } => conductor(cos.abs(), *n, *k),
            Fresnel::General(g) => g.eval(cos),
        }
    }
}

/// Glossy reflection `scale · F D G / (4 cos_o cos_i)`.
#[derive(Clone, Copy, Debug)]
pub struct MicrofacetReflection {
    pub scale: Rgb,
    pub fresnel: Fresnel,
    pub dist: SchlickDist,
}

/// The half vector of a reflection pair on the +z side.
fn half_up(wo: Vec3A, wi: Vec3A) -> Option<Vec3A> {
    let h = (wo + wi).normalize_or_zero();
    if h == Vec3A::ZERO {
        return None;
    }
    Some(if h.z < 0.0 { -h } else { h })
}

impl MicrofacetReflection {
    pub fn f(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        if !same_hemisphere(wo, wi) {
            return Rgb::BLACK;
        }
        let (co, ci) = (wo.z.abs(), wi.z.abs());
        let Some(h) = half_up(wo, wi) else {
            return Rgb::BLACK;
        };
        let fr = self.fresnel.eval(wi.dot(h));
        self.scale * fr * (self.dist.d(h) * self.dist.g(co, ci) / (4.0 * co * ci))
    }

    pub fn sample(&self, wo: Vec3A, u2: Vec2) -> Option<LocalSample> {
        let h = self.dist.sample_h(u2);
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
        let Some(h) = half_up(wo, wi) else {
            return 0.0;
        };
        let oh = wo.dot(h).abs();
        if oh == 0.0 {
            return 0.0;
        }
        self.dist.pdf_h(h) / (4.0 * oh)
    }
}
