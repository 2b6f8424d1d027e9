//! Point light: intensity `L × gain` from a point, optionally normalised by power/efficacy,
//! optionally shaped by a goniometric profile ([`super::gonio`]: `iesname`, `mapname`,
//! `flipz`; LuxRender's `goniometric` light is a point light with a `mapname`). With a profile
//! the intensity toward a direction is `L × gain × profile(light-space direction)` and the
//! power normalisation divides by the profile's mean as well; light subpaths leave in
//! directions drawn ∝ the profile.

use super::gonio::Goniometric;
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
    /// Directional profile with the light's frame it is looked up in.
    profile: Option<Box<Profile>>,
}

/// A goniometric profile and the light-to-world transform (and inverse) it turns with.
#[derive(Debug)]
struct Profile {
    gonio: Goniometric,
    l2w: Mat4,
    w2l: Mat4,
}

impl PointLight {
    pub fn new(params: &ParamSet, l2w: Mat4, color: &LightColor, common: LightCommon) -> Self {
        PointLight::with_profile(params, l2w, color, common, None)
    }

    /// A point light shaped by `profile` (looked up in the light's space).
    pub fn with_profile(
        params: &ParamSet,
        l2w: Mat4,
        color: &LightColor,
        common: LightCommon,
        profile: Option<Goniometric>,
    ) -> Self {
        let power = params.float_or("power", 0.0);
        let efficacy = params.float_or("efficacy", 0.0);
        PointLight::build(params, l2w, color, common, profile, (power, efficacy))
    }

    /// LuxRender's `projection` light: a point light shaped by its slide, with `L` and `gain`
    /// only (LuxRender 1.x reads no `power` or `efficacy` for it; given, they stay unused).
    pub fn projection(
        params: &ParamSet,
        l2w: Mat4,
        color: &LightColor,
        common: LightCommon,
        slide: Goniometric,
    ) -> Self {
        PointLight::build(params, l2w, color, common, Some(slide), (0.0, 0.0))
    }

    fn build(
        params: &ParamSet,
        l2w: Mat4,
        color: &LightColor,
        common: LightCommon,
        profile: Option<Goniometric>,
        (power, efficacy): (f32, f32),
    ) -> Self {
        let gain = params.float_or("gain", 1.0);
        let from = point3(params.point("from").unwrap_or([0.0; 3]));
        let mean = profile.as_ref().map_or(1.0, Goniometric::mean);
        let scale = gain * power_gain(power, efficacy, 4.0 * PI * mean, color.y);
        let l = color.emission.eval(&SurfaceInteraction::default());
        PointLight {
            common,
            falloff_exponent: falloff_exponent(params),
            pos: l2w.transform_point3a(from),
            intensity: l * scale,
            y: color.y * scale * mean,
            profile: profile.map(|gonio| {
                Box::new(Profile {
                    gonio,
                    l2w,
                    w2l: l2w.inverse(),
                })
            }),
        }
    }

    /// Radiant intensity toward the unit world direction `w`.
    pub fn intensity_toward(&self, w: Vec3A) -> Rgb {
        match &self.profile {
            None => self.intensity,
            Some(p) => {
                let d = p.w2l.transform_vector3a(w).normalize_or_zero();
                self.intensity * p.gonio.eval(d)
            }
        }
    }

    pub fn sample_li(&self, r: &Interaction) -> Option<LightSample> {
        let d = self.pos - r.p;
        let d2 = d.length_squared();
        if d2 <= 0.0 {
            return None;
        }
        let wi = d / d2.sqrt();
        Some(LightSample {
            li: self.intensity_toward(-wi) * distance_falloff(d2, self.falloff_exponent),
            wi,
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

    /// A ray leaving the light (light subpaths): uniform over the sphere of directions, or
    /// drawn ∝ the profile.
    pub fn sample_le(&self, u_dir: glam::Vec2, time: f32) -> Option<super::emission::LightRay> {
        let (d, pdf_dir) = match &self.profile {
            None => (
                crate::sampling::uniform_sphere(u_dir),
                crate::sampling::UNIFORM_SPHERE_PDF,
            ),
            Some(p) => {
                let (dl, _) = p.gonio.sample(u_dir)?;
                let d = p.l2w.transform_vector3a(dl).normalize_or_zero();
                (d, self.pdf_dir(d))
            }
        };
        Some(super::emission::LightRay {
            ray: crate::geometry::Ray {
                o: self.pos,
                d,
                t_max: f32::INFINITY,
                time,
            },
            n: Vec3A::ZERO,
            le: self.intensity_toward(d),
            pdf_pos: 1.0,
            pdf_dir,
            uv: glam::Vec2::ZERO,
        })
    }

    /// Solid-angle density of [`Self::sample_le`]'s direction `w` (unit, world).
    pub fn pdf_dir(&self, w: Vec3A) -> f32 {
        match &self.profile {
            None => crate::sampling::UNIFORM_SPHERE_PDF,
            Some(p) => p.gonio.pdf(p.w2l.transform_vector3a(w).normalize_or_zero()),
        }
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
