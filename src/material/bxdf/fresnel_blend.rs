//! LuxRender's `FresnelBlend` BRDF (Ashikhmin–Shirley's coupled diffuse/specular model with
//! a Schlick distribution), the BSDF of glossy_lossy and of the legacy plastic and substrate
//! materials:
//!
//! `f = 28/(23π) Kd (1 - Ks) A (1 - (1 - cos_i/2)^5)(1 - (1 - cos_o/2)^5)
//!      + D(h) S(|wi·h|) / (4 |wi·h| max(cos_i, cos_o))`,
//! `S(c) = Ks + (1 - Ks)(1 - c)^5`, `A` the coating absorption of `Ka` over depth `d`.
//! Half of the samples are cosine distributed, half follow the distribution's half vectors;
//! the pdf is the average of both densities.

use super::schlick::{SchlickCoat, SchlickDist};
use super::{cosine_hemisphere, reflect, same_hemisphere, LocalSample};
use crate::spectrum::Rgb;
use glam::{Vec2, Vec3A};
use std::f32::consts::{FRAC_1_PI, PI};

#[derive(Clone, Copy, Debug)]
pub struct FresnelBlend {
    pub kd: Rgb,
    pub ks: Rgb,
    pub ka: Rgb,
    pub depth: f32,
    pub dist: SchlickDist,
}

fn pow5(x: f32) -> f32 {
    let x2 = x * x;
    x2 * x2 * x
}

impl FresnelBlend {
    fn half(wo: Vec3A, wi: Vec3A) -> Option<Vec3A> {
        let h = (wo + wi).normalize_or_zero();
        if h == Vec3A::ZERO {
            return None;
        }
        Some(if h.z < 0.0 { -h } else { h })
    }

    pub fn f(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        if !same_hemisphere(wo, wi) {
            return Rgb::BLACK;
        }
        let (ci, co) = (wi.z.abs(), wo.z.abs());
        let Some(h) = Self::half(wo, wi) else {
            return Rgb::BLACK;
        };
        let absorption = SchlickCoat {
            ks: self.ks,
            ka: self.ka,
            depth: self.depth,
            dist: self.dist,
            multibounce: false,
        }
        .absorption(co, ci);
        let diffuse = self.kd
            * (Rgb::WHITE - self.ks)
            * absorption
            * (28.0 / (23.0 * PI) * (1.0 - pow5(1.0 - 0.5 * ci)) * (1.0 - pow5(1.0 - 0.5 * co)));
        let cih = wi.dot(h).abs();
        if cih == 0.0 {
            return diffuse;
        }
        let s = self.ks + (Rgb::WHITE - self.ks) * pow5(1.0 - cih);
        diffuse + s * (self.dist.d(h) / (4.0 * cih * ci.max(co)))
    }

    pub fn pdf(&self, wo: Vec3A, wi: Vec3A) -> f32 {
        if !same_hemisphere(wo, wi) {
            return 0.0;
        }
        let Some(h) = Self::half(wo, wi) else {
            return 0.0;
        };
        let oh = wo.dot(h).abs();
        let spec = if oh > 0.0 {
            self.dist.pdf_h(h) / (4.0 * oh)
        } else {
            0.0
        };
        0.5 * (wi.z.abs() * FRAC_1_PI + spec)
    }

    pub fn sample(&self, wo: Vec3A, u: f32, u2: Vec2) -> Option<LocalSample> {
        let wi = if u < 0.5 {
            let mut wi = cosine_hemisphere(u2);
            if wo.z < 0.0 {
                wi.z = -wi.z;
            }
            wi
        } else {
            reflect(wo, self.dist.sample_h(u2))
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
