//! Spot light: a point light restricted to a cone from `from` toward `to`, with LuxRender's
//! fourth-power falloff between `coneangle − conedeltaangle` and `coneangle` (degrees).
//!
//! With `iesname` (and/or `mapname`, `flipz`, as the point light reads them, see
//! [`super::gonio`]) the cone is shaped further: the intensity toward a direction is
//! `L × gain × falloff × profile(d)`, d the direction in the spot's frame — z along the axis
//! `from → to` (the IES nadir, so a downlight profile points where the spot points), x and y
//! a frame around it. LuxRender 1.x's spot reads no profile; point and area lights do, and
//! luxfarm gives the spot the same. The power normalisation then divides by the flux of
//! falloff × profile luminance over the cone, integrated on a grid.
//!
//! mental ray's spot (luxfarm's addition, used when `float spread` is given): `spread` is the
//! cosine of the outer half-angle (nothing outside it), `cone` the cosine of the inner
//! half-angle (full intensity inside; default `spread`, a hard edge), and between them the
//! intensity falls off linearly in the cosine, (cosθ − spread)/(cone − spread), as
//! mental ray's `mib_light_spot` and `physical_light` shaders compute it.

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
pub struct SpotLight {
    pub common: LightCommon,
    pub pos: Vec3A,
    /// Unit axis of the cone (world space).
    pub axis: Vec3A,
    pub intensity: Rgb,
    /// k of the 1/d^k falloff (`falloffexponent`, 2 by default).
    pub falloff_exponent: f32,
    cos_total: f32,
    cos_falloff: f32,
    shape: ConeShape,
    y: f32,
    /// The IES / goniometric profile shaping the cone, looked up in the spot's frame.
    profile: Option<Box<Goniometric>>,
    /// The spot's frame: x, y around the axis (z).
    frame: (Vec3A, Vec3A),
}

/// How intensity falls off between the inner and the outer cone.
#[derive(Clone, Copy, Debug, PartialEq)]
enum ConeShape {
    /// LuxRender: the fourth power of the normalised cosine.
    Quartic,
    /// mental ray: linear in the cosine.
    Linear,
}

/// The outer and inner cone cosines and their falloff shape from the parameters.
fn cone(params: &ParamSet) -> (f32, f32, ConeShape) {
    if let Some(spread) = params.float("spread") {
        let spread = if spread.is_finite() {
            spread.clamp(-1.0, 1.0)
        } else {
            0.0
        };
        let inner = params.float_or("cone", spread);
        let inner = if inner.is_finite() {
            inner.clamp(spread, 1.0)
        } else {
            spread
        };
        return (spread, inner, ConeShape::Linear);
    }
    let cone = params.float_or("coneangle", 30.0);
    let delta = params.float_or("conedeltaangle", 5.0);
    (
        cone.to_radians().cos(),
        (cone - delta).to_radians().cos(),
        ConeShape::Quartic,
    )
}

impl SpotLight {
    pub fn new(params: &ParamSet, l2w: Mat4, color: &LightColor, common: LightCommon) -> Self {
        SpotLight::with_profile(params, l2w, color, common, None)
    }

    /// A spot shaped by `profile` (an IES file and/or a map) in its frame.
    pub fn with_profile(
        params: &ParamSet,
        l2w: Mat4,
        color: &LightColor,
        common: LightCommon,
        profile: Option<Goniometric>,
    ) -> Self {
        let gain = params.float_or("gain", 1.0);
        let power = params.float_or("power", 0.0);
        let efficacy = params.float_or("efficacy", 0.0);
        let from = point3(params.point("from").unwrap_or([0.0; 3]));
        let to = point3(params.point("to").unwrap_or([0.0, 0.0, 1.0]));
        let (cos_total, cos_falloff, shape) = cone(params);
        let axis = l2w.transform_vector3a(to - from).normalize_or(Vec3A::Z);
        let mut l = SpotLight {
            common,
            falloff_exponent: falloff_exponent(params),
            pos: l2w.transform_point3a(from),
            axis,
            intensity: color.emission.eval(&SurfaceInteraction::default()),
            cos_total,
            cos_falloff,
            shape,
            y: color.y,
            profile: profile.map(Box::new),
            frame: crate::geometry::frame::coordinate_system(axis),
        };
        let norm = l.flux_solid_angle();
        let scale = gain * power_gain(power, efficacy, norm, color.y);
        l.intensity *= scale;
        l.y = color.y * scale;
        l
    }

    /// The solid angle the power normalisation divides by: LuxRender's cone weighting
    /// without a profile; with one, ∫ falloff × Y(profile) dω over the cone (midpoint rule on
    /// a grid in cos θ and φ).
    fn flux_solid_angle(&self) -> f32 {
        let Some(p) = &self.profile else {
            return cone_solid_angle(self.cos_total, self.cos_falloff);
        };
        const NC: usize = 64;
        const NP: usize = 128;
        let span = 1.0 - self.cos_total;
        let mut sum = 0.0f64;
        for i in 0..NC {
            let c = self.cos_total + span * (i as f32 + 0.5) / NC as f32;
            let f = self.falloff(c);
            if f <= 0.0 {
                continue;
            }
            let sin = (1.0 - c * c).max(0.0).sqrt();
            for j in 0..NP {
                let phi = 2.0 * PI * (j as f32 + 0.5) / NP as f32;
                let d = Vec3A::new(sin * phi.cos(), sin * phi.sin(), c);
                sum += f64::from(f * luminance(p.eval(d)));
            }
        }
        (sum * f64::from(span) * 2.0 * std::f64::consts::PI / (NC * NP) as f64) as f32
    }

    /// The profile's value toward the unit world direction `w` (1 without a profile).
    fn shaped(&self, w: Vec3A) -> Rgb {
        match &self.profile {
            None => Rgb::WHITE,
            Some(p) => {
                let (x, y) = self.frame;
                p.eval(Vec3A::new(w.dot(x), w.dot(y), w.dot(self.axis)))
            }
        }
    }

    fn falloff(&self, cos: f32) -> f32 {
        if cos < self.cos_total {
            0.0
        } else if cos >= self.cos_falloff {
            1.0
        } else {
            let d = (cos - self.cos_total) / (self.cos_falloff - self.cos_total);
            match self.shape {
                ConeShape::Quartic => d.powi(4),
                ConeShape::Linear => d,
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
        let li = self.intensity_toward(-wi);
        if li.is_black() {
            return None;
        }
        Some(LightSample {
            li: li * distance_falloff(d2, self.falloff_exponent),
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

    /// Radiant intensity toward unit direction `w` (the cone's falloff and the profile
    /// applied).
    pub fn intensity_toward(&self, w: Vec3A) -> Rgb {
        let f = self.falloff(w.dot(self.axis));
        if f <= 0.0 {
            return Rgb::BLACK;
        }
        self.intensity * self.shaped(w) * f
    }

    /// A ray leaving the light (light subpaths): uniform over the cone of `coneangle`.
    pub fn sample_le(&self, u_dir: glam::Vec2, time: f32) -> Option<super::emission::LightRay> {
        let local = crate::sampling::uniform_cone(u_dir, self.cos_total);
        let (s, t) = crate::geometry::frame::coordinate_system(self.axis);
        let d = (s * local.x + t * local.y + self.axis * local.z).normalize_or_zero();
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
            pdf_dir: self.pdf_dir(d),
            uv: glam::Vec2::ZERO,
        })
    }

    /// Solid-angle density of [`Self::sample_le`] leaving in unit direction `w`.
    pub fn pdf_dir(&self, w: Vec3A) -> f32 {
        if w.dot(self.axis) >= self.cos_total {
            crate::sampling::uniform_cone_pdf(self.cos_total)
        } else {
            0.0
        }
    }

    pub fn power(&self) -> f32 {
        self.y * self.flux_solid_angle()
    }
}

fn luminance(c: Rgb) -> f32 {
    0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b
}

/// The solid angle the power normalisation divides by: the full inner cone plus half the
/// band between the cones (LuxRender's weighting for its quartic falloff; exact for the
/// linear one, whose mean over the band, uniform in the cosine, is ½).
fn cone_solid_angle(cos_total: f32, cos_falloff: f32) -> f32 {
    2.0 * PI * (1.0 - 0.5 * (cos_falloff + cos_total))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::Emission;

    #[test]
    fn cone_and_falloff() {
        let color = LightColor {
            emission: Emission::Const(Rgb::WHITE),
            y: 1.0,
        };
        let common = LightCommon::single(0);
        let l = SpotLight::new(&ParamSet::new(), Mat4::IDENTITY, &color, common);
        // Light at the origin pointing +z: a point straight ahead is fully lit.
        let at = |p: Vec3A| Interaction {
            p,
            ..Default::default()
        };
        let s = l.sample_li(&at(Vec3A::new(0.0, 0.0, 2.0))).unwrap();
        assert!((s.li.r - 0.25).abs() < 1e-6);
        // 40° off axis: outside the 30° cone.
        let a = 40f32.to_radians();
        assert!(l
            .sample_li(&at(Vec3A::new(a.sin(), 0.0, a.cos())))
            .is_none());
        // 27.5°: inside the falloff band, partially lit.
        let a = 27.5f32.to_radians();
        let s = l.sample_li(&at(Vec3A::new(a.sin(), 0.0, a.cos()))).unwrap();
        assert!(s.li.r > 0.0 && s.li.r < 1.0);
    }

    #[test]
    fn mental_ray_spread_falls_off_linearly_in_the_cosine() {
        // spread cos 40°, inner cone cos 20°: at 30° the intensity is the cosine's share.
        let color = LightColor {
            emission: Emission::Const(Rgb::splat(4.0)),
            y: 4.0,
        };
        let mut ps = ParamSet::new();
        let (c40, c20) = (40f32.to_radians().cos(), 20f32.to_radians().cos());
        ps.add("spread", crate::lxs::ParamValue::Float(vec![c40]));
        ps.add("cone", crate::lxs::ParamValue::Float(vec![c20]));
        let l = SpotLight::new(&ps, Mat4::IDENTITY, &color, LightCommon::single(0));
        let at = |deg: f32| {
            let a = deg.to_radians();
            Interaction {
                p: Vec3A::new(a.sin(), 0.0, a.cos()) * 2.0,
                ..Default::default()
            }
        };
        // Distance 2: intensity 4 gives 1 on axis.
        assert!((l.sample_li(&at(0.0)).unwrap().li.r - 1.0).abs() < 1e-5);
        assert!((l.sample_li(&at(15.0)).unwrap().li.r - 1.0).abs() < 1e-5);
        let want = (30f32.to_radians().cos() - c40) / (c20 - c40);
        assert!((l.sample_li(&at(30.0)).unwrap().li.r - want).abs() < 1e-5);
        assert!(l.sample_li(&at(41.0)).is_none());
        // Without an inner cone the edge is hard.
        let mut hard = ParamSet::new();
        hard.add("spread", crate::lxs::ParamValue::Float(vec![c40]));
        let l = SpotLight::new(&hard, Mat4::IDENTITY, &color, LightCommon::single(0));
        assert!((l.sample_li(&at(39.0)).unwrap().li.r - 1.0).abs() < 1e-5);
    }
}
