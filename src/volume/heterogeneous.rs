//! `heterogeneous`: a medium whose absorption `sigma_a` and scattering `sigma_s` vary in
//! space — colour textures evaluated at points of the medium (3D textures such as `cloud`,
//! `fbm`, `wrinkled`, scaled and placed by their mapping) — with a Henyey–Greenstein `g`, the
//! common `fresnel` index, and `stepsize` (metres, default 1): integrals along a ray are ray
//! marched in steps of that length, the density taken at each step's middle.
//!
//! `exponential` ([`Field::Exponential`]) is the same marching over constant coefficients
//! scaled by an analytic density a·e^(-b·h), h the height along `updir`
//! ([`super::exponential`]); [`Field::Grid`] scales them by the values of a `volumegrid`
//! region ([`super::grid`]) and [`Field::Cloud`] by a `cloud` region's density
//! ([`super::cloud`]). A region's scaled density also scales its emission `Le`.

use super::cloud::CloudRegion;
use super::grid::Grid;
use super::{channel_avg, HenyeyGreenstein, MediumSample, VolumeError};
use crate::geometry::{Interaction, Ray, SurfaceInteraction};
use crate::plugin::Stmt;
use crate::spectrum::Rgb;
use crate::texture::{ColorTex, TextureSet};
use glam::Vec3A;

/// Steps one integral may take; longer rays take longer steps.
const MAX_STEPS: f32 = 1024.0;
/// Marching stops once every channel's transmittance is below this.
pub(super) const OPAQUE: f32 = 1e-4;

/// The coefficients of a medium at one point: absorption, scattering and (region volumes)
/// emitted radiance per unit length.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Coeffs {
    pub sigma_a: Rgb,
    pub sigma_s: Rgb,
    pub le: Rgb,
}

impl Coeffs {
    pub fn sigma_t(&self) -> Rgb {
        self.sigma_a + self.sigma_s
    }
}

impl std::ops::Add for Coeffs {
    type Output = Coeffs;
    fn add(self, o: Coeffs) -> Coeffs {
        Coeffs {
            sigma_a: self.sigma_a + o.sigma_a,
            sigma_s: self.sigma_s + o.sigma_s,
            le: self.le + o.le,
        }
    }
}

/// A scalar density in space (≥ 0 and at most [`DENSITY_CAP`] wherever it is evaluated).
#[derive(Debug)]
pub enum Field {
    /// a·e^(-b·h), h = (p - origin)·up.
    Exponential {
        a: f32,
        b: f32,
        up: Vec3A,
        origin: Vec3A,
    },
    /// The values of a `volumegrid` region's grid.
    Grid(Box<Grid>),
    /// LuxRender's `cloud` region ([`super::cloud`]).
    Cloud(Box<CloudRegion>),
}

impl Field {
    /// The density at world point `p`.
    pub fn at(&self, p: Vec3A) -> f32 {
        let d = match self {
            Field::Exponential { a, b, up, origin } => a * (-b * (p - *origin).dot(*up)).exp(),
            Field::Grid(g) => g.density(p),
            Field::Cloud(c) => c.density(p),
        };
        clean_density(d)
    }
}

/// Densities and coefficients past this count as this: an absorbing or scattering medium that
/// dense stops any ray within a step (an emitting one emits that much: the field says so).
/// The coefficients at a point (constant × density) are capped too, so nothing the marcher
/// multiplies them by (a step of at most a few metres) reaches infinity.
pub const DENSITY_CAP: f32 = 1e30;

/// A density or coefficient as the marcher can use it: NaN and negative values are 0, and
/// values past [`DENSITY_CAP`] (an exponential's overflow deep below its origin: +inf) are
/// the cap, so an overflowing medium stays dense instead of vanishing.
fn clean_density(d: f32) -> f32 {
    if d.is_nan() {
        0.0
    } else {
        d.clamp(0.0, DENSITY_CAP)
    }
}

/// How the coefficients vary in space.
#[derive(Debug)]
pub enum Density {
    /// Colour textures for sigma_a and sigma_s.
    Textures {
        sigma_a: ColorTex,
        sigma_s: ColorTex,
    },
    /// Constant coefficients (and emission `le`) times a scalar field.
    Scaled { c: Coeffs, field: Field },
}

impl Density {
    /// Whether the field neither attenuates nor emits anywhere: every coefficient is zero
    /// (constant black textures, or black constants whatever the field).
    pub fn is_vacuum(&self) -> bool {
        match self {
            Density::Textures { sigma_a, sigma_s } => {
                is_black_const(sigma_a) && is_black_const(sigma_s)
            }
            Density::Scaled { c, .. } => {
                c.sigma_a.is_black() && c.sigma_s.is_black() && c.le.is_black()
            }
        }
    }

    /// Whether the field can scatter light somewhere.
    pub fn scatters(&self) -> bool {
        match self {
            Density::Textures { sigma_s, .. } => !is_black_const(sigma_s),
            Density::Scaled { c, .. } => !c.sigma_s.is_black(),
        }
    }

    /// (sigma_a, sigma_s) at world point `p`.
    fn at(&self, p: Vec3A) -> (Rgb, Rgb) {
        let c = self.coeffs(p);
        (c.sigma_a, c.sigma_s)
    }

    /// The coefficients at world point `p`.
    pub fn coeffs(&self, p: Vec3A) -> Coeffs {
        match self {
            Density::Textures { sigma_a, sigma_s } => {
                let si = SurfaceInteraction {
                    it: Interaction {
                        p,
                        ..Interaction::default()
                    },
                    ..SurfaceInteraction::default()
                };
                let clean = |c: Rgb| c.map(clean_density);
                Coeffs {
                    sigma_a: clean(sigma_a.eval(&si)),
                    sigma_s: clean(sigma_s.eval(&si)),
                    le: Rgb::BLACK,
                }
            }
            Density::Scaled { c, field } => {
                let d = field.at(p);
                Coeffs {
                    sigma_a: (c.sigma_a * d).map(clean_density),
                    sigma_s: (c.sigma_s * d).map(clean_density),
                    le: (c.le * d).map(clean_density),
                }
            }
        }
    }
}

/// Whether a colour texture is the constant black.
fn is_black_const(t: &ColorTex) -> bool {
    t.as_const().is_some_and(|c| c.is_black())
}

#[derive(Debug)]
pub struct Heterogeneous {
    pub density: Density,
    pub g: f32,
    pub step: f32,
}

impl Heterogeneous {
    pub fn build(s: &mut Stmt, textures: &mut TextureSet) -> Result<Heterogeneous, VolumeError> {
        let p = s.params();
        let sigma_a = textures.color_param(p, "sigma_a", Rgb::BLACK)?;
        let sigma_s = textures.color_param(p, "sigma_s", Rgb::BLACK)?;
        let g = super::read_g(s);
        let step = s.positive("stepsize", 1.0)?;
        super::read_fresnel(p, s.loc(), textures)?;
        Ok(Heterogeneous {
            density: Density::Textures { sigma_a, sigma_s },
            g,
            step,
        })
    }

    /// The steps along [0, `dist_max`] (distance units): (step length, count).
    pub fn steps(&self, dist_max: f32) -> (f32, u32) {
        if !dist_max.is_finite() || dist_max <= 0.0 {
            return (self.step, if dist_max > 0.0 { MAX_STEPS as u32 } else { 0 });
        }
        let step = self.step.max(dist_max / MAX_STEPS);
        (step, (dist_max / step).ceil() as u32)
    }

    /// The extinction coefficient sigma_a + sigma_s at world point `p`.
    pub fn sigma_t(&self, p: Vec3A) -> Rgb {
        let (sa, ss) = self.density.at(p);
        sa + ss
    }

    /// Transmittance over the ray's parametric extent [0, `t_max`].
    pub fn tr(&self, ray: &Ray, t_max: f32) -> Rgb {
        let len = ray.d.length();
        if len <= 0.0 {
            return Rgb::WHITE;
        }
        let dir = ray.d / len;
        let dist_max = t_max * len;
        let (step, n) = self.steps(dist_max);
        let mut tau = Rgb::BLACK;
        for i in 0..n {
            let a = i as f32 * step;
            let h = step.min(dist_max - a);
            let (sa, ss) = self.density.at(ray.o + dir * (a + 0.5 * h));
            tau += (sa + ss) * h;
            if tau.to_array().iter().all(|&t| t > -OPAQUE.ln()) {
                return Rgb::BLACK;
            }
        }
        tau.map(|t| (-t).exp())
    }

    /// Samples where along [0, `t_max`] the ray scatters (or that it passes): the optical
    /// depth of one channel picked by `u_channel` is marched until it reaches -ln(1 - u).
    pub fn sample(&self, ray: &Ray, t_max: f32, u: f32, u_channel: f32) -> MediumSample {
        let len = ray.d.length();
        let pass = |tau: Rgb| {
            let tr = tau.map(|t| (-t).exp());
            let pdf = channel_avg(tr);
            MediumSample {
                scatter_t: None,
                weight: if pdf > 0.0 { tr / pdf } else { Rgb::BLACK },
                phase: HenyeyGreenstein::new(self.g),
            }
        };
        if len <= 0.0 {
            return pass(Rgb::BLACK);
        }
        let dir = ray.d / len;
        let dist_max = t_max * len;
        let ch = ((u_channel * 3.0) as usize).min(2);
        let target = -(1.0 - u).max(f32::MIN_POSITIVE).ln();
        let (step, n) = self.steps(dist_max);
        let mut tau = Rgb::BLACK;
        for i in 0..n {
            let a = i as f32 * step;
            let h = step.min(dist_max - a);
            let (sa, ss) = self.density.at(ray.o + dir * (a + 0.5 * h));
            let st = sa + ss;
            let s_ch = st.to_array()[ch];
            let before = tau.to_array()[ch];
            if s_ch > 0.0 && before + s_ch * h >= target {
                let d = (target - before) / s_ch;
                let tr = (tau + st * d).map(|t| (-t).exp());
                let pdf = channel_avg(st * tr);
                let weight = if pdf > 0.0 { ss * tr / pdf } else { Rgb::BLACK };
                return MediumSample {
                    scatter_t: Some((a + d) / len),
                    weight,
                    phase: HenyeyGreenstein::new(self.g),
                };
            }
            tau += st * h;
        }
        pass(tau)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_overflowing_density_stays_opaque_and_nan_is_empty() {
        // a·exp(-b·h) overflows f32 far below the origin: the medium is densest there.
        let f = Field::Exponential {
            a: 1.0,
            b: 2.0,
            up: Vec3A::Z,
            origin: Vec3A::ZERO,
        };
        assert_eq!(f.at(Vec3A::new(0.0, 0.0, -100.0)), DENSITY_CAP);
        assert!((f.at(Vec3A::ZERO) - 1.0).abs() < 1e-6);
        assert_eq!(f.at(Vec3A::new(0.0, 0.0, 100.0)), 0.0);
        assert_eq!(clean_density(f32::NAN), 0.0);
        assert_eq!(clean_density(-3.0), 0.0);
        assert_eq!(clean_density(f32::INFINITY), DENSITY_CAP);
        // capped coefficients times a step stay finite
        assert!((DENSITY_CAP * 1e6 * 10.0).is_finite());
        // so do a huge constant times a capped density
        let d = Density::Scaled {
            c: Coeffs {
                sigma_a: Rgb::splat(1e20),
                sigma_s: Rgb::splat(0.5),
                le: Rgb::BLACK,
            },
            field: f,
        };
        let c = d.coeffs(Vec3A::new(0.0, 0.0, -100.0));
        assert_eq!(c.sigma_a.r, DENSITY_CAP);
        assert_eq!(c.sigma_s.r, 0.5 * DENSITY_CAP);
    }
}
