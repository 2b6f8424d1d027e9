//! Light leaving the lights: the rays that start light subpaths (bidirectional path tracing)
//! and the densities with which they are drawn, for every light kind.
//!
//! A light subpath starts with [`Light::sample_le`]: a point on the light (area density
//! `pdf_pos`), a direction leaving it (solid-angle density `pdf_dir`) and what is emitted
//! along it (`le`: radiance for area lights and lights at infinity, radiant intensity for
//! point and spot lights, irradiance for a sharp distant light). Lights at infinity (infinite,
//! sky, sun, distant) emit from a disc of the scene's bounding sphere radius facing the
//! chosen direction, the disc one radius out from the centre: `pdf_pos = 1 / (π R²)`. Delta
//! positions (point, spot) and delta directions (sharp distant) have density 1 in that
//! dimension.
//!
//! The reverse questions, asked when a path built from the camera has to be weighed against
//! the light subpaths that could have built it: [`Light::pdf_dir_from`] (the direction density
//! of leaving a point of a finite light toward a point), [`Light::emitted`] (what a finite
//! light sends that way) and [`Light::area_density`] (the position density of an area light's
//! points). Directions of lights at infinity are answered by `pdf_li`/`le`.

use super::{portal, Light, ShapeSampler};
use crate::geometry::frame::coordinate_system;
use crate::geometry::{Interaction, Ray, Shading, SurfaceInteraction};
use crate::sampling::concentric_disc;
use crate::spectrum::Rgb;
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;

/// The scene's bounding sphere (centre, radius): where lights at infinity emit from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundingSphere {
    pub center: Vec3A,
    pub radius: f32,
}

impl BoundingSphere {
    /// Area density of points on the emitting disc of a light at infinity.
    pub fn disc_pdf(&self) -> f32 {
        1.0 / (PI * self.radius * self.radius)
    }
}

/// A ray leaving a light.
#[derive(Clone, Copy, Debug)]
pub struct LightRay {
    /// Origin on the light (on the disc for lights at infinity); unit direction.
    pub ray: Ray,
    /// Surface normal at the origin (area lights), the ray direction (lights at infinity),
    /// zero for point and spot lights.
    pub n: Vec3A,
    /// Radiance (area, infinite), intensity (point, spot) or irradiance (sharp distant).
    pub le: Rgb,
    /// Area density of the origin (1 for a delta position).
    pub pdf_pos: f32,
    /// Solid-angle density of the direction (1 for a delta direction).
    pub pdf_dir: f32,
    /// Surface coordinates of the origin on an area light's shape (textured emission); zero
    /// for the other lights.
    pub uv: Vec2,
}

impl Light {
    /// True for lights whose emitting point is fixed (point, spot).
    pub fn is_delta_position(&self) -> bool {
        match self {
            Light::Point(_) | Light::Spot(_) => true,
            Light::Moving(l) => !l.at_infinity(),
            _ => false,
        }
    }

    /// True for lights with a single emitted direction (a sharp distant light).
    pub fn is_delta_direction(&self) -> bool {
        match self {
            Light::Distant(l) => l.is_delta(),
            Light::Moving(l) => l.inner().is_delta_direction(),
            _ => false,
        }
    }

    /// Samples a ray leaving the light: `u_pos` (and `u_pick` for meshes and portals) the origin,
    /// `u_dir` the direction.
    pub fn sample_le(
        &self,
        u_pos: Vec2,
        u_dir: Vec2,
        u_pick: f32,
        time: f32,
        shapes: &dyn ShapeSampler,
        sphere: BoundingSphere,
    ) -> Option<LightRay> {
        let s = match self {
            Light::Area(l) => l.sample_le(u_pos, u_dir, u_pick, time, shapes),
            Light::Point(l) => l.sample_le(u_dir, time),
            Light::Spot(l) => l.sample_le(u_dir, time),
            Light::Moving(l) if !l.at_infinity() => {
                l.sample_le(u_pos, u_dir, u_pick, time, shapes, sphere)
            }
            Light::Distant(_)
            | Light::Infinite(_)
            | Light::Sun(_)
            | Light::Sky(_)
            | Light::Sky2(_)
            | Light::Moving(_) => {
                self.sample_le_infinite(u_pos, u_dir, u_pick, time, shapes, sphere)
            }
            // Not emitted by light subpaths: bidirectional refuses scenes with them
            // (`Light::physical`).
            Light::Primitive(_) => None,
        }?;
        let ok = s.pdf_pos > 0.0
            && s.pdf_dir > 0.0
            && s.pdf_pos.is_finite()
            && s.pdf_dir.is_finite()
            && s.le.is_finite()
            && !s.le.is_black()
            && s.ray.d.is_finite();
        ok.then_some(s)
    }

    /// A light at infinity: the direction toward the light as its direct-lighting sampling
    /// picks it, then a point on the disc facing it, or for a light with portals (`u_pick`
    /// choosing) mostly a line through a point on its portals.
    fn sample_le_infinite(
        &self,
        u_pos: Vec2,
        u_dir: Vec2,
        u_pick: f32,
        time: f32,
        shapes: &dyn ShapeSampler,
        sphere: BoundingSphere,
    ) -> Option<LightRay> {
        let at = Interaction {
            p: sphere.center,
            time,
            ..Default::default()
        };
        let ls = match self {
            Light::Distant(l) => l.sample_li(&at, u_dir),
            Light::Infinite(l) => l.sample_li(&at, u_dir),
            Light::Sun(l) => l.sample_li(&at, u_dir),
            Light::Sky(l) => l.sample_li(&at, u_dir),
            Light::Sky2(l) => l.sample_li(&at, u_dir),
            Light::Moving(l) if l.at_infinity() => l.sample_li(&at, u_dir, u_pick, shapes),
            Light::Area(_)
            | Light::Point(_)
            | Light::Spot(_)
            | Light::Primitive(_)
            | Light::Moving(_) => None,
        }?;
        let to_light = ls.wi;
        let plane = sphere.center + to_light * sphere.radius;
        let origin = match self.portals() {
            // Through a portal point, from the plane the disc lies in.
            Some(portals) if u_pick < portal::PORTAL_SHARE => {
                let y = portals.sample_point(u_pos, u_pick / portal::PORTAL_SHARE)?;
                y + to_light * to_light.dot(plane - y)
            }
            _ => {
                let (s, t) = coordinate_system(to_light);
                let d = concentric_disc(u_pos) * sphere.radius;
                plane + s * d.x + t * d.y
            }
        };
        Some(LightRay {
            ray: Ray {
                o: origin,
                d: -to_light,
                t_max: f32::INFINITY,
                time,
            },
            n: -to_light,
            le: ls.li,
            pdf_pos: self.line_density(origin, to_light, sphere),
            pdf_dir: ls.pdf,
            uv: Vec2::ZERO,
        })
    }

    /// Density, per unit area across the line, with which [`Self::sample_le`] draws the line
    /// through `p` toward the light at infinity in unit direction `to_light`: uniform on the
    /// disc facing it that covers the scene, or for a light with portals the mixture of a
    /// point on its portals ([`portal::PORTAL_SHARE`]) and the disc.
    pub fn line_density(&self, p: Vec3A, to_light: Vec3A, sphere: BoundingSphere) -> f32 {
        let off = p - sphere.center;
        let across = off - to_light * off.dot(to_light);
        let disc = if across.length_squared() <= sphere.radius * sphere.radius {
            sphere.disc_pdf()
        } else {
            0.0
        };
        match self.portals() {
            Some(portals) => portal::mixture_pdf(portals.line_density(p, -to_light), disc),
            None => disc,
        }
    }

    /// Solid-angle density with which [`Self::sample_le`] leaves the finite light's point
    /// `from` (with its normal) in unit direction `w`; 0 for lights at infinity.
    pub fn pdf_dir_from(&self, from: &Interaction, w: Vec3A) -> f32 {
        match self {
            Light::Area(l) => l.pdf_dir(from.n, w),
            Light::Point(l) => l.pdf_dir(w),
            Light::Spot(l) => l.pdf_dir(w),
            Light::Moving(l) => l.pdf_dir_from(from, w),
            _ => 0.0,
        }
    }

    /// What the finite light sends from its point `from` in unit direction `w`: radiance for
    /// area lights (`uv` locates textured emission), intensity for point and spot lights.
    pub fn emitted(&self, from: &Interaction, uv: Vec2, w: Vec3A) -> Rgb {
        match self {
            Light::Area(l) => {
                let si = SurfaceInteraction {
                    it: *from,
                    uv,
                    wo: w,
                    shading: Shading {
                        n: from.n,
                        ..Default::default()
                    },
                    ..Default::default()
                };
                l.le(&si, w, None)
            }
            Light::Point(l) => l.intensity_toward(w),
            Light::Spot(l) => l.intensity_toward(w),
            Light::Moving(l) => l.emitted(from, w),
            _ => Rgb::BLACK,
        }
    }

    /// Area density of the points [`Self::sample_le`] and `sample_li` draw on an area light
    /// (uniform by area); 1 for delta positions, 0 for lights at infinity.
    pub fn area_density(&self) -> f32 {
        match self {
            Light::Area(l) if l.area > 0.0 => 1.0 / l.area,
            Light::Point(_) | Light::Spot(_) => 1.0,
            Light::Moving(l) if !l.at_infinity() => 1.0,
            _ => 0.0,
        }
    }

    /// Why light subpaths cannot start on this light, if they cannot: the mental ray area
    /// primitives, and area lights whose emission profile is not LuxRender's physical one
    /// (falloff exponent 2, cosine exponent 1), have no emission sampling yet.
    pub fn bidir_unsupported(&self) -> Option<&'static str> {
        match self {
            Light::Primitive(_) => Some("an area primitive light (rectangle, disc, sphere, cylinder)"),
            Light::Area(a)
                if a.profile.falloff_exponent != 2.0 || a.profile.cos_exponent != 1.0 =>
            {
                Some("an area light with a falloffexponent other than 2 or a cosineexponent other than 1")
            }
            _ => None,
        }
    }

    /// A point or spot light's intensity falls off as 1/d^k (`falloffexponent`); light
    /// subpaths travel with the physical 1/d², so their first vertex at squared distance
    /// `d2` is scaled by d^(2-k). 1 for every other light.
    pub fn falloff_correction(&self, d2: f32) -> f32 {
        let k = match self {
            Light::Point(l) => l.falloff_exponent,
            Light::Spot(l) => l.falloff_exponent,
            Light::Moving(l) => return l.inner().falloff_correction(d2),
            _ => return 1.0,
        };
        if k == 2.0 {
            1.0
        } else {
            d2.powf(1.0 - 0.5 * k)
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::light::{Emission, LightColor, LightCommon, PointLight};
    use crate::lxs::{ParamSet, ParamValue};
    use glam::Mat4;

    fn common() -> LightCommon {
        LightCommon::single(0)
    }

    /// A scene without shapes to sample (tests of lights that need none).
    pub(crate) struct NoShapes;
    impl ShapeSampler for NoShapes {
        fn sample_shape(
            &self,
            _: u32,
            _: Vec2,
            _: f32,
            _: f32,
        ) -> Option<(Interaction, Vec2, f32)> {
            None
        }
    }

    /// The power a point light emits, estimated from its light rays, is 4π·I.
    #[test]
    fn point_light_rays_carry_its_power() {
        let mut ps = ParamSet::new();
        ps.add("from", ParamValue::Point(vec![[1.0, 2.0, 3.0]]));
        let color = LightColor {
            emission: Emission::Const(Rgb::splat(2.0)),
            y: 2.0,
        };
        let l = Light::Point(PointLight::new(&ps, Mat4::IDENTITY, &color, common()));
        let sphere = BoundingSphere {
            center: Vec3A::ZERO,
            radius: 10.0,
        };
        let n = 64;
        let mut flux = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let r = l
                    .sample_le(Vec2::ZERO, u, 0.0, 0.0, &NoShapes, sphere)
                    .unwrap();
                assert!((r.ray.o - Vec3A::new(1.0, 2.0, 3.0)).length() < 1e-6);
                assert!((r.ray.d.length() - 1.0).abs() < 1e-5);
                let at = Interaction {
                    p: r.ray.o,
                    ..Default::default()
                };
                assert!((l.pdf_dir_from(&at, r.ray.d) - r.pdf_dir).abs() < 1e-6);
                flux += f64::from(r.le.g / (r.pdf_pos * r.pdf_dir));
            }
        }
        flux /= (n * n) as f64;
        assert!((flux - 8.0 * std::f64::consts::PI).abs() < 1e-3, "{flux}");
        assert!(l.is_delta_position() && !l.is_delta_direction());
    }

    /// An infinite light's rays start on the disc facing the sampled direction, one radius
    /// out, and travel into the sphere.
    #[test]
    fn infinite_light_rays_leave_the_facing_disc() {
        let l = Light::Infinite(Box::new(crate::light::InfiniteLight::with_map(
            Rgb::splat(0.5),
            Mat4::IDENTITY,
            None,
            common(),
        )));
        let sphere = BoundingSphere {
            center: Vec3A::new(1.0, 0.0, 0.0),
            radius: 2.0,
        };
        for (a, b) in [(0.1, 0.7), (0.5, 0.5), (0.9, 0.2)] {
            let r = l
                .sample_le(
                    Vec2::new(a, b),
                    Vec2::new(b, a),
                    0.0,
                    0.0,
                    &NoShapes,
                    sphere,
                )
                .unwrap();
            let to_light = -r.ray.d;
            let along = (r.ray.o - sphere.center).dot(to_light);
            assert!((along - 2.0).abs() < 1e-4, "{along}");
            assert!((r.pdf_pos - 1.0 / (PI * 4.0)).abs() < 1e-6);
            assert!((r.pdf_dir - l.pdf_li(&Interaction::default(), to_light, None)).abs() < 1e-6);
            assert_eq!(r.le, Rgb::splat(0.5));
        }
    }
}
