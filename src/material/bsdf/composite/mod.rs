//! BSDFs made of other BSDFs, evaluated in world space through their components' own frames:
//! glossycoating's coating over any base ([`coated`]), doubleside's choice of a front and a
//! back BSDF by the side of `wo`, a layer of the layered material seen through its opacity
//! (a blend with a null pass-through), and the layered stack itself ([`layered`]).
//!
//! Each variant gives `f`, `pdf` (for any pair) and `sample_f` with the same conventions as
//! [`Bsdf`]: `f` without the cosine, specular samples carrying their 1/|cos| and a discrete
//! probability.

pub mod coated;
pub mod layered;

use super::{Bsdf, BsdfSample};
use crate::spectrum::Rgb;
use glam::{Vec2, Vec3A};

/// Largest `u` below 1, for rescaled lobe selectors.
pub(crate) const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

#[derive(Clone, Debug)]
pub enum Composite {
    /// glossycoating.
    Coated(coated::Coated),
    /// doubleside: `front` when `wo` is on the side of the geometric normal, else `back`.
    DoubleSide { front: Bsdf, back: Bsdf },
    /// `opacity × bsdf + (1 - opacity) × pass-through` (a layer of the layered material).
    Opacity { bsdf: Bsdf, opacity: f32 },
    /// layered.
    Layered(layered::Layered),
}

impl Composite {
    pub fn has_non_specular(&self) -> bool {
        match self {
            Composite::Coated(_) | Composite::Layered(_) => true,
            Composite::DoubleSide { front, back } => {
                front.has_non_specular() || back.has_non_specular()
            }
            Composite::Opacity { bsdf, opacity } => *opacity > 0.0 && bsdf.has_non_specular(),
        }
    }

    pub fn f(&self, parent: &Bsdf, wo: Vec3A, wi: Vec3A) -> Rgb {
        match self {
            Composite::Coated(c) => c.f(parent, wo, wi),
            Composite::DoubleSide { front, back } => side(parent, front, back, wo).f(wo, wi),
            Composite::Opacity { bsdf, opacity } => bsdf.f(wo, wi) * *opacity,
            Composite::Layered(l) => l.f(parent, wo, wi),
        }
    }

    pub fn pdf(&self, parent: &Bsdf, wo: Vec3A, wi: Vec3A) -> f32 {
        match self {
            Composite::Coated(c) => c.pdf(parent, wo, wi),
            Composite::DoubleSide { front, back } => side(parent, front, back, wo).pdf(wo, wi),
            Composite::Opacity { bsdf, opacity } => bsdf.pdf(wo, wi) * *opacity,
            Composite::Layered(l) => l.pdf(),
        }
    }

    pub fn sample_f(&self, parent: &Bsdf, wo: Vec3A, u: f32, u2: Vec2) -> Option<BsdfSample> {
        match self {
            Composite::Coated(c) => c.sample_f(parent, wo, u, u2),
            Composite::DoubleSide { front, back } => {
                side(parent, front, back, wo).sample_f(wo, u, u2)
            }
            Composite::Opacity { bsdf, opacity } => sample_opacity(bsdf, *opacity, wo, u, u2),
            Composite::Layered(l) => l.sample_f(parent, wo, u, u2),
        }
    }
}

/// The component of a doubleside BSDF that sees `wo`.
fn side<'a>(parent: &Bsdf, front: &'a Bsdf, back: &'a Bsdf, wo: Vec3A) -> &'a Bsdf {
    if wo.dot(parent.ng) > 0.0 {
        front
    } else {
        back
    }
}

/// Samples the blend of `bsdf` (probability `opacity`) and a straight pass-through.
fn sample_opacity(bsdf: &Bsdf, opacity: f32, wo: Vec3A, u: f32, u2: Vec2) -> Option<BsdfSample> {
    if u < opacity {
        let v = (u / opacity).min(ONE_MINUS_EPSILON);
        let mut s = bsdf.sample_f(wo, v, u2)?;
        s.f *= opacity;
        s.pdf *= opacity;
        return Some(s);
    }
    let wi = -wo;
    let c = wi.dot(bsdf.frame.n).abs();
    let p = 1.0 - opacity;
    (c > 0.0 && p > 0.0).then(|| BsdfSample {
        wi,
        f: Rgb::splat(p / c),
        pdf: p,
        specular: true,
    })
}
