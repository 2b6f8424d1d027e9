//! Light sources: area, point, spot, distant, infinite — with LuxRender's radiometric
//! conventions (checked against LuxRender 1.x `lights/*.cpp`):
//!
//! - **area**: `L` (colour or texture, default 1) × `gain` (1) is the emitted *radiance*,
//!   on the side of the (oriented) geometric normal only. When `power` (default 100 W) ×
//!   `efficacy` (default 17 lm/W) / (area × π × Y(L)) is positive and finite, the gain is
//!   multiplied by it, so the lamp emits `power × efficacy` lumens whatever its size.
//!   Scenes that want raw `L` write `"float power" [0]`. `nsamples` (1) shadow rays.
//!   luxfarm adds the emission profile of [`emitter`] (`falloffexponent`, `cosineexponent`,
//!   `twosided`, `visible`), defaulting to LuxRender's behaviour.
//! - **rectangle**, **disc**, **sphere**, **cylinder** (luxfarm's, after mental ray's area
//!   primitives): emitters that are not scene geometry (see [`primitive`]); rays pass
//!   through them and pick up their emission.
//! - **point**, **goniometric**: intensity `L × gain` (W/sr), shaped by an IES profile
//!   (`iesname`) and/or a lat-long map (`mapname`) as [`gonio`] describes; `power`/`efficacy` (default 0) normalise by
//!   4π·Y(L). `from` offsets the position. luxfarm's own `falloffexponent` k (default 2, the
//!   physical inverse square) sets the falloff 1/d^k for scenes imported from formats whose
//!   lights do not fall off physically (LightWave, mental ray); spot lights take it too
//!   (see [`falloff`]).
//! - **spot**: like point, times the falloff ((cosθ − cos total)/(cos start − cos total))⁴
//!   between `coneangle − conedeltaangle` and `coneangle` (30°, 5°); normalisation by
//!   2π(1 − (cos start + cos total)/2)·Y(L). Direction `from` → `to`. With luxfarm's
//!   `spread` (the cosine of the outer half-angle, mental ray's) the cone falls off linearly
//!   in the cosine from `cone` (inner cosine) to `spread`, as mental ray's spot shaders do.
//! - **distant**: irradiance `L × gain` from direction `to → from` (light travels from `from`
//!   to `to`); `theta` > 0 (degrees) spreads it over a cone of directions.
//! - **infinite**: radiance `L × gain` (× the map `mapname`, raised to `gamma`) for
//!   escaping rays; the map is indexed with the light-space direction through its `mapping`
//!   (latlong: s = φ/2π (φ = atan2(y, x) in [0, 2π)), t = θ/π (θ from +z), row 0 at the top;
//!   angular and vcross as [`envmapping`] describes). Maps are importance sampled with a 2D
//!   piecewise-constant distribution.
//! - **sun**, **sky**, **sunsky**: Preetham et al.'s daylight as LuxRender has it: a sun disc
//!   of spectral radiance from the turbidity and an analytic sky (see [`sun`], [`sky`],
//!   [`sunsky`]); **sky2**, **sunsky2**: Hosek & Wilkie's sky ([`sky2`]), with the same sun.
//!
//! - **portals** (`PortalShape`/`PortalInstance` after an infinite, sky, sky2, sunsky or
//!   sunsky2 light in the same scope): the light is sampled through those windows
//!   ([`portal`]) by path and direct lighting; bidirectional ignores them.
//!
//! - **moving**: a point, spot, goniometric or projection light defined in an object that is
//!   instanced with motion moves with the instance at each ray's time, and a light at
//!   infinity turns with it ([`moving`]); an area primitive's shape is rebuilt where the
//!   instance puts it ([`primitive`]).
//!
//! Every light's `nsamples` (1) is the number of shadow rays per direct-lighting estimate;
//! `lownsamples` replaces it from path depth `lowlevel` on (0: never), as mental ray's
//! `low_samples` at `low_level`.
//!
//! The film side: LuxRender's camera ray weight is 1 and the sample pipeline adds the
//! radiance's XYZ times the filter weight, with the filter weight summed alongside; the
//! pixel value is the weighted mean (no pixel-count or spp factor for eye-path integrators).

pub mod area;
mod build;
pub mod cylinder;
pub mod disc;
pub mod distant;
pub mod emission;
pub mod emitter;
pub mod envmapping;
pub mod falloff;
pub mod gonio;
pub mod ies;
pub mod infinite;
pub mod latlong;
pub mod moving;
pub mod point;
pub mod portal;
pub mod primitive;
pub mod primshape;
pub mod rectangle;
pub mod sky;
pub mod sky2;
pub mod sky2_data;
pub mod sphere;
pub mod spot;
pub mod strategy;
pub mod sun;
pub mod sunsky;
pub mod sunsky_data;

use crate::geometry::{Interaction, Ray, SurfaceInteraction};
use crate::lxs::ParamSet;
use crate::spectrum::Rgb;
use glam::{DMat4, Mat4, Vec2, Vec3A};
use std::sync::Arc;

pub use area::AreaLight;
pub use build::KINDS;
pub use distant::DistantLight;
pub use emission::{BoundingSphere, LightRay};
pub use emitter::EmissionProfile;
pub use falloff::{distance_falloff, falloff_exponent, mental_ray_exponent, radiance_falloff};
pub use infinite::InfiniteLight;
pub use moving::MovingLight;
pub use point::PointLight;
pub use portal::Portals;
pub use primitive::{PrimShape, PrimitiveLight, PRIMITIVE_KINDS};
pub use sky::SkyLight;
pub use sky2::Sky2Light;
pub use spot::SpotLight;
pub use strategy::{LightSelector, LightStrategy};
pub use sun::SunLight;

/// A colour evaluated on a surface (an area light's `L` texture).
pub type EmitFn = Arc<dyn Fn(&SurfaceInteraction) -> Rgb + Send + Sync>;

/// The `L` parameter of a light: a constant, or a texture evaluated where light leaves.
#[derive(Clone)]
pub enum Emission {
    Const(Rgb),
    Tex(EmitFn),
}

impl std::fmt::Debug for Emission {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Emission::Const(c) => write!(f, "Const({c:?})"),
            Emission::Tex(_) => write!(f, "Tex(..)"),
        }
    }
}

impl Emission {
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        match self {
            Emission::Const(c) => *c,
            Emission::Tex(t) => t(si),
        }
    }
}

/// `L` with its luminance Y (as LuxRender's colour pipeline computes it), which power and
/// efficacy normalisation divides by.
#[derive(Clone, Debug)]
pub struct LightColor {
    pub emission: Emission,
    pub y: f32,
}

/// Where area lights find points on their shapes (implemented by the scene over the
/// geometry): a point uniformly by area on emitter `shape` at shutter time `time` (a moving
/// shape is where it is then), its uv (textured emission is looked up there), and the area
/// pdf.
pub trait ShapeSampler {
    fn sample_shape(
        &self,
        shape: u32,
        u: Vec2,
        u_pick: f32,
        time: f32,
    ) -> Option<(Interaction, Vec2, f32)>;

    /// Whether [`Self::sample_shape`] of `shape` reads its `u_pick` (a mesh with many
    /// triangles picks one with it; a few triangles are picked with `u` itself). An
    /// integrator draws `u_pick` only then; true when not known.
    fn reads_pick(&self, _shape: u32) -> bool {
        true
    }
}

/// One sampled light direction as seen from a reference point.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Incident radiance (or intensity / d² for delta lights) arriving along `wi`.
    pub li: Rgb,
    /// Unit direction from the reference point toward the light.
    pub wi: Vec3A,
    /// Solid-angle density of `wi` (1 for delta lights).
    pub pdf: f32,
    /// The point on the light (for a shadow ray); unused when `infinite`.
    pub p_light: Interaction,
    pub delta: bool,
    /// The light is at infinity: the shadow ray runs unbounded along `wi`.
    pub infinite: bool,
}

impl LightSample {
    /// A sample of a light at infinity (sun, sky, infinite, distant) seen from `r`: the
    /// shadow ray runs along `wi` past a point twice the scene's radius away.
    pub fn from_infinity(
        r: &Interaction,
        wi: Vec3A,
        li: Rgb,
        pdf: f32,
        delta: bool,
        world_radius: f32,
    ) -> LightSample {
        LightSample {
            li,
            wi,
            pdf,
            p_light: Interaction {
                p: r.p + wi * (2.0 * world_radius),
                time: r.time,
                ..Default::default()
            },
            delta,
            infinite: true,
        }
    }
}

/// Parameters every light shares.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightCommon {
    /// Index of its light group in the film.
    pub group: usize,
    /// Shadow rays per direct-lighting estimate (`nsamples`).
    pub nsamples: u32,
    /// Shadow rays from depth `low_level` on (`lownsamples`, default `nsamples`).
    pub low_nsamples: u32,
    /// The path depth (bounces before the shading point) where `low_nsamples` takes over
    /// (`lowlevel`; 0: never).
    pub low_level: u32,
    /// Weight of the light in the importance-based light strategies (`importance`, default
    /// 1, at least 0; [`LightSelector`]).
    pub importance: f32,
}

impl LightCommon {
    pub fn from_params(params: &ParamSet, group: usize) -> LightCommon {
        let nsamples = params.int_or("nsamples", 1).max(1) as u32;
        LightCommon {
            group,
            nsamples,
            low_nsamples: params.int_or("lownsamples", nsamples as i32).max(1) as u32,
            low_level: params.int_or("lowlevel", 0).max(0) as u32,
            importance: params.float_or("importance", 1.0).max(0.0),
        }
    }

    /// One shadow ray at every depth, in film group `group`.
    pub fn single(group: usize) -> LightCommon {
        LightCommon {
            group,
            nsamples: 1,
            low_nsamples: 1,
            low_level: 0,
            importance: 1.0,
        }
    }

    /// Shadow rays per estimate at a shading point `depth` bounces down the path.
    pub fn nsamples_at(&self, depth: u32) -> u32 {
        if self.low_level > 0 && depth >= self.low_level {
            self.low_nsamples
        } else {
            self.nsamples
        }
    }
}

#[derive(Debug)]
pub enum Light {
    Point(PointLight),
    Spot(SpotLight),
    Distant(DistantLight),
    Infinite(Box<InfiniteLight>),
    Area(AreaLight),
    /// Rectangle, disc, sphere or cylinder: an emitter that is not scene geometry.
    Primitive(PrimitiveLight),
    Sun(SunLight),
    Sky(Box<SkyLight>),
    /// The Hosek–Wilkie sky (`sky2`).
    Sky2(Box<Sky2Light>),
    /// A point-like light carried by a moving object instance ([`moving`]).
    Moving(Box<MovingLight>),
}

impl Light {
    pub fn common(&self) -> &LightCommon {
        match self {
            Light::Point(l) => &l.common,
            Light::Spot(l) => &l.common,
            Light::Distant(l) => &l.common,
            Light::Infinite(l) => &l.common,
            Light::Area(l) => &l.common,
            Light::Primitive(l) => &l.common,
            Light::Sun(l) => &l.common,
            Light::Sky(l) => &l.common,
            Light::Sky2(l) => &l.common,
            Light::Moving(l) => l.common(),
        }
    }

    pub fn group(&self) -> usize {
        self.common().group
    }

    pub fn nsamples(&self) -> u32 {
        self.common().nsamples
    }

    /// Shadow rays per estimate at a shading point `depth` bounces down the path.
    pub fn nsamples_at(&self, depth: u32) -> u32 {
        self.common().nsamples_at(depth)
    }

    /// True for the lights that are not geometry (found along rays by [`Self::crossings`]).
    pub fn is_primitive(&self) -> bool {
        matches!(self, Light::Primitive(_))
    }

    /// Whether camera rays see the light's emission (area emitters with `visible` false do
    /// not; every other light is either invisible anyway or at infinity).
    pub fn visible(&self) -> bool {
        match self {
            Light::Area(l) => l.profile.visible,
            Light::Primitive(l) => l.profile.visible,
            _ => true,
        }
    }

    /// Calls `f` with each point where `ray` (0 < t < `t_max`) passes through the light
    /// (primitive lights only; others are found as geometry or at infinity).
    pub fn crossings(&self, ray: &Ray, t_max: f32, f: &mut dyn FnMut(&SurfaceInteraction)) {
        if let Light::Primitive(l) = self {
            l.crossings(ray, t_max, f);
        }
    }

    /// Radiance leaving `si` (a point of this area emitter) toward `si.wo`, to a point at
    /// squared distance `d2` (`None`: seen by the camera, which no falloff applies to).
    pub fn le_at(&self, si: &SurfaceInteraction, d2: Option<f32>) -> Rgb {
        match self {
            Light::Area(l) => l.le(si, si.wo, d2),
            Light::Primitive(l) => {
                let q = primshape::PrimPoint {
                    p: si.it.p,
                    n: si.it.n,
                };
                l.le(&q, si.wo, d2)
            }
            _ => Rgb::BLACK,
        }
    }

    /// True for lights a BSDF-sampled ray can never hit (point, spot, sharp distant).
    pub fn is_delta(&self) -> bool {
        match self {
            Light::Point(_) | Light::Spot(_) => true,
            Light::Distant(l) => l.is_delta(),
            Light::Moving(l) => l.inner().is_delta(),
            Light::Infinite(_)
            | Light::Area(_)
            | Light::Primitive(_)
            | Light::Sun(_)
            | Light::Sky(_)
            | Light::Sky2(_) => false,
        }
    }

    /// True for lights at infinity, seen by rays that leave the scene.
    pub fn is_infinite(&self) -> bool {
        match self {
            Light::Infinite(_)
            | Light::Distant(_)
            | Light::Sun(_)
            | Light::Sky(_)
            | Light::Sky2(_) => true,
            Light::Moving(l) => l.at_infinity(),
            Light::Point(_) | Light::Spot(_) | Light::Area(_) | Light::Primitive(_) => false,
        }
    }

    /// Called once the scene bounds are known (distant and infinite lights need them).
    pub fn preprocess(&mut self, center: Vec3A, radius: f32) {
        match self {
            Light::Distant(l) => l.world_radius = radius,
            Light::Infinite(l) => l.world_radius = radius,
            Light::Sun(l) => l.world_radius = radius,
            Light::Sky(l) => l.world_radius = radius,
            Light::Sky2(l) => l.world_radius = radius,
            Light::Moving(l) => l.preprocess(center, radius),
            Light::Point(_) | Light::Spot(_) | Light::Area(_) | Light::Primitive(_) => {}
        }
        let _ = center;
    }

    /// The portals this light is sampled through (infinite, sky and sky2 lights given some).
    pub fn portals(&self) -> Option<&Portals> {
        match self {
            Light::Infinite(l) => l.portals.as_ref(),
            Light::Sky(l) => l.portals.as_ref(),
            Light::Sky2(l) => l.portals.as_ref(),
            _ => None,
        }
    }

    /// Gives the light windows to be sampled through; `false` (and nothing changes) for the
    /// kinds that do not use portals.
    pub fn set_portals(&mut self, portals: Portals) -> bool {
        match self {
            Light::Infinite(l) => l.portals = Some(portals),
            Light::Sky(l) => l.portals = Some(portals),
            Light::Sky2(l) => l.portals = Some(portals),
            _ => return false,
        }
        true
    }

    /// Samples a direction toward the light from `r`; a light with portals draws most of its
    /// directions through them and the rest as it would without ([`portal::PORTAL_SHARE`]).
    pub fn sample_li<S: ShapeSampler + ?Sized>(
        &self,
        r: &Interaction,
        u: Vec2,
        u_pick: f32,
        shapes: &S,
    ) -> Option<LightSample> {
        let Some(portals) = self.portals() else {
            return self.sample_li_ignoring_portals(r, u, u_pick, shapes);
        };
        let share = portal::PORTAL_SHARE;
        let wi = if u_pick < share {
            portals.sample(r.p, u, u_pick / share)?.0
        } else {
            let u_own = ((u_pick - share) / (1.0 - share)).min(1.0 - f32::EPSILON);
            self.sample_li_ignoring_portals(r, u, u_own, shapes)?.wi
        };
        let pdf = self.pdf_li(r, wi, None);
        let s =
            LightSample::from_infinity(r, wi, self.le(wi, r.time), pdf, false, self.world_radius());
        (s.pdf > 0.0 && s.pdf.is_finite() && s.li.is_finite() && !s.li.is_black()).then_some(s)
    }

    /// Samples a direction toward the light from `r` over the light's whole extent, portals
    /// or not (bidirectional's position-free directions at infinity).
    pub fn sample_li_ignoring_portals<S: ShapeSampler + ?Sized>(
        &self,
        r: &Interaction,
        u: Vec2,
        u_pick: f32,
        shapes: &S,
    ) -> Option<LightSample> {
        let s = match self {
            Light::Point(l) => l.sample_li(r),
            Light::Spot(l) => l.sample_li(r),
            Light::Distant(l) => l.sample_li(r, u),
            Light::Infinite(l) => l.sample_li(r, u),
            Light::Area(l) => l.sample_li(r, u, u_pick, shapes),
            Light::Primitive(l) => l.sample_li(r, u),
            Light::Sun(l) => l.sample_li(r, u),
            Light::Sky(l) => l.sample_li(r, u),
            Light::Sky2(l) => l.sample_li(r, u),
            Light::Moving(l) => l.sample_li(r, u, u_pick, shapes),
        }?;
        (s.pdf > 0.0 && s.pdf.is_finite() && s.li.is_finite() && !s.li.is_black()).then_some(s)
    }

    /// Whether [`Self::sample_li`] reads its `u_pick`: a light with portals (it chooses
    /// between them and its own sampling, and picks the portal's triangle), an area light on
    /// a mesh with many triangles, a moving one. The other lights ignore it.
    pub fn reads_pick(&self, shapes: &dyn ShapeSampler) -> bool {
        self.portals().is_some()
            || match self {
                Light::Area(l) => shapes.reads_pick(l.shape),
                Light::Moving(_) => true,
                _ => false,
            }
    }

    /// Solid-angle density with which [`Self::sample_li`] picks `wi` from `r`; for area
    /// lights `hit` is where a ray along `wi` met the light (for primitives, the crossing;
    /// without one, the first crossing along `wi`).
    pub fn pdf_li(&self, r: &Interaction, wi: Vec3A, hit: Option<&SurfaceInteraction>) -> f32 {
        let own = self.pdf_li_ignoring_portals(r, wi, hit);
        match self.portals() {
            Some(p) => portal::mixture_pdf(p.pdf(r.p, wi), own),
            None => own,
        }
    }

    /// The density of [`Self::sample_li_ignoring_portals`].
    pub fn pdf_li_ignoring_portals(
        &self,
        r: &Interaction,
        wi: Vec3A,
        hit: Option<&SurfaceInteraction>,
    ) -> f32 {
        match self {
            Light::Point(_) | Light::Spot(_) => 0.0,
            Light::Moving(l) => l.pdf_li(r, wi),
            Light::Distant(l) => l.pdf_li(wi),
            Light::Infinite(l) => l.pdf_li(wi),
            Light::Area(l) => hit.map_or(0.0, |h| l.pdf_li(r, h)),
            Light::Primitive(l) => hit.map_or_else(|| l.pdf_li(r, wi), |h| l.pdf_at(r, h)),
            Light::Sun(l) => l.pdf_li(wi),
            Light::Sky(l) => l.pdf_li(wi),
            Light::Sky2(l) => l.pdf_li(wi),
        }
    }

    /// Radiance reaching a ray that escapes the scene in direction `dir` at shutter time
    /// `time` (infinite lights, sun, sky and wide distant lights; `time` turns those that
    /// move with an object instance).
    pub fn le(&self, dir: Vec3A, time: f32) -> Rgb {
        match self {
            Light::Infinite(l) => l.le(dir),
            Light::Distant(l) => l.le(dir),
            Light::Sun(l) => l.le(dir),
            Light::Sky(l) => l.le(dir),
            Light::Sky2(l) => l.le(dir),
            Light::Moving(l) => l.le(dir, time),
            _ => Rgb::BLACK,
        }
    }

    /// The scene radius a light at infinity was given ([`Self::preprocess`]): its shadow rays
    /// run twice that far; 1 for the other lights.
    pub fn world_radius(&self) -> f32 {
        match self {
            Light::Infinite(l) => l.world_radius,
            Light::Distant(l) => l.world_radius,
            Light::Sun(l) => l.world_radius,
            Light::Sky(l) => l.world_radius,
            Light::Sky2(l) => l.world_radius,
            Light::Moving(l) => l.inner().world_radius(),
            _ => 1.0,
        }
    }

    /// The light's `importance` (the importance-based light strategies).
    pub fn importance(&self) -> f32 {
        self.common().importance
    }

    /// Emitted power's luminance (for the power-based light strategy).
    pub fn power(&self) -> f32 {
        let p = match self {
            Light::Point(l) => l.power(),
            Light::Spot(l) => l.power(),
            Light::Distant(l) => l.power(),
            Light::Infinite(l) => l.power(),
            Light::Area(l) => l.power(),
            Light::Primitive(l) => l.power(),
            Light::Sun(l) => l.power(),
            Light::Sky(l) => l.power(),
            Light::Sky2(l) => l.power(),
            Light::Moving(l) => l.inner().power(),
        };
        if p.is_finite() {
            p.max(0.0)
        } else {
            0.0
        }
    }
}

/// LuxRender's `power × efficacy / (norm × Y)` gain factor, applied only when positive and
/// finite.
pub fn power_gain(power: f32, efficacy: f32, norm: f32, y: f32) -> f32 {
    let f = power * efficacy / (norm * y);
    if f > 0.0 && f.is_finite() {
        f
    } else {
        1.0
    }
}

/// The f32 matrix of a (static) light transform.
pub fn to_mat4(m: DMat4) -> Mat4 {
    m.as_mat4()
}

pub(crate) fn point3(p: [f32; 3]) -> Vec3A {
    Vec3A::from_array(p)
}
