//! Point light: intensity `L × gain` from a point, optionally normalised by power/efficacy.

use super::{
    distance_falloff, falloff_exponent, point3, power_gain, LightColor, LightCommon, LightSample,
};
use crate::geometry::{Interaction, SurfaceInteraction};
use crate::lxs::ParamSet;
use crate::spectrum::Rgb;
use glam::{Mat4, Vec3A};
use std::f32::consts::PI;

#[derive(Debug)]
pub struct PointLight {
    pub common: LightCommon,
    pub pos: Vec3A,
    /// Radiant intensity (W/sr).
    pub intensity: Rgb,
    /// k of the 1/d^k falloff (`falloffexponent`, 2 by default).
    pub falloff_exponent: f32,
    y: f32,
}

impl PointLight {
    pub fn new(params: &ParamSet, l2w: Mat4, color: &LightColor, common: LightCommon) -> Self {
        let gain = params.float_or("gain", 1.0);
        let power = params.float_or("power", 0.0);
        let efficacy = params.float_or("efficacy", 0.0);
        let from = point3(params.point("from").unwrap_or([0.0; 3]));
        let scale = gain * power_gain(power, efficacy, 4.0 * PI, color.y);
        let l = color.emission.eval(&SurfaceInteraction::default());
        PointLight {
            common,
            falloff_exponent: falloff_exponent(params),
            pos: l2w.transform_point3a(from),
            intensity: l * scale,
            y: color.y * scale,
        }
    }

    pub fn sample_li(&self, r: &Interaction) -> Option<LightSample> {
        let d = self.pos - r.p;
        let d2 = d.length_squared();
        if d2 <= 0.0 {
            return None;
        }
        Some(LightSample {
            li: self.intensity * distance_falloff(d2, self.falloff_exponent),
            wi: d / d2.sqrt(),
            pdf: 1.0,
            p_light: Interaction {
                p: self.pos,
                time: r.time,
                ..Default::default()
            },
            delta: true,
            infinite: false,
        })
    }

    pub fn power(&self) -> f32 {
        4.0 * PI * self.y
    }

    /// A ray leaving the light (light subpaths): uniform over the sphere of directions.
    pub fn sample_le(&self, u_dir: glam::Vec2, time: f32) -> Option<super::emission::LightRay> {
        let d = crate::sampling::uniform_sphere(u_dir);
        Some(super::emission::LightRay {
            ray: crate::geometry::Ray {
                o: self.pos,
                d,
                t_max: f32::INFINITY,
                time,
            },
            n: Vec3A::ZERO,
            le: self.intensity,
            pdf_pos: 1.0,
            pdf_dir: self.pdf_dir(),
        })
    }

    /// Solid-angle density of [`Self::sample_le`]'s directions.
    pub fn pdf_dir(&self) -> f32 {
        crate::sampling::UNIFORM_SPHERE_PDF
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::Emission;
    use crate::lxs::ParamValue;

    #[test]
    fn falloff_exponent_sets_the_power_of_distance() {
        // Intensity 3 at distance 2: irradiance 3/2^k for k = 0, 1, 2 (hand-computed).
        for (k, want) in [(0.0f32, 3.0f32), (1.0, 1.5), (2.0, 0.75)] {
            let mut ps = ParamSet::new();
            ps.add("from", ParamValue::Point(vec![[0.0, 0.0, 2.0]]));
            ps.add("falloffexponent", ParamValue::Float(vec![k]));
            let color = LightColor {
                emission: Emission::Const(Rgb::splat(3.0)),
                y: 3.0,
            };
            let common = LightCommon::single(0);
            let l = PointLight::new(&ps, Mat4::IDENTITY, &color, common);
            let s = l.sample_li(&Interaction::default()).unwrap();
            assert!((s.li.g - want).abs() < 1e-6, "k={k}: {}", s.li.g);
        }
    }

    #[test]
    fn inverse_square_and_power_normalisation() {
        let mut ps = ParamSet::new();
        ps.add("from", ParamValue::Point(vec![[0.0, 0.0, 2.0]]));
        let color = LightColor {
            emission: Emission::Const(Rgb::splat(3.0)),
            y: 3.0,
        };
        let common = LightCommon::single(0);
        let l = PointLight::new(&ps, Mat4::IDENTITY, &color, common);
        let s = l.sample_li(&Interaction::default()).unwrap();
        assert!((s.li.g - 3.0 / 4.0).abs() < 1e-6);
        assert!((s.wi - Vec3A::Z).length() < 1e-6);
        ps.add("power", ParamValue::Float(vec![100.0]));
        ps.add("efficacy", ParamValue::Float(vec![17.0]));
        let l = PointLight::new(&ps, Mat4::IDENTITY, &color, common);
        // Luminous flux = 4π · Y(I) = power × efficacy.
        assert!((l.power() - 1700.0).abs() < 1e-2);
    }
}
