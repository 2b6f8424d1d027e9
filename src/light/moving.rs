//! Lights carried by a moving object instance (LuxRender 1.x's `MotionLight`): a `LightSource`
//! inside `ObjectBegin … ObjectEnd`, placed by an `ObjectInstance` inside `MotionBegin …
//! MotionEnd`, moves with the instance. The light is built in the instance's space (its own
//! transform inside the object); at each query the instance's transform is interpolated at the
//! ray's time ([`MotionTransform`], as for moving shapes) and the query is answered there.
//!
//! LuxRender places a `LightSource` written directly inside `MotionBegin` at its first key
//! (the light's static transform), and so does luxfarm (`build`); only instancing moves a
//! light. Lights with a position (point, spot, goniometric, projection) move with the
//! instance; lights at infinity (infinite, distant, sun, sky, sky2) turn with its linear part
//! (a translation does not move what is infinitely far). luxfarm's area primitives
//! (rectangle, disc, sphere, cylinder) move by rebuilding their shape at each time
//! ([`super::PrimitiveLight::with_motion`]).
//!
//! Distances are measured in world space, so a motion key with scale places the light where a
//! static instance with that key would, with the same falloff over world distance. A world
//! direction w is the light's local direction B w / |B w| (B: world to instance at the ray's
//! time), and densities over directions carry the solid-angle change |det B| / |B w|³ of
//! that map (1 for rotations and uniform scale), whether the directions leave a point light
//! or arrive from a light at infinity. Lights at infinity that move have no portals.

use super::{distance_falloff, Light, LightCommon, LightRay, LightSample, ShapeSampler};
use crate::geometry::motion::MotionTransform;
use crate::geometry::{Interaction, Ray, Transform};
use crate::spectrum::Rgb;
use glam::{Vec2, Vec3A};

/// A point-like light or a light at infinity moved by its instance's motion.
#[derive(Debug)]
pub struct MovingLight {
    /// The light in the instance's space.
    inner: Light,
    motion: MotionTransform,
}

impl MovingLight {
    /// Whether a light of this kind moves with its instance: the lights with a position
    /// (point, spot, goniometric, projection) and the lights at infinity (infinite,
    /// distant, sun, sky, sky2).
    pub fn can_move(light: &Light) -> bool {
        matches!(light, Light::Point(_) | Light::Spot(_)) || light.is_infinite()
    }

    /// Wraps a light built in the instance's space; `None` for the kinds it does not carry
    /// (area primitives move on their own).
    pub fn new(inner: Light, motion: MotionTransform) -> Option<MovingLight> {
        MovingLight::can_move(&inner).then_some(MovingLight { inner, motion })
    }

    pub fn inner(&self) -> &Light {
        &self.inner
    }

    pub fn common(&self) -> &LightCommon {
        self.inner.common()
    }

    /// True when the light is at infinity (it turns with the instance, it has no position).
    pub fn at_infinity(&self) -> bool {
        self.inner.is_infinite()
    }

    /// Gives a light at infinity the scene's bounds.
    pub fn preprocess(&mut self, center: Vec3A, radius: f32) {
        self.inner.preprocess(center, radius);
    }

    /// Instance-to-world at `time` (with its inverse); `None` where the interpolated
    /// transform is singular.
    fn at(&self, time: f32) -> Option<Transform> {
        self.motion.transform_at(time)
    }

    /// The light's position in world space at `time`.
    fn position(&self, t: &Transform) -> Vec3A {
        t.point_f32(self.local_position())
    }

    fn local_position(&self) -> Vec3A {
        match &self.inner {
            Light::Point(l) => l.pos,
            Light::Spot(l) => l.pos,
            _ => Vec3A::ZERO,
        }
    }

    fn falloff_exponent(&self) -> f32 {
        match &self.inner {
            Light::Point(l) => l.falloff_exponent,
            Light::Spot(l) => l.falloff_exponent,
            _ => 2.0,
        }
    }

    /// Intensity toward world direction `w` (from the light) at the instance placement `t`.
    fn intensity_toward(&self, t: &Transform, w: Vec3A) -> Rgb {
        let local = t.inverse().vector_f32(w).normalize_or_zero();
        self.inner
            .emitted(&Interaction::default(), Vec2::ZERO, local)
    }

    /// A direction toward the light from `r` at the ray's time: toward a point light's
    /// position, with the intensity that reaches `r` over the world distance, or for a light
    /// at infinity a direction it draws in its own space (`u`, `u_pick`), turned to world
    /// space.
    pub fn sample_li<S: ShapeSampler + ?Sized>(
        &self,
        r: &Interaction,
        u: Vec2,
        u_pick: f32,
        shapes: &S,
    ) -> Option<LightSample> {
        if self.at_infinity() {
            return self.sample_li_at_infinity(r, u, u_pick, shapes);
        }
        self.sample_li_point(r)
    }

    fn sample_li_point(&self, r: &Interaction) -> Option<LightSample> {
        let t = self.at(r.time)?;
        let pos = self.position(&t);
        let d = pos - r.p;
        let d2 = d.length_squared();
        if d2 <= 0.0 || !d2.is_finite() {
            return None;
        }
        let wi = d / d2.sqrt();
        let li = self.intensity_toward(&t, -wi) * distance_falloff(d2, self.falloff_exponent());
        Some(LightSample {
            li,
            wi,
            pdf: 1.0,
            p_light: Interaction {
                p: pos,
                time: r.time,
                ..Default::default()
            },
            delta: true,
            infinite: false,
        })
    }

    /// A light at infinity's [`Self::sample_li`]: the local sample's direction in world
    /// space, its density over world directions.
    fn sample_li_at_infinity<S: ShapeSampler + ?Sized>(
        &self,
        r: &Interaction,
        u: Vec2,
        u_pick: f32,
        shapes: &S,
    ) -> Option<LightSample> {
        let t = self.at(r.time)?;
        let local = Interaction {
            p: t.inverse().point_f32(r.p),
            ..*r
        };
        let s = self
            .inner
            .sample_li_ignoring_portals(&local, u, u_pick, shapes)?;
        let w = t.vector_f32(s.wi).normalize_or_zero();
        if w == Vec3A::ZERO {
            return None;
        }
        let pdf = if s.delta {
            s.pdf
        } else {
            s.pdf * direction_jacobian(&t, w)?.1
        };
        let radius = self.inner.world_radius();
        Some(LightSample::from_infinity(r, w, s.li, pdf, s.delta, radius))
    }

    /// Radiance arriving from the light at infinity along world direction `-dir` (a ray
    /// escaping in direction `dir`) at `time`.
    pub fn le(&self, dir: Vec3A, time: f32) -> Rgb {
        if !self.at_infinity() {
            return Rgb::BLACK;
        }
        self.at(time)
            .and_then(|t| direction_jacobian(&t, dir))
            .map_or(Rgb::BLACK, |(local, _)| self.inner.le(local, time))
    }

    /// Density with which [`Self::sample_li`] draws world direction `wi` from `r` (0 for
    /// point-like lights, which are delta).
    pub fn pdf_li(&self, r: &Interaction, wi: Vec3A) -> f32 {
        if !self.at_infinity() {
            return 0.0;
        }
        let Some(t) = self.at(r.time) else {
            return 0.0;
        };
        let Some((local, jacobian)) = direction_jacobian(&t, wi) else {
            return 0.0;
        };
        let at = Interaction {
            p: t.inverse().point_f32(r.p),
            ..*r
        };
        self.inner.pdf_li_ignoring_portals(&at, local, None) * jacobian
    }

    /// A ray leaving the light at `time` (light subpaths): drawn in the instance's space and
    /// carried to world space.
    pub fn sample_le(
        &self,
        u_pos: Vec2,
        u_dir: Vec2,
        u_pick: f32,
        time: f32,
        shapes: &dyn ShapeSampler,
        sphere: super::BoundingSphere,
    ) -> Option<LightRay> {
        let t = self.at(time)?;
        let lr = self
            .inner
            .sample_le(u_pos, u_dir, u_pick, time, shapes, sphere)?;
        let d = t.vector_f32(lr.ray.d).normalize_or_zero();
        let pdf_dir = self.pdf_dir_at(&t, d);
        (d != Vec3A::ZERO && pdf_dir > 0.0).then_some(LightRay {
            ray: Ray {
                o: self.position(&t),
                d,
                t_max: f32::INFINITY,
                time,
            },
            n: Vec3A::ZERO,
            le: self.intensity_toward(&t, d),
            pdf_pos: 1.0,
            pdf_dir,
            uv: Vec2::ZERO,
        })
    }

    /// The solid-angle density of world direction `w`: the local density of the direction it
    /// comes from, times the change of solid angle `|det B| / |B w|³` of the world-to-instance
    /// map `B` (1 for rotations and uniform scale).
    fn pdf_dir_at(&self, t: &Transform, w: Vec3A) -> f32 {
        direction_jacobian(t, w).map_or(0.0, |(local, jacobian)| {
            self.inner.pdf_dir_from(&Interaction::default(), local) * jacobian
        })
    }

    /// Direction density of leaving the light toward world direction `w` at `from.time`
    /// (0 for a light at infinity, whose directions `pdf_li` answers).
    pub fn pdf_dir_from(&self, from: &Interaction, w: Vec3A) -> f32 {
        if self.at_infinity() {
            return 0.0;
        }
        self.at(from.time).map_or(0.0, |t| self.pdf_dir_at(&t, w))
    }

    /// Intensity sent toward world direction `w` at `from.time` (black for a light at
    /// infinity).
    pub fn emitted(&self, from: &Interaction, w: Vec3A) -> Rgb {
        if self.at_infinity() {
            return Rgb::BLACK;
        }
        self.at(from.time)
            .map_or(Rgb::BLACK, |t| self.intensity_toward(&t, w))
    }
}

/// World direction `w` (unit) in the instance's space at placement `t` (B w / |B w|, B the
/// world-to-instance map), with the change of solid angle |det B| / |B w|³ of that map;
/// `None` where B w vanishes or is not finite.
fn direction_jacobian(t: &Transform, w: Vec3A) -> Option<(Vec3A, f32)> {
    let b = t.inverse();
    let v = b.vector(crate::geometry::transform::to_f64(w));
    let len = v.length();
    if len <= 0.0 || !len.is_finite() {
        return None;
    }
    let jacobian = glam::DMat3::from_mat4(b.m).determinant().abs() / (len * len * len);
    Some(((v / len).as_vec3a(), jacobian as f32))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::emission::tests::NoShapes;
    use crate::light::{Emission, LightColor, PointLight, SpotLight};
    use crate::lxs::{ParamSet, ParamValue};
    use glam::{DAffine3, DVec3, Mat4};

    fn color() -> LightColor {
        LightColor {
            emission: Emission::Const(Rgb::splat(2.0)),
            y: 2.0,
        }
    }

    /// A translation from x = 0 at time 0 to x = `dx` at time 1.
    fn slide(dx: f64) -> MotionTransform {
        MotionTransform::new(&[
            (0.0, DAffine3::IDENTITY),
            (1.0, DAffine3::from_translation(DVec3::new(dx, 0.0, 0.0))),
        ])
        .unwrap()
    }

    fn at(p: [f32; 3], time: f32) -> Interaction {
        Interaction {
            p: Vec3A::from_array(p),
            time,
            ..Default::default()
        }
    }

    fn point() -> Light {
        let common = LightCommon::single(0);
        Light::Point(PointLight::new(
            &ParamSet::new(),
            Mat4::IDENTITY,
            &color(),
            common,
        ))
    }

    #[test]
    fn a_point_light_is_where_its_instance_is_at_the_rays_time() {
        let l = MovingLight::new(point(), slide(4.0)).unwrap();
        // From (2, 0, -1): at time 0 the light is at the origin, at time 0.5 straight above.
        let s0 = l.sample_li_point(&at([2.0, 0.0, -1.0], 0.0)).unwrap();
        let s5 = l.sample_li_point(&at([2.0, 0.0, -1.0], 0.5)).unwrap();
        let s1 = l.sample_li_point(&at([2.0, 0.0, -1.0], 1.0)).unwrap();
        assert!((s0.p_light.p - Vec3A::ZERO).length() < 1e-5);
        assert!((s5.p_light.p - Vec3A::new(2.0, 0.0, 0.0)).length() < 1e-5);
        assert!((s1.p_light.p - Vec3A::new(4.0, 0.0, 0.0)).length() < 1e-5);
        assert!((s5.wi - Vec3A::Z).length() < 1e-5);
        // Intensity 2 W/sr over the squared world distance: 5 at times 0 and 1, 1 at 0.5.
        assert!((s0.li.g - 2.0 / 5.0).abs() < 1e-5, "{:?}", s0.li);
        assert!((s5.li.g - 2.0).abs() < 1e-5, "{:?}", s5.li);
        assert!((s1.li.g - 2.0 / 5.0).abs() < 1e-5, "{:?}", s1.li);
    }

    #[test]
    fn the_shutter_average_of_a_sliding_light_is_the_line_lights_irradiance() {
        // A light of intensity I sliding from x = -1 to x = 1 at height h over a floor point
        // (x0, 0, 0): the time-averaged irradiance is (1/2) ∫ I h / ((s − x0)² + h²)^(3/2) ds
        // over s in [-1, 1] = I / (2 h) · [(s − x0) / √((s − x0)² + h²)] from -1 to 1.
        let slide = MotionTransform::new(&[
            (0.0, DAffine3::from_translation(DVec3::new(-1.0, 0.0, 1.0))),
            (1.0, DAffine3::from_translation(DVec3::new(1.0, 0.0, 1.0))),
        ])
        .unwrap();
        let l = MovingLight::new(point(), slide).unwrap();
        let (i, h) = (2.0f64, 1.0f64);
        for x0 in [0.0f64, 0.4, 1.5] {
            let f = |s: f64| (s - x0) / ((s - x0).powi(2) + h * h).sqrt();
            let want = i / (2.0 * h) * (f(1.0) - f(-1.0));
            let n = 20000;
            let got = (0..n)
                .map(|k| {
                    let t = (k as f32 + 0.5) / n as f32;
                    let s = l.sample_li_point(&at([x0 as f32, 0.0, 0.0], t)).unwrap();
                    f64::from(s.li.g * s.wi.z)
                })
                .sum::<f64>()
                / n as f64;
            assert!((got / want - 1.0).abs() < 1e-4, "x0 {x0}: {got} vs {want}");
        }
    }

    #[test]
    fn directions_through_a_stretching_key_keep_their_density() {
        // Light subpaths of a point light stretched 3x along x: the world directions crowd
        // toward ±x, and pdf_dir is their density: over directions drawn on a stratified grid,
        // the mean of x²/pdf is ∫ x² dω = 4π/3 (a uniform density would give about twice it).
        let stretch = MotionTransform::new(&[
            (0.0, DAffine3::from_scale(DVec3::new(3.0, 1.0, 1.0))),
            (1.0, DAffine3::from_scale(DVec3::new(3.0, 1.0, 1.0))),
        ])
        .unwrap();
        let l = MovingLight::new(point(), stretch).unwrap();
        let sphere = crate::light::BoundingSphere {
            center: Vec3A::ZERO,
            radius: 10.0,
        };
        let n = 200;
        let mut inv = 0.0f64;
        for a in 0..n {
            for b in 0..n {
                let u = Vec2::new((a as f32 + 0.5) / n as f32, (b as f32 + 0.5) / n as f32);
                let lr = l
                    .sample_le(Vec2::ZERO, u, 0.0, 0.5, &NoShapes, sphere)
                    .unwrap();
                let back = l.pdf_dir_from(&at([0.0; 3], 0.5), lr.ray.d);
                assert!((back / lr.pdf_dir - 1.0).abs() < 1e-3);
                inv += f64::from(lr.ray.d.x * lr.ray.d.x) / f64::from(lr.pdf_dir);
            }
        }
        let integral = inv / f64::from(n * n);
        let want = 4.0 * std::f64::consts::PI / 3.0;
        assert!((integral / want - 1.0).abs() < 2e-3, "{integral} vs {want}");
    }

    #[test]
    fn a_spot_light_turns_with_its_instance() {
        // A spot along +z (cone 30°); the instance turns it a quarter turn about y by time 1,
        // so it points along +x.
        let mut ps = ParamSet::new();
        ps.add("to", ParamValue::Point(vec![[0.0, 0.0, 1.0]]));
        let spot = Light::Spot(SpotLight::new(
            &ps,
            Mat4::IDENTITY,
            &color(),
            LightCommon::single(0),
        ));
        let turn = MotionTransform::new(&[
            (0.0, DAffine3::IDENTITY),
            (1.0, DAffine3::from_rotation_y(std::f64::consts::FRAC_PI_2)),
        ])
        .unwrap();
        let l = MovingLight::new(spot, turn).unwrap();
        let on_z = at([0.0, 0.0, 3.0], 0.0);
        let on_x = at([3.0, 0.0, 0.0], 0.0);
        assert!(l.sample_li_point(&on_z).unwrap().li.g > 0.0);
        assert_eq!(l.sample_li_point(&on_x).unwrap().li.g, 0.0);
        let (on_z, on_x) = (at([0.0, 0.0, 3.0], 1.0), at([3.0, 0.0, 0.0], 1.0));
        assert_eq!(l.sample_li_point(&on_z).unwrap().li.g, 0.0);
        assert!(l.sample_li_point(&on_x).unwrap().li.g > 0.0);
        // Light subpaths leave along the turned axis at time 1.
        let sphere = crate::light::BoundingSphere {
            center: Vec3A::ZERO,
            radius: 10.0,
        };
        let lr = l
            .sample_le(Vec2::ZERO, Vec2::new(0.0, 0.0), 0.0, 1.0, &NoShapes, sphere)
            .unwrap();
        assert!(lr.ray.d.x > 0.8, "{:?}", lr.ray.d);
        assert!((l.pdf_dir_from(&at([0.0; 3], 1.0), lr.ray.d) - lr.pdf_dir).abs() < 1e-3);
    }

    #[test]
    fn a_stretched_light_at_infinity_keeps_its_densities() {
        // A constant infinite light (radiance 1) under a key stretching x by 3 and z by 1/2:
        // its directions, drawn uniformly in the light's space, crowd toward ±x in the world,
        // and their density carries the change of solid angle. The irradiance on a floor
        // facing +z, the mean of le·cos/pdf over stratified draws, is π whatever the stretch.
        let inf = Light::Infinite(Box::new(crate::light::InfiniteLight::with_map(
            Rgb::WHITE,
            Mat4::IDENTITY,
            None,
            LightCommon::single(0),
        )));
        let key = DAffine3::from_scale(DVec3::new(3.0, 1.0, 0.5));
        let stretch = MotionTransform::new(&[(0.0, key), (1.0, key)]).unwrap();
        let l = MovingLight::new(inf, stretch).unwrap();
        let r = at([0.0; 3], 0.5);
        let n = 300;
        let mut sum = 0.0f64;
        for a in 0..n {
            for b in 0..n {
                let u = Vec2::new((a as f32 + 0.5) / n as f32, (b as f32 + 0.5) / n as f32);
                let s = l.sample_li(&r, u, 0.5, &NoShapes).unwrap();
                let back = l.pdf_li(&r, s.wi);
                assert!((back / s.pdf - 1.0).abs() < 1e-3, "{back} vs {}", s.pdf);
                assert_eq!(l.le(s.wi, 0.5), s.li);
                sum += f64::from(s.li.g * s.wi.z.max(0.0)) / f64::from(s.pdf);
            }
        }
        let e = sum / f64::from(n * n);
        assert!((e / std::f64::consts::PI - 1.0).abs() < 5e-3, "{e}");
    }

    #[test]
    fn a_light_at_infinity_turns_with_its_instance() {
        // A soft distant light from +z (theta 10°), turned a quarter about y by time 1: from
        // +x then. Sampled directions, their density and the radiance of escaping rays turn.
        let mut ps = ParamSet::new();
        ps.add("from", ParamValue::Point(vec![[0.0, 0.0, 1.0]]));
        ps.add("theta", ParamValue::Float(vec![10.0]));
        let mut d = Light::Distant(crate::light::DistantLight::new(
            &ps,
            Mat4::IDENTITY,
            &color(),
            LightCommon::single(0),
        ));
        d.preprocess(Vec3A::ZERO, 10.0);
        let turn = MotionTransform::new(&[
            (0.0, DAffine3::IDENTITY),
            (1.0, DAffine3::from_rotation_y(std::f64::consts::FRAC_PI_2)),
        ])
        .unwrap();
        let l = MovingLight::new(d, turn).unwrap();
        assert!(l.at_infinity());
        for (time, axis) in [(0.0, Vec3A::Z), (1.0, Vec3A::X)] {
            let r = at([0.3, -0.2, 0.1], time);
            let s = l
                .sample_li(&r, Vec2::new(0.3, 0.7), 0.5, &NoShapes)
                .unwrap();
            assert!(
                s.infinite && s.wi.dot(axis) > 0.98,
                "time {time}: {:?}",
                s.wi
            );
            let back = l.pdf_li(&r, s.wi);
            assert!((back / s.pdf - 1.0).abs() < 1e-3, "{back} vs {}", s.pdf);
            assert!(l.le(s.wi, time).g > 0.0);
            assert!(l.le(s.wi, 1.0 - time).is_black());
        }
        // Light subpaths leave from the turned direction (toward -x at time 1).
        let sphere = crate::light::BoundingSphere {
            center: Vec3A::ZERO,
            radius: 10.0,
        };
        let m = Light::Moving(Box::new(l));
        let lr = m
            .sample_le(
                Vec2::new(0.5, 0.5),
                Vec2::new(0.3, 0.7),
                0.5,
                1.0,
                &NoShapes,
                sphere,
            )
            .unwrap();
        assert!(lr.ray.d.x < -0.98, "{:?}", lr.ray.d);
        assert!(!m.is_delta_position() && m.is_infinite());
    }
}
