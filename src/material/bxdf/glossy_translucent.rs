//! LuxRender's glossytranslucent: a double-sided Schlick coating BRDF (front parameters when
//! `wo` is above the surface, back-face parameters below) plus a diffuse BTDF
//! `Kt (1 - Kd) / π · (1 - S1)(1 - S2) / (1 - (S1 + S2)/2)`, where S1 and S2 are the Schlick
//! reflectances of both faces at the angle between `wi` and the half vector of `wi` and the
//! mirrored `wo`, attenuated by each face's coating absorption. Reflection and transmission
//! are each sampled half of the time, as LuxRender's two-component BSDF does.

use super::fresnel::schlick;
use super::schlick::Coating;
use super::{cosine_hemisphere, LocalSample};
use crate::spectrum::Rgb;
use glam::{Vec2, Vec3A};
use std::f32::consts::FRAC_1_PI;

fn flip(w: Vec3A) -> Vec3A {
    Vec3A::new(w.x, w.y, -w.z)
}

#[derive(Clone, Copy, Debug)]
pub struct GlossyTranslucentLobes {
    pub front: Coating,
    pub back: Coating,
    pub kt: Rgb,
}

impl GlossyTranslucentLobes {
    fn reflect_f(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        if wo.z > 0.0 {
            self.front.f(wo, wi)
        } else {
            self.back.f(flip(wo), flip(wi))
        }
    }

    fn reflect_pdf(&self, wo: Vec3A, wi: Vec3A) -> f32 {
        if wo.z > 0.0 {
            self.front.pdf(wo, wi)
        } else {
            self.back.pdf(flip(wo), flip(wi))
        }
    }

    fn transmit_f(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        let (ci, co) = (wi.z.abs(), wo.z.abs());
        if ci == 0.0 || co == 0.0 {
            return Rgb::BLACK;
        }
        let h = Vec3A::new(wi.x + wo.x, wi.y + wo.y, wi.z - wo.z).normalize_or_zero();
        let u = wi.dot(h).abs();
        let s1 = schlick(u, self.front.coat.ks);
        let s2 = schlick(u, self.back.coat.ks);
        let denom = Rgb::WHITE - (s1 + s2) * 0.5;
        let mut s = (Rgb::WHITE - s1) * (Rgb::WHITE - s2);
        s = Rgb::new(
            safe_div(s.r, denom.r),
            safe_div(s.g, denom.g),
            safe_div(s.b, denom.b),
        );
        let (df, db) = (self.front.coat.depth, self.back.coat.depth);
        if df > 0.0 || db > 0.0 {
            let (cf, cb) = if wi.z > 0.0 { (ci, co) } else { (co, ci) };
            let (af, ab) = (self.front.coat.ka, self.back.coat.ka);
            s *= Rgb::new(
                (-af.r * df / cf - ab.r * db / cb).exp(),
                (-af.g * df / cf - ab.g * db / cb).exp(),
                (-af.b * df / cf - ab.b * db / cb).exp(),
            );
        }
        s * self.kt * (Rgb::WHITE - self.front.base.r) * FRAC_1_PI
    }

    pub fn f(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        if wo.z * wi.z > 0.0 {
            self.reflect_f(wo, wi)
        } else {
            self.transmit_f(wo, wi)
        }
    }

    pub fn pdf(&self, wo: Vec3A, wi: Vec3A) -> f32 {
        if wo.z * wi.z > 0.0 {
            0.5 * self.reflect_pdf(wo, wi)
        } else {
            0.5 * wi.z.abs() * FRAC_1_PI
        }
    }

    pub fn sample(&self, wo: Vec3A, u: f32, u2: Vec2) -> Option<LocalSample> {
        let wi = if u < 0.5 {
            let u = u * 2.0;
            if wo.z > 0.0 {
                self.front.sample(wo, u, u2)?.wi
            } else {
                flip(self.back.sample(flip(wo), u, u2)?.wi)
            }
        } else {
            let mut wi = cosine_hemisphere(u2);
            if wo.z > 0.0 {
                wi.z = -wi.z;
            }
            wi
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

fn safe_div(a: f32, b: f32) -> f32 {
    if b > 0.0 {
        a / b
    } else {
        0.0
    }
}
