//! Path vertices of bidirectional path tracing and the densities between them.
//!
//! A vertex is the camera, a point on a light, a direction toward the lights at infinity, or
//! a surface hit. Each remembers its throughput `beta` (the subpath's value up to it over its
//! density) and two area densities (solid angle for directions at infinity): `pdf_fwd`, with
//! which its own subpath generated it, and `pdf_rev`, with which the other subpath would have
//! generated it. Multiple importance sampling ([`super::mis`]) compares strategies through
//! these densities.
//!
//! The density of generating one vertex from another is asked in three ways:
//! [`Ctx::scatter_pdf`] (a surface's BSDF or a medium point's phase function),
//! [`Ctx::camera_pdf`] (the camera's rays) and [`Ctx::emit_pdf`] (a light's emitted rays);
//! [`to_area`] converts a solid-angle density at one vertex to an area density at the next
//! (with no cosine at a point in a medium).
//!
//! In a scene with scattering media a ray's end is itself sampled (distance sampling: it stops
//! in a medium or passes through to a surface), so every area density also carries the
//! probability of that end: [`Ctx::segment`] walks the segment between two vertices through
//! null surfaces and medium boundaries and returns, besides the segment's transmittance, this
//! factor in both directions. Each vertex keeps the medium it was reached in (`medium`) and
//! the factor of the reverse direction of the segment that reached it (`dist_rev`).

use super::BidirIntegrator;
use crate::camera::Camera;
use crate::geometry::{Interaction, SurfaceInteraction};
use crate::light::{Light, LightSelector};
use crate::material::Bsdf;
use crate::scene::{SegmentEnd, World};
use crate::spectrum::Rgb;
use crate::volume::{channel_avg, HenyeyGreenstein, Medium, MediumId};
use glam::Vec3A;

/// What a vertex is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// The camera's lens point.
    Camera,
    /// A point on a finite light (area, point or spot) with its index.
    LightPoint(u32),
    /// The direction of a sharp distant light (index): a delta direction at infinity.
    LightDir(u32),
    /// A direction toward the lights at infinity that rays can meet (infinite, sky, sun,
    /// wide distant): all of them at once.
    Sky,
    /// A surface hit; `emitter` is its area light's index when it has one.
    Surface { emitter: Option<u32> },
    /// A scattering point in a medium (`medium`, with its phase function).
    Medium,
}

/// One vertex of a subpath.
#[derive(Clone, Debug)]
pub struct Vertex {
    pub kind: Kind,
    /// The hit (surfaces), or the point with its normal (lights, camera: `it` only).
    pub si: SurfaceInteraction,
    /// Unit direction toward the lights for `Sky` and `LightDir` vertices.
    pub dir: Vec3A,
    pub bsdf: Option<Bsdf>,
    pub beta: Rgb,
    /// The scattering sampled at this vertex was a delta distribution.
    pub delta: bool,
    pub pdf_fwd: f32,
    pub pdf_rev: f32,
    /// The medium the vertex lies in (a medium point) or was reached through (a surface: the
    /// medium on the arriving side); for the camera and lights, the one their rays start in.
    pub medium: Option<MediumId>,
    /// The phase function of a medium point.
    pub phase: Option<HenyeyGreenstein>,
    /// The distance-sampling factor of generating the previous vertex of this subpath from
    /// this one (1 without scattering media).
    pub dist_rev: f32,
}

impl Vertex {
    pub fn new(kind: Kind, si: SurfaceInteraction, beta: Rgb, pdf_fwd: f32) -> Vertex {
        Vertex {
            kind,
            si,
            dir: Vec3A::ZERO,
            bsdf: None,
            beta,
            delta: false,
            pdf_fwd,
            pdf_rev: 0.0,
            medium: None,
            phase: None,
            dist_rev: 1.0,
        }
    }

    /// A vertex at infinity in direction `dir` (toward the light).
    pub fn at_infinity(kind: Kind, dir: Vec3A, beta: Rgb, pdf_fwd: f32) -> Vertex {
        let mut v = Vertex::new(kind, SurfaceInteraction::default(), beta, pdf_fwd);
        v.dir = dir;
        v
    }

    pub fn p(&self) -> Vec3A {
        self.si.it.p
    }

    pub fn is_at_infinity(&self) -> bool {
        matches!(self.kind, Kind::Sky | Kind::LightDir(_))
    }

    /// A surface whose BSDF has a non-delta part, or a point in a medium (a connection may
    /// end here).
    pub fn connectable(&self) -> bool {
        match self.kind {
            Kind::Surface { .. } => self.bsdf.as_ref().is_some_and(|b| b.has_non_specular()),
            Kind::Medium => self.phase.is_some(),
            _ => false,
        }
    }

    /// The eye side's value of the vertex's scattering of light arriving from unit direction
    /// `wi` toward `si.wo`: f·|wi·ns| at a surface, the phase function at a medium point.
    pub fn f_eye(&self, wi: Vec3A) -> Rgb {
        if let Some(ph) = self.phase {
            return Rgb::splat(ph.eval(-self.si.wo, wi));
        }
        match &self.bsdf {
            Some(b) => b.f(self.si.wo, wi) * wi.dot(b.frame.n).abs(),
            None => Rgb::BLACK,
        }
    }

    /// The medium a ray leaving this vertex in direction `d` starts in.
    pub fn medium_toward(&self, world: &World, d: Vec3A) -> Option<MediumId> {
        match (self.kind, world.media()) {
            (Kind::Surface { .. }, Some(ms)) => {
                ms.after(self.si.prim, self.si.it.n, d, self.medium)
            }
            (Kind::LightPoint(i), Some(ms)) => ms
                .area_light_side(i as usize, self.si.it.n, d)
                .unwrap_or(self.medium),
            _ => self.medium,
        }
    }

    /// The geometric normal that densities on this vertex are measured with (none for the
    /// camera and point-like lights).
    fn normal(&self) -> Option<Vec3A> {
        match self.kind {
            Kind::Surface { .. } | Kind::LightPoint(_) if self.si.it.n != Vec3A::ZERO => {
                Some(self.si.it.n)
            }
            _ => None,
        }
    }

    /// Unit direction from this vertex toward `other`.
    pub fn dir_to(&self, other: &Vertex) -> Vec3A {
        if other.is_at_infinity() {
            other.dir
        } else {
            (other.p() - self.p()).normalize_or_zero()
        }
    }

    /// The interaction a ray toward `other` leaves from.
    pub fn interaction(&self) -> Interaction {
        self.si.it
    }
}

/// A solid-angle density at `from` for the direction toward `to`, as an area density at
/// `to` (unchanged when `to` is at infinity).
pub fn to_area(pdf: f32, from: &Vertex, to: &Vertex) -> f32 {
    if to.is_at_infinity() {
        return pdf;
    }
    let d2 = (to.p() - from.p()).length_squared();
    if d2 == 0.0 {
        return 0.0;
    }
    pdf * cos_toward(to, from) / d2
}

/// |cos| between `v`'s normal and the segment toward `other` (1 without a normal: the
/// camera, point lights, medium points).
pub fn cos_toward(v: &Vertex, other: &Vertex) -> f32 {
    let w = other.p() - v.p();
    let len = w.length();
    match v.normal() {
        Some(n) if len > 0.0 => n.dot(w).abs() / len,
        Some(_) => 0.0,
        None => 1.0,
    }
}

/// A segment between two vertices: its transmittance and the distance-sampling factors of
/// generating each end from the other (1 without scattering media).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    pub tr: Rgb,
    pub a_to_b: f32,
    pub b_to_a: f32,
}

impl Segment {
    /// A segment through no medium: full transmittance, distance factors 1.
    const CLEAR: Segment = Segment {
        tr: Rgb::WHITE,
        a_to_b: 1.0,
        b_to_a: 1.0,
    };

    fn reversed(self) -> Segment {
        Segment {
            tr: self.tr,
            a_to_b: self.b_to_a,
            b_to_a: self.a_to_b,
        }
    }
}

/// What densities need besides the vertices: the world, the camera, the integrator's
/// light selections and the sample's time.
pub struct Ctx<'a> {
    pub world: &'a World,
    pub camera: &'a Camera,
    pub bidir: &'a BidirIntegrator,
    pub time: f32,
}

impl Ctx<'_> {
    pub fn light(&self, i: u32) -> Option<&Light> {
        self.world.lights().get(i as usize)
    }

    /// Expected light samples of light `i` per direct-lighting estimate.
    pub fn direct_draws(&self, i: usize) -> f32 {
        draws(self.world.selector(), i)
    }

    /// Expected light subpaths starting on light `i` per sample.
    pub fn path_draws(&self, i: usize) -> f32 {
        draws(self.bidir.path_selector(), i)
    }

    /// Area density of generating `next` by sampling the BSDF at surface `cur` that was
    /// reached from `prev`.
    /// (Geometry only: the distance-sampling factor of the segment is the caller's.)
    pub fn scatter_pdf(&self, cur: &Vertex, prev: &Vertex, next: &Vertex) -> f32 {
        let pdf = if let Some(ph) = cur.phase {
            ph.eval(-cur.dir_to(prev), cur.dir_to(next))
        } else if let Some(bsdf) = &cur.bsdf {
            bsdf.pdf(cur.dir_to(prev), cur.dir_to(next))
        } else {
            return 0.0;
        };
        to_area(pdf, cur, next)
    }

    /// Whether the scene's media are sampled for scattering (some medium scatters and the
    /// volume integrator lets paths scatter): distance-sampling factors differ from 1.
    pub fn scattering(&self) -> bool {
        self.bidir.volume.max_scatters() > 0 && self.world.media().is_some_and(|m| m.scatters)
    }

    /// Whether rays in medium `m` are distance sampled (else only attenuated).
    pub fn samples_distance(&self, m: &Medium) -> bool {
        self.bidir.volume.max_scatters() > 0 && m.scatters()
    }

    /// Walks the segment between `a` and `b` ([`World::walk_segment`]); `None` when a
    /// surface blocks it.
    pub fn segment(&self, a: &Vertex, b: &Vertex) -> Option<Segment> {
        if a.is_at_infinity() {
            return self.segment(b, a).map(Segment::reversed);
        }
        let end = if b.is_at_infinity() {
            SegmentEnd::Direction(b.dir)
        } else {
            SegmentEnd::Point(&b.si.it)
        };
        if self.world.media().is_none() {
            // No media: only visibility (the common case, kept as lean as a shadow ray).
            return self
                .world
                .walk_segment(&a.si.it, end, None, |_, _, _| {})
                .then_some(Segment::CLEAR);
        }
        let start = a.medium_toward(self.world, a.dir_to(b));
        let scattering = self.scattering();
        let mut tr = Rgb::WHITE;
        // Channel-averaged transmittance of the pieces in distance-sampled media: the first
        // piece's, the last one's, and the products of all but the first / last.
        let (mut first, mut last) = (None::<Rgb>, None::<Rgb>);
        let (mut but_first, mut but_last) = (1.0f32, 1.0f32);
        let open = self
            .world
            .walk_segment(&a.si.it, end, start, |m, ray, t_end| {
                let Some(m) = m else {
                    return;
                };
                let t = m.tr(ray, t_end);
                tr *= t;
                if !scattering {
                    return;
                }
                let piece = if self.samples_distance(m) {
                    t
                } else {
                    Rgb::WHITE
                };
                if let Some(lt) = last {
                    but_last *= channel_avg(lt);
                }
                if first.is_none() {
                    first = Some(piece);
                } else {
                    but_first *= channel_avg(piece);
                }
                last = Some(piece);
            });
        if !open {
            return None;
        }
        // Stopping at a medium point: sigma_t there times the transmittance of its piece.
        let end_factor = |v: &Vertex, piece: Option<Rgb>| -> f32 {
            match (v.kind, piece) {
                (Kind::Medium, Some(t)) => {
                    let st = v
                        .medium
                        .and_then(|id| self.world.media().and_then(|ms| ms.get(id)))
                        .map_or(Rgb::BLACK, |m| m.sigma_t(v.p()));
                    channel_avg(st * t)
                }
                (Kind::Medium, None) => 0.0,
                (_, Some(t)) => channel_avg(t),
                (_, None) => 1.0,
            }
        };
        Some(Segment {
            tr,
            a_to_b: but_last * end_factor(b, last),
            b_to_a: but_first * end_factor(a, first),
        })
    }

    /// Area density of the camera vertex `cam` generating `next`.
    pub fn camera_pdf(&self, cam: &Vertex, next: &Vertex) -> f32 {
        to_area(self.camera.dir_pdf(cam.dir_to(next), self.time), cam, next)
    }

    /// Area density of light vertex `light` (a light point, an emitting surface, or a
    /// direction at infinity) emitting toward `next`.
    pub fn emit_pdf(&self, light: &Vertex, next: &Vertex) -> f32 {
        match light.kind {
            Kind::Sky => {
                let cos = next.normal().map_or(1.0, |n| n.dot(light.dir).abs());
                self.sky_line_density(next.p(), light.dir) * cos
            }
            Kind::LightDir(_) => {
                let disc = self.world.bounding_sphere().disc_pdf();
                let cos = next.normal().map_or(1.0, |n| n.dot(light.dir).abs());
                disc * cos
            }
            Kind::LightPoint(i) | Kind::Surface { emitter: Some(i) } => {
                let Some(l) = self.light(i) else {
                    return 0.0;
                };
                let pdf = l.pdf_dir_from(&light.si.it, light.dir_to(next));
                to_area(pdf, light, next)
            }
            Kind::Camera | Kind::Surface { emitter: None } | Kind::Medium => 0.0,
        }
    }

    /// Σ over the lights at infinity that rays meet of `count(i) ×` their direction density
    /// toward `dir`: from `from` as direct lighting draws it (through a light's portals as
    /// well, [`Light::pdf_li`]), or without a point as light subpaths draw it.
    fn sky_density(&self, dir: Vec3A, from: Option<&Vertex>, count: impl Fn(usize) -> f32) -> f32 {
        let lights = self.world.lights();
        let lights_at_infinity = self
            .world
            .infinite_lights()
            .iter()
            .filter_map(|&i| Some((i, lights.get(i)?)));
        match from {
            Some(f) => lights_at_infinity
                .map(|(i, l)| count(i) * l.pdf_li(&f.si.it, dir, None))
                .sum(),
            None => {
                let at = Interaction {
                    time: self.time,
                    ..Default::default()
                };
                lights_at_infinity
                    .map(|(i, l)| count(i) * l.pdf_li_ignoring_portals(&at, dir, None))
                    .sum()
            }
        }
    }

    /// Density, per unit area across it, of the line through `p` toward the lights at infinity
    /// in direction `dir` as light subpaths draw it: each light's own line density (the disc
    /// facing it, or its portals mixed with the disc, [`Light::line_density`]) weighed by how
    /// often it emits that direction; only its product with the direction density
    /// ([`Self::origin_density`]) enters the weights, and that product is the sum over lights.
    pub fn sky_line_density(&self, p: Vec3A, dir: Vec3A) -> f32 {
        let lights = self.world.lights();
        let sphere = self.world.bounding_sphere();
        let at = Interaction {
            time: self.time,
            ..Default::default()
        };
        let (mut num, mut den) = (0.0f32, 0.0f32);
        for &i in self.world.infinite_lights() {
            let Some(l) = lights.get(i) else {
                continue;
            };
            let w = self.path_draws(i) * l.pdf_li_ignoring_portals(&at, dir, None);
            num += w * l.line_density(p, dir, sphere);
            den += w;
        }
        if den > 0.0 {
            num / den
        } else {
            sphere.disc_pdf()
        }
    }

    /// Density of light vertex `v` as the origin of a light subpath (position × choice).
    pub fn origin_density(&self, v: &Vertex) -> f32 {
        self.light_density(v, None, |i| self.path_draws(i))
    }

    /// Density of light vertex `v` as sampled by direct lighting from the surface or medium
    /// vertex `from` (portals make a direction's density depend on where it is drawn from).
    pub fn direct_density(&self, v: &Vertex, from: Option<&Vertex>) -> f32 {
        self.light_density(v, from, |i| self.direct_draws(i))
    }

    fn light_density(
        &self,
        v: &Vertex,
        from: Option<&Vertex>,
        count: impl Fn(usize) -> f32,
    ) -> f32 {
        match v.kind {
            Kind::Sky => self.sky_density(v.dir, from, count),
            Kind::LightDir(i) => count(i as usize),
            Kind::LightPoint(i) | Kind::Surface { emitter: Some(i) } => {
                count(i as usize) * self.light(i).map_or(0.0, Light::area_density)
            }
            Kind::Camera | Kind::Surface { emitter: None } | Kind::Medium => 0.0,
        }
    }

    /// Whether a light vertex can be hit by a ray (not a delta position or direction).
    pub fn hittable(&self, v: &Vertex) -> bool {
        match v.kind {
            Kind::Sky | Kind::Surface { emitter: Some(_) } => true,
            Kind::LightPoint(i) => self.light(i).is_some_and(|l| !l.is_delta_position()),
            _ => false,
        }
    }
}

/// Expected draws of light `i` under a selection: 1 each for `All`, the draws times the
/// choice probability otherwise.
pub fn draws(sel: &LightSelector, i: usize) -> f32 {
    sel.pdf(i)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn area_conversion_uses_the_receiving_normal() {
        let mut a = Vertex::new(
            Kind::Surface { emitter: None },
            SurfaceInteraction::default(),
            Rgb::WHITE,
            1.0,
        );
        a.si.it.n = Vec3A::Z;
        let mut b = a.clone();
        b.si.it.p = Vec3A::new(0.0, 2.0, 2.0);
        b.si.it.n = Vec3A::Y;
        // d² = 8, cos at b = 2 / sqrt(8).
        let want = 3.0 * (2.0 / 8f32.sqrt()) / 8.0;
        assert!((to_area(3.0, &a, &b) - want).abs() < 1e-6);
        let sky = Vertex::at_infinity(Kind::Sky, Vec3A::Z, Rgb::WHITE, 1.0);
        assert_eq!(to_area(3.0, &a, &sky), 3.0);
        assert_eq!(a.dir_to(&sky), Vec3A::Z);
    }
}
