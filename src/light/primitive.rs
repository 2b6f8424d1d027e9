//! Area lights that are shapes of their own rather than scene geometry: mental ray's area
//! primitives (rectangle, disc, sphere, cylinder), usable from .lxs as `LightSource` kinds.
//!
//! ```text
//! LightSource "rectangle"|"disc"|"sphere"|"cylinder" + params
//!     --<shape>::build--> PrimShape --PrimitiveLight::new (L, gain, power, profile)--> Light::Primitive
//! render: sample_li (a point of the shape, its solid-angle pdf, L × profile factor)
//!         crossings (every point a ray passes through: emission on hit, with pdf_at for MIS)
//! ```
//!
//! Like mental ray's, these lights neither block nor reflect rays: a ray passes through them,
//! picking up their emission at every crossing (one-sided emitters only emit toward the side
//! of their normal), and shadow rays ignore them. `L` (colour, default white) × `gain` (1) is
//! the radiance of a Lambertian emitter (see [`super::emitter`] for `cosineexponent`,
//! `twosided`, `falloffexponent` and `visible`); when `power` × `efficacy` (both default 0,
//! unlike `area`'s 100 W × 17 lm/W) is positive, L is scaled so the light emits that many
//! lumens. `nsamples` shadow rays per estimate (and `lownsamples` from path depth
//! `lowlevel` on; see [`super::LightCommon`]).
//!
//! Defined in an object instanced with motion, a primitive moves with the instance: at each
//! query its shape is built again where the instance puts it at the ray's time
//! ([`PrimitiveLight::with_motion`]), which costs a few parameter look-ups and a matrix
//! interpolation per query (static primitives pay nothing). Its radiance and the power the
//! light strategies weigh it by keep the first key's size (a key that scales the shape
//! changes its power, as a scaled area light's does).

use super::cylinder::{self, Cylinder};
use super::disc::{self, Disc};
use super::emitter::EmissionProfile;
use super::primshape::{LightShape, PrimPoint};
use super::rectangle::{self, Rectangle};
use super::sphere::{self, Sphere};
use super::{power_gain, LightColor, LightCommon, LightSample};
use crate::geometry::motion::MotionTransform;
use crate::geometry::{Interaction, Ray, SurfaceInteraction};
use crate::lxs::ParamSet;
use crate::spectrum::Rgb;
use glam::{DMat4, Mat4, Vec2, Vec3A};

/// The geometry of an area primitive.
#[derive(Clone, Copy, Debug)]
pub enum PrimShape {
    Rectangle(Rectangle),
    Disc(Disc),
    Sphere(Sphere),
    Cylinder(Cylinder),
}

/// The `LightSource` names of the area primitives.
pub const PRIMITIVE_KINDS: [&str; 4] = ["rectangle", "disc", "sphere", "cylinder"];

impl PrimShape {
    /// Builds the shape of primitive light `kind` from its parameters (`None`: not a primitive).
    pub fn build(kind: &str, p: &ParamSet, l2w: Mat4) -> Option<Result<PrimShape, String>> {
        Some(match kind {
            "rectangle" => rectangle::build(p, l2w).map(PrimShape::Rectangle),
            "disc" => disc::build(p, l2w).map(PrimShape::Disc),
            "sphere" => sphere::build(p, l2w).map(PrimShape::Sphere),
            "cylinder" => cylinder::build(p, l2w).map(PrimShape::Cylinder),
            _ => return None,
        })
    }

    fn shape(&self) -> &dyn LightShape {
        match self {
            PrimShape::Rectangle(s) => s,
            PrimShape::Disc(s) => s,
            PrimShape::Sphere(s) => s,
            PrimShape::Cylinder(s) => s,
        }
    }
}

#[derive(Debug)]
pub struct PrimitiveLight {
    pub common: LightCommon,
    pub profile: EmissionProfile,
    /// Radiance L × gain × power normalisation.
    pub l: Rgb,
    /// The shape (at the first key of a moving instance).
    pub shape: PrimShape,
    y: f32,
    motion: Option<Box<PrimMotion>>,
}

/// What a primitive carried by a moving instance is rebuilt from at each time.
#[derive(Debug)]
struct PrimMotion {
    kind: String,
    params: ParamSet,
    /// Light to instance space (the light's own transform inside the object).
    l2i: DMat4,
    /// Instance to world over the shutter.
    keys: MotionTransform,
}

impl PrimitiveLight {
    pub fn new(
        params: &ParamSet,
        color: &LightColor,
        common: LightCommon,
        shape: PrimShape,
    ) -> Result<PrimitiveLight, String> {
        let profile = EmissionProfile::from_params(params)?;
        let gain = params.float_or("gain", 1.0);
        let power = params.float_or("power", 0.0);
        let efficacy = params.float_or("efficacy", 0.0);
        let flux_per_l = shape.shape().area() * profile.flux_per_area();
        let scale = gain * power_gain(power, efficacy, flux_per_l, color.y);
        let l = color.emission.eval(&SurfaceInteraction::default()) * scale;
        Ok(PrimitiveLight {
            common,
            profile,
            l,
            shape,
            y: color.y * scale,
            motion: None,
        })
    }

    /// Makes the light move with an instance: `kind` and `params` are its statement's, `l2i`
    /// its transform in the instance's space, `keys` the instance's motion.
    pub fn with_motion(
        mut self,
        kind: &str,
        params: &ParamSet,
        l2i: DMat4,
        keys: MotionTransform,
    ) -> PrimitiveLight {
        self.motion = Some(Box::new(PrimMotion {
            kind: kind.to_string(),
            params: params.clone(),
            l2i,
            keys,
        }));
        self
    }

    /// The shape at shutter time `time`; `None` where a moving instance's transform is
    /// singular there.
    fn shape_at(&self, time: f32) -> Option<PrimShape> {
        let Some(m) = &self.motion else {
            return Some(self.shape);
        };
        let t = m.keys.transform_at(time)?;
        let l2w = (t.m * m.l2i).as_mat4();
        PrimShape::build(&m.kind, &m.params, l2w)?.ok()
    }

    /// Radiance leaving `q` toward the unit direction `w`, toward a point at squared
    /// distance `d2` (`None`: seen by the camera).
    pub fn le(&self, q: &PrimPoint, w: Vec3A, d2: Option<f32>) -> Rgb {
        let f = self.profile.factor(q.n.dot(w), d2);
        if f > 0.0 {
            self.l * f
        } else {
            Rgb::BLACK
        }
    }

    pub fn sample_li(&self, r: &Interaction, u: Vec2) -> Option<LightSample> {
        let shape = self.shape_at(r.time)?;
        let (q, pdf) = shape.shape().sample(r.p, u)?;
        let d = q.p - r.p;
        let d2 = d.length_squared();
        if d2 <= 0.0 {
            return None;
        }
        let wi = d / d2.sqrt();
        Some(LightSample {
            li: self.le(&q, -wi, Some(d2)),
            wi,
            pdf,
            p_light: Interaction {
                p: q.p,
                n: q.n,
                time: r.time,
                ..Default::default()
            },
            delta: false,
            infinite: false,
        })
    }

    /// Solid-angle density with which [`Self::sample_li`] picks the point `hit` from `r`.
    pub fn pdf_at(&self, r: &Interaction, hit: &SurfaceInteraction) -> f32 {
        let q = PrimPoint {
            p: hit.it.p,
            n: hit.it.n,
        };
        self.shape_at(r.time)
            .map_or(0.0, |s| s.shape().pdf(r.p, &q))
    }

    /// The density of the first point along `wi` from `r` (when no crossing is given).
    pub fn pdf_li(&self, r: &Interaction, wi: Vec3A) -> f32 {
        let Some(shape) = self.shape_at(r.time) else {
            return 0.0;
        };
        let c = shape.shape().intersect(r.p, wi, f32::INFINITY);
        c.first().map_or(0.0, |(_, q)| shape.shape().pdf(r.p, q))
    }

    /// Calls `f` with each point where `ray` (0 < t < `t_max`) crosses the light, as a
    /// surface interaction whose `wo` points back along the ray.
    pub fn crossings(&self, ray: &Ray, t_max: f32, f: &mut dyn FnMut(&SurfaceInteraction)) {
        let Some(shape) = self.shape_at(ray.time) else {
            return;
        };
        let c = shape.shape().intersect(ray.o, ray.d, t_max.min(ray.t_max));
        let wo = -ray.d.normalize_or_zero();
        for &(t, q) in c.iter() {
            let si = SurfaceInteraction {
                it: Interaction {
                    p: q.p,
                    n: q.n,
                    time: ray.time,
                    ..Default::default()
                },
                wo,
                t,
                ..Default::default()
            };
            f(&si);
        }
    }

    pub fn power(&self) -> f32 {
        self.y * self.shape.shape().area() * self.profile.flux_per_area()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::Emission;
    use crate::lxs::ParamValue;

    fn white() -> LightColor {
        LightColor {
            emission: Emission::Const(Rgb::WHITE),
            y: 1.0,
        }
    }

    #[test]
    fn power_normalisation_counts_lumens() {
        let mut ps = ParamSet::new();
        ps.add("power", ParamValue::Float(vec![10.0]));
        ps.add("efficacy", ParamValue::Float(vec![17.0]));
        ps.add("radius", ParamValue::Float(vec![0.5]));
        let shape = PrimShape::build("sphere", &ps, Mat4::IDENTITY)
            .unwrap()
            .unwrap();
        let l = PrimitiveLight::new(&ps, &white(), LightCommon::single(0), shape).unwrap();
        assert!((l.power() - 170.0).abs() < 1e-2, "{}", l.power());
        assert!(PrimShape::build("spot", &ps, Mat4::IDENTITY).is_none());
    }

    #[test]
    fn rays_pick_up_every_crossing_toward_their_origin() {
        // A unit sphere at the origin seen from z = −3: the near crossing emits toward the
        // ray's origin, the far one faces away.
        let ps = ParamSet::new();
        let shape = PrimShape::build("sphere", &ps, Mat4::IDENTITY)
            .unwrap()
            .unwrap();
        let l = PrimitiveLight::new(&ps, &white(), LightCommon::single(0), shape).unwrap();
        let ray = Ray::new(Vec3A::new(0.0, 0.0, -3.0), Vec3A::Z);
        let mut seen = Vec::new();
        l.crossings(&ray, f32::INFINITY, &mut |si| {
            let q = PrimPoint {
                p: si.it.p,
                n: si.it.n,
            };
            seen.push(l.le(&q, si.wo, None).r);
        });
        assert_eq!(seen, vec![1.0, 0.0]);
        let mut n = 0;
        l.crossings(&ray, 2.5, &mut |_| n += 1);
        assert_eq!(n, 1);
    }
}
