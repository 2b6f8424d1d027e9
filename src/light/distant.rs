//! Distant light: parallel light of irradiance `L × gain` arriving from direction
//! `from − to`; with `theta` > 0 (degrees) the directions fill a cone of that half-angle,
//! with the same total irradiance (radiance = irradiance / cone solid angle).

use super::{point3, LightColor, LightCommon, LightSample};
use crate::geometry::frame::coordinate_system;
use crate::geometry::{Interaction, SurfaceInteraction};
use crate::lxs::ParamSet;
use crate::sampling::{uniform_cone, uniform_cone_pdf};
use crate::spectrum::Rgb;
use glam::{Mat4, Vec2, Vec3A};
use std::f32::consts::PI;

#[derive(Debug)]
pub struct DistantLight {
    pub common: LightCommon,
    /// Unit direction toward the light.
    pub to_light: Vec3A,
    pub irradiance: Rgb,
    cos_theta: f32,
    y: f32,
    pub world_radius: f32,
}

impl DistantLight {
    pub fn new(params: &ParamSet, l2w: Mat4, color: &LightColor, common: LightCommon) -> Self {
        let gain = params.float_or("gain", 1.0);
        let from = point3(params.point("from").unwrap_or([0.0; 3]));
        let to = point3(params.point("to").unwrap_or([0.0, 0.0, 1.0]));
        let theta = params.float_or("theta", 0.0).clamp(0.0, 90.0);
        let to_light = l2w.transform_vector3a(from - to).normalize_or(Vec3A::Z);
        DistantLight {
            common,
            to_light,
            irradiance: color.emission.eval(&SurfaceInteraction::default()) * gain,
            cos_theta: theta.to_radians().cos(),
            y: color.y * gain,
            world_radius: 1.0,
        }
    }

    pub fn is_delta(&self) -> bool {
        self.cos_theta >= 1.0
    }

    fn radiance(&self) -> Rgb {
        self.irradiance * uniform_cone_pdf(self.cos_theta)
    }

    pub fn sample_li(&self, r: &Interaction, u: Vec2) -> Option<LightSample> {
        let (wi, li, pdf) = if self.is_delta() {
            (self.to_light, self.irradiance, 1.0)
        } else {
            let (s, t) = coordinate_system(self.to_light);
            let l = uniform_cone(u, self.cos_theta);
            let wi = s * l.x + t * l.y + self.to_light * l.z;
            (wi, self.radiance(), uniform_cone_pdf(self.cos_theta))
        };
        Some(LightSample::from_infinity(
            r,
            wi,
            li,
            pdf,
            self.is_delta(),
            self.world_radius,
        ))
    }

    pub fn pdf_li(&self, wi: Vec3A) -> f32 {
        if !self.is_delta() && wi.dot(self.to_light) >= self.cos_theta {
            uniform_cone_pdf(self.cos_theta)
        } else {
            0.0
        }
    }

    pub fn le(&self, dir: Vec3A) -> Rgb {
        if self.pdf_li(dir) > 0.0 {
            self.radiance()
        } else {
            Rgb::BLACK
        }
    }

    pub fn power(&self) -> f32 {
        self.y * PI * self.world_radius * self.world_radius
    }
}
