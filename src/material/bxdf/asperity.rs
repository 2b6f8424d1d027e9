//! Asperity scattering (Koenderink & Pont, "The secret of velvety skin"), LuxRender's velvet:
//! a thin layer of scatterers with a Legendre phase function `1 + A1 P1 + A2 P2 + A3 P3` of the
//! angle between `-wo` and `wi`, giving `f = clamp(p δ / (4π |cos_i|), 0, 1) R / |cos_o|` with
//! layer thickness δ (LuxRender clamps its value, which carries the cosine of `wo`, to [0, 1]).
//! Cosine-sampled.

use super::diffuse::Diffuse;
use super::{same_hemisphere, LocalSample};
use crate::spectrum::Rgb;
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug)]
pub struct Asperity {
    pub r: Rgb,
    pub a1: f32,
    pub a2: f32,
    pub a3: f32,
    pub thickness: f32,
}

impl Asperity {
    pub fn f(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        if !same_hemisphere(wo, wi) {
            return Rgb::BLACK;
        }
        let c = (-wo).dot(wi);
        let b = 3.0 * c;
        let phase = 1.0
            + self.a1 * c
            + self.a2 * 0.5 * (b * c - 1.0)
            + self.a3 * 0.5 * (5.0 * c * c * c - b);
        let (co, ci) = (wo.z.abs(), wi.z.abs());
        if co == 0.0 || ci == 0.0 {
            return Rgb::BLACK;
        }
        let p = (phase / (4.0 * PI) * self.thickness / ci).clamp(0.0, 1.0);
        self.r * (p / co)
    }

    pub fn pdf(&self, wo: Vec3A, wi: Vec3A) -> f32 {
        Diffuse::lambert(self.r).pdf(wo, wi)
    }

    pub fn sample(&self, wo: Vec3A, u2: Vec2) -> Option<LocalSample> {
        let wi = Diffuse::lambert(self.r).sample(wo, u2)?.wi;
        Some(LocalSample {
            wi,
            f: self.f(wo, wi),
            pdf: self.pdf(wo, wi),
            specular: false,
        })
    }
}
