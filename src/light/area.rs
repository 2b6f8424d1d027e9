//! Area light: emission `L × gain` (radiance) on the side of a shape's oriented geometric
//! normal, with LuxRender's power/efficacy normalisation (defaults 100 W, 17 lm/W:
//! `gain *= power × efficacy / (area × π × Y(L))` when that is positive and finite).
//! One light per shape; points are sampled uniformly by area through [`ShapeSampler`].
//! The emission profile ([`EmissionProfile`]: falloff exponent, cosine exponent, two sides,
//! camera visibility) is luxfarm's addition; its defaults are LuxRender's area light. This is
//! also mental ray's `object` area light: the emitting geometry is an instance's own.
//!
//! **IES profiles** (`iesname`, and/or `mapname`, `flipz`, read as the point light reads them,
//! see [`super::gonio`]), as LuxRender 1.x's area light applies them: the profile f is looked
//! up with the leaving direction in the surface's frame (z the oriented geometric normal, so
//! an IES nadir points along the normal; x, y a frame around it) and replaces the one-sided
//! Lambertian emission: the radiance toward ω is `L × gain × π × f(ω) / ∫f dω` — LuxRender's
//! `π · f / Average_f` with Average_f the integral of f over the sphere — on both sides as
//! far as the profile reaches (`twosided` and `cosineexponent` are then unused). The profile
//! is therefore deformed by the shape, as LuxRender's documentation warns. Power/efficacy
//! normalise by `area × π × Y(L)` as without a profile. Light subpaths leave in directions
//! drawn ∝ the profile.
use super::emitter::EmissionProfile;
use super::falloff::radiance_falloff;
use super::gonio::Goniometric;
use super::{power_gain, Emission, LightColor, LightCommon, LightSample, ShapeSampler};
use crate::geometry::frame::coordinate_system;
use crate::geometry::{Interaction, Shading, SurfaceInteraction};
use crate::lxs::ParamSet;
use crate::spectrum::Rgb;
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;

#[derive(Debug)]
pub struct AreaLight {
    pub common: LightCommon,
    /// The emitter index the [`ShapeSampler`] knows this shape by.
    pub shape: u32,
    pub emission: Emission,
    /// gain × power normalisation.
    pub scale: f32,
    pub area: f32,
    pub profile: EmissionProfile,
    y: f32,
    /// The IES / goniometric profile replacing the Lambertian emission, if any.
    ies: Option<Box<IesEmission>>,
}

/// A profile with LuxRender's factor π / ∫f dω.
#[derive(Debug)]
struct IesEmission {
    gonio: Goniometric,
    norm: f32,
}

impl IesEmission {
    /// The profile toward the unit world direction `w` leaving a point of normal `n`.
    fn eval(&self, n: Vec3A, w: Vec3A) -> Rgb {
        self.gonio.eval(to_local(n, w)) * self.norm
    }
}

/// `w` in the frame of normal `n` (z = n).
fn to_local(n: Vec3A, w: Vec3A) -> Vec3A {
    let (s, t) = coordinate_system(n);
    Vec3A::new(w.dot(s), w.dot(t), w.dot(n))
}

/// The local direction `d` in world space, for the frame of normal `n`.
fn to_world(n: Vec3A, d: Vec3A) -> Vec3A {
    let (s, t) = coordinate_system(n);
    (s * d.x + t * d.y + n * d.z).normalize_or_zero()
}

impl AreaLight {
    pub fn new(
        params: &ParamSet,
        color: &LightColor,
        shape: u32,
        area: f32,
        common: LightCommon,
        profile: EmissionProfile,
    ) -> Self {
        let gain = params.float_or("gain", 1.0);
        let power = params.float_or("power", 100.0);
        let efficacy = params.float_or("efficacy", 17.0);
        let scale = gain * power_gain(power, efficacy, area * profile.flux_per_area(), color.y);
        AreaLight {
            common,
            shape,
            emission: color.emission.clone(),
            scale,
            area,
            profile,
            y: color.y,
            ies: None,
        }
    }

    /// An area light whose emission follows `gonio` (an IES profile and/or a map).
    pub fn with_ies(
        params: &ParamSet,
        color: &LightColor,
        shape: u32,
        area: f32,
        common: LightCommon,
        profile: EmissionProfile,
        gonio: Option<Goniometric>,
    ) -> Self {
        let mut l = AreaLight::new(params, color, shape, area, common, profile);
        l.ies = gonio.and_then(|g| {
            // ∫ f dω = 4π × the profile's solid-angle mean.
            let integral = 4.0 * PI * g.mean();
            (integral > 0.0 && integral.is_finite()).then(|| {
                Box::new(IesEmission {
                    gonio: g,
                    norm: PI / integral,
                })
            })
        });
        l
    }

    /// Radiance leaving the light at `si` in direction `w` (unit), toward a point at squared
    /// distance `d2` (`None`: seen by the camera; see [`EmissionProfile::factor`]).
    pub fn le(&self, si: &SurfaceInteraction, w: glam::Vec3A, d2: Option<f32>) -> Rgb {
        if let Some(ies) = &self.ies {
            let fall = d2.map_or(1.0, |d2| {
                radiance_falloff(d2, self.profile.falloff_exponent)
            });
            let f = ies.eval(si.it.n, w) * fall;
            return if f.is_black() {
                Rgb::BLACK
            } else {
                self.emission.eval(si) * f * self.scale
            };
        }
        let f = self.profile.factor(si.it.n.dot(w), d2);
        if f > 0.0 {
            self.emission.eval(si) * (self.scale * f)
        } else {
            Rgb::BLACK
        }
    }

    pub fn sample_li<S: ShapeSampler + ?Sized>(
        &self,
        r: &Interaction,
        u: Vec2,
        u_pick: f32,
        shapes: &S,
    ) -> Option<LightSample> {
        let (it, uv, pdf_area) = shapes.sample_shape(self.shape, u, u_pick, r.time)?;
        let d = it.p - r.p;
        let d2 = d.length_squared();
        if d2 <= 0.0 || pdf_area <= 0.0 {
            return None;
        }
        let wi = d / d2.sqrt();
        let cos_l = it.n.dot(-wi).abs();
        if cos_l <= 0.0 {
            return None;
        }
        let si = SurfaceInteraction {
            it,
            wo: -wi,
            uv,
            shading: Shading {
                n: it.n,
                ..Default::default()
            },
            ..Default::default()
        };
        let li = self.le(&si, -wi, Some(d2));
        if li.is_black() {
            return None;
        }
        Some(LightSample {
            li,
            wi,
            pdf: pdf_area * d2 / cos_l,
            p_light: it,
            delta: false,
            infinite: false,
        })
    }

    /// A ray leaving the light (light subpaths): a point uniform by area, a direction
    /// cosine-distributed about the normal.
    pub fn sample_le(
        &self,
        u_pos: Vec2,
        u_dir: Vec2,
        u_pick: f32,
        time: f32,
        shapes: &dyn ShapeSampler,
    ) -> Option<super::emission::LightRay> {
        let (mut it, uv, pdf_pos) = shapes.sample_shape(self.shape, u_pos, u_pick, time)?;
        it.time = time;
        let local = match &self.ies {
            None => crate::sampling::cosine_hemisphere(u_dir),
            Some(ies) => ies.gonio.sample(u_dir)?.0,
        };
        let d = to_world(it.n, local);
        let pdf_dir = self.pdf_dir(it.n, d);
        if pdf_dir <= 0.0 {
            return None;
        }
        let si = SurfaceInteraction {
            it,
            wo: d,
            uv,
            shading: Shading {
                n: it.n,
                ..Default::default()
            },
            ..Default::default()
        };
        Some(super::emission::LightRay {
            ray: it.spawn_ray(d),
            n: it.n,
            le: self.le(&si, d, None),
            pdf_pos,
            pdf_dir,
            uv,
        })
    }

    /// Solid-angle density with which [`Self::sample_le`] leaves a point of normal `n` in
    /// unit direction `w`: cosine-weighted about the normal, or ∝ the IES profile.
    pub fn pdf_dir(&self, n: Vec3A, w: Vec3A) -> f32 {
        match &self.ies {
            None => {
                let c = n.dot(w);
                if c > 0.0 {
                    c / PI
                } else {
                    0.0
                }
            }
            Some(ies) => ies.gonio.pdf(to_local(n, w)),
        }
    }

    /// Solid-angle pdf of reaching `hit` on this light from `r` by [`Self::sample_li`].
    pub fn pdf_li(&self, r: &Interaction, hit: &SurfaceInteraction) -> f32 {
        let d = hit.it.p - r.p;
        let d2 = d.length_squared();
        let cos_l = hit.it.n.dot(-d).abs() / d2.sqrt();
        if cos_l <= 0.0 || self.area <= 0.0 {
            return 0.0;
        }
        d2 / (cos_l * self.area)
    }

    pub fn power(&self) -> f32 {
        self.scale * self.area * self.profile.flux_per_area() * self.y
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lxs::ParamValue;
    use glam::Vec3A;

    /// A unit square at z = 1 facing down.
    struct Square;
    impl ShapeSampler for Square {
        fn sample_shape(
            &self,
            _: u32,
            u: Vec2,
            _: f32,
            _: f32,
        ) -> Option<(Interaction, Vec2, f32)> {
            let it = Interaction {
                p: Vec3A::new(u.x - 0.5, u.y - 0.5, 1.0),
                n: -Vec3A::Z,
                ..Default::default()
            };
            Some((it, u, 1.0))
        }
    }

    #[test]
    fn one_sided_emission_and_normalisation() {
        let mut ps = ParamSet::new();
        ps.add("power", ParamValue::Float(vec![0.0]));
        let color = LightColor {
            emission: Emission::Const(Rgb::splat(2.0)),
            y: 2.0,
        };
        let common = LightCommon::single(0);
        let l = AreaLight::new(&ps, &color, 0, 1.0, common, EmissionProfile::default());
        let below = Interaction::default();
        let s = l.sample_li(&below, Vec2::splat(0.5), 0.0, &Square).unwrap();
        assert!((s.li.r - 2.0).abs() < 1e-6 && (s.pdf - 1.0).abs() < 1e-5);
        let above = Interaction {
            p: Vec3A::new(0.0, 0.0, 2.0),
            ..Default::default()
        };
        assert!(l
            .sample_li(&above, Vec2::splat(0.5), 0.0, &Square)
            .is_none());
        // Default power 100 W × 17 lm/W: flux = π · area · Y(L · gain).
        let l = AreaLight::new(
            &ParamSet::new(),
            &color,
            0,
            1.0,
            common,
            EmissionProfile::default(),
        );
        assert!((l.power() - 1700.0).abs() < 1e-2);
    }

    #[test]
    fn irradiance_estimate_matches_analytic() {
        // Irradiance at the centre below a unit square at height 1 with L = 1:
        // E = ∫ L cosθ dω; Monte Carlo with the light's own samples.
        let mut ps = ParamSet::new();
        ps.add("power", ParamValue::Float(vec![0.0]));
        let color = LightColor {
            emission: Emission::Const(Rgb::WHITE),
            y: 1.0,
        };
        let l = AreaLight::new(
            &ps,
            &color,
            0,
            1.0,
            LightCommon::single(0),
            EmissionProfile::default(),
        );
        let r = Interaction::default();
        let n = 256;
        let mut e = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let s = l.sample_li(&r, u, 0.0, &Square).unwrap();
                e += f64::from(s.li.r * s.wi.z / s.pdf);
                assert!(
                    (l.pdf_li(
                        &r,
                        &SurfaceInteraction {
                            it: s.p_light,
                            ..Default::default()
                        }
                    ) - s.pdf)
                        .abs()
                        < 1e-3 * s.pdf
                );
            }
        }
        e /= (n * n) as f64;
        // Closed form for a centred square of side a at distance h: 4·atan(a²/(2h·sqrt(a²/2·... ))).
        // Use the polygon formula: E = Σ_edges ½ γ_i (n·(v_i × v_{i+1})/|..|) → 0.9 approx; check
        // against a fine midpoint quadrature instead.
        let m = 1000;
        let mut q = 0.0f64;
        for i in 0..m {
            for j in 0..m {
                let x = (i as f64 + 0.5) / m as f64 - 0.5;
                let y = (j as f64 + 0.5) / m as f64 - 0.5;
                let d2 = x * x + y * y + 1.0;
                q += 1.0 / (d2 * d2) / (m * m) as f64;
            }
        }
        assert!((e - q).abs() < 1e-3 * q, "{e} vs {q}");
    }
}
