//! LuxRender's car paint BSDF (after Günther et al. 2005): up to three Schlick-distribution
//! microfacet lobes `Ks_i · F_schlick(R_i) · D G / (4 cos_o cos_i)` (roughness `M_i²`, front
//! side only) over a base `A · Kd/π · (1 - S) + S/(4π)` with `S = (1 - |wi·h|)^5` and coating
//! absorption `A` (the Schlick BRDF with zero specular colour and roughness 1 that LuxRender
//! uses as the base). Components are sampled with equal probability; the pdf is their mean.

use super::fresnel::schlick;
use super::schlick::SchlickDist;
use super::{cosine_hemisphere, reflect, same_hemisphere, LocalSample};
use crate::spectrum::Rgb;
use glam::{Vec2, Vec3A};
use std::f32::consts::{FRAC_1_PI, PI};

#[derive(Clone, Copy, Debug)]
pub struct PaintLayer {
    pub ks: Rgb,
    pub r0: f32,
    pub dist: SchlickDist,
}

#[derive(Clone, Copy, Debug)]
pub struct CarPaintLobes {
    pub kd: Rgb,
    pub ka: Rgb,
    pub depth: f32,
    pub layers: [Option<PaintLayer>; 3],
}

impl CarPaintLobes {
    fn count(&self) -> usize {
        1 + self.layers.iter().flatten().count()
    }

    fn base_f(&self, wo: Vec3A, wi: Vec3A, h: Vec3A) -> Rgb {
        let s = (1.0 - wi.dot(h).abs().min(1.0)).powi(5);
        let a = if self.depth > 0.0 {
            let k = self.depth * (1.0 / wi.z.abs().max(1e-4) + 1.0 / wo.z.abs().max(1e-4));
            self.ka.map(|x| (-x * k).exp())
        } else {
            Rgb::WHITE
        };
        a * self.kd * (FRAC_1_PI * (1.0 - s)) + Rgb::splat(s / (4.0 * PI))
    }

    pub fn f(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        if !same_hemisphere(wo, wi) {
            return Rgb::BLACK;
        }
        let mut h = (wo + wi).normalize_or_zero();
        if h == Vec3A::ZERO {
            return Rgb::BLACK;
        }
        if h.z < 0.0 {
            h = -h;
        }
        let mut sum = self.base_f(wo, wi, h);
        if wo.z > 0.0 {
            let (co, ci) = (wo.z, wi.z);
            for l in self.layers.iter().flatten() {
                let g = l.dist.g1(co) * l.dist.g1(ci);
                let fr = schlick(wi.dot(h), Rgb::splat(l.r0));
                sum += l.ks * fr * (l.dist.d(h) * g / (4.0 * co * ci));
            }
        }
        sum
    }

    pub fn pdf(&self, wo: Vec3A, wi: Vec3A) -> f32 {
        if !same_hemisphere(wo, wi) {
            return 0.0;
        }
        let mut sum = wi.z.abs() * FRAC_1_PI;
        if wo.z > 0.0 {
            let h = (wo + wi).normalize_or_zero();
            let oh = wo.dot(h);
            if h != Vec3A::ZERO && oh > 0.0 {
                for l in self.layers.iter().flatten() {
                    sum += l.dist.pdf_h(h) / (4.0 * oh);
                }
            }
        }
        sum / self.count() as f32
    }

    pub fn sample(&self, wo: Vec3A, u: f32, u2: Vec2) -> Option<LocalSample> {
        let n = self.count();
        let pick = ((u * n as f32) as usize).min(n - 1);
        let wi = if pick == 0 || wo.z <= 0.0 {
            let mut wi = cosine_hemisphere(u2);
            if wo.z < 0.0 {
                wi.z = -wi.z;
            }
            wi
        } else {
            let l = self.layers.iter().flatten().nth(pick - 1)?;
            reflect(wo, l.dist.sample_h(u2))
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
