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
//! [`Ctx::scatter_pdf`] (a surface's BSDF sampling), [`Ctx::camera_pdf`] (the camera's rays)
//! and [`Ctx::emit_pdf`] (a light's emitted rays); [`to_area`] converts a solid-angle density
//! at one vertex to an area density at the next.

use super::BidirIntegrator;
use crate::camera::Camera;
use crate::geometry::{Interaction, SurfaceInteraction};
use crate::light::{Light, LightSelector};
use crate::material::Bsdf;
use crate::scene::World;
use crate::spectrum::Rgb;
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

    /// A surface whose BSDF has a non-delta part (a connection may end here).
    pub fn connectable(&self) -> bool {
        matches!(self.kind, Kind::Surface { .. })
            && self.bsdf.as_ref().is_some_and(|b| b.has_non_specular())
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
    let w = to.p() - from.p();
    let d2 = w.length_squared();
    if d2 == 0.0 {
        return 0.0;
    }
    let cos = to.normal().map_or(1.0, |n| n.dot(w).abs() / d2.sqrt());
    pdf * cos / d2
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
    pub fn scatter_pdf(&self, cur: &Vertex, prev: &Vertex, next: &Vertex) -> f32 {
        let Some(bsdf) = &cur.bsdf else {
            return 0.0;
        };
        let pdf = bsdf.pdf(cur.dir_to(prev), cur.dir_to(next));
        to_area(pdf, cur, next)
    }

    /// Area density of the camera vertex `cam` generating `next`.
    pub fn camera_pdf(&self, cam: &Vertex, next: &Vertex) -> f32 {
        to_area(self.camera.dir_pdf(cam.dir_to(next), self.time), cam, next)
    }

    /// Area density of light vertex `light` (a light point, an emitting surface, or a
    /// direction at infinity) emitting toward `next`.
    pub fn emit_pdf(&self, light: &Vertex, next: &Vertex) -> f32 {
        match light.kind {
            Kind::Sky | Kind::LightDir(_) => {
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
            Kind::Camera | Kind::Surface { emitter: None } => 0.0,
        }
    }

    /// Σ over the lights at infinity that rays meet of `count(i) ×` their direction density
    /// toward `dir`.
    fn sky_density(&self, dir: Vec3A, count: impl Fn(usize) -> f32) -> f32 {
        let lights = self.world.lights();
        let at = Interaction::default();
        self.world
            .infinite_lights()
            .iter()
            .filter_map(|&i| Some((i, lights.get(i)?)))
            .map(|(i, l)| count(i) * l.pdf_li_ignoring_portals(&at, dir, None))
            .sum()
    }

    /// Density of light vertex `v` as the origin of a light subpath (position × choice).
    pub fn origin_density(&self, v: &Vertex) -> f32 {
        self.light_density(v, |i| self.path_draws(i))
    }

    /// Density of light vertex `v` as sampled by direct lighting from a surface.
    pub fn direct_density(&self, v: &Vertex) -> f32 {
        self.light_density(v, |i| self.direct_draws(i))
    }

    fn light_density(&self, v: &Vertex, count: impl Fn(usize) -> f32) -> f32 {
        match v.kind {
            Kind::Sky => self.sky_density(v.dir, count),
            Kind::LightDir(i) => count(i as usize),
            Kind::LightPoint(i) | Kind::Surface { emitter: Some(i) } => {
                count(i as usize) * self.light(i).map_or(0.0, Light::area_density)
            }
            Kind::Camera | Kind::Surface { emitter: None } => 0.0,
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

/// Expected draws of light `i` under a selection: 1 each for `All`, the choice probability
/// for `One`.
pub fn draws(sel: &LightSelector, i: usize) -> f32 {
    match sel {
        LightSelector::All => 1.0,
        LightSelector::One(d) => d.discrete_pdf(i),
    }
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
