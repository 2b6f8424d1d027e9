//! Diffuse reflection plus diffuse transmission (a diffuse lobe mirrored to the other side).
//! Each lobe is sampled with probability proportional to its average albedo.

use super::diffuse::Diffuse;
use super::{avg, LocalSample};
use crate::spectrum::Rgb;
use glam::{Vec2, Vec3A};

#[derive(Clone, Copy, Debug)]
pub struct Translucent {
    pub reflect: Diffuse,
    pub transmit: Diffuse,
    pub p_reflect: f32,
}

fn flip(w: Vec3A) -> Vec3A {
    Vec3A::new(w.x, w.y, -w.z)
}

impl Translucent {
    pub fn new(reflect: Diffuse, transmit: Diffuse) -> Translucent {
        let (a, b) = (avg(reflect.r), avg(transmit.r));
        let p_reflect = if a + b > 0.0 { a / (a + b) } else { 0.5 };
        Translucent {
            reflect,
            transmit,
            p_reflect,
        }
    }

    pub fn f(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        if wo.z * wi.z > 0.0 {
            self.reflect.f(wo, wi)
        } else {
            self.transmit.f(wo, flip(wi))
        }
    }

    pub fn pdf(&self, wo: Vec3A, wi: Vec3A) -> f32 {
        if wo.z * wi.z > 0.0 {
            self.p_reflect * self.reflect.pdf(wo, wi)
        } else {
            (1.0 - self.p_reflect) * self.transmit.pdf(wo, flip(wi))
        }
    }

    pub fn sample(&self, wo: Vec3A, u: f32, u2: Vec2) -> Option<LocalSample> {
        let wi = if u < self.p_reflect {
            self.reflect.sample(wo, u2)?.wi
        } else {
            flip(self.transmit.sample(wo, u2)?.wi)
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
