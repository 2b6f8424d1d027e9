//! The `directlighting` integrator: emission plus direct lighting (light samples and one BSDF
//! sample, combined with MIS) at the first hit, and recursion along perfectly specular
//! reflection/refraction up to `maxdepth` (5) times.
//!
//! In a scene with participating media ([`crate::volume`]) the eye path knows the medium it
//! is in (the camera's, changed where it crosses a medium boundary, specular bounces
//! included): every segment, shadow ray and BSDF-sampled ray is attenuated by the media it
//! crosses (the `emission` volume integrator and up). With `single` or `multi` the eye path
//! may instead scatter once in a medium (distance sampling, as `path` does it): that point
//! receives direct lighting through the phase function (light samples and one phase sample,
//! combined with MIS) and ends the path, as a surface's direct lighting does. This is
//! LuxRender 1.x's single scattering along the eye ray. The emission of region volumes is
//! added along the eye ray and its specular continuations (where LuxRender 1.x's
//! directlighting adds its volume integrator's `Li`), not along the rays that sample the
//! BSDF for direct light.

use super::direct::{
    add_emission, add_medium_emission, bsdf_hit_weight, escaped, sample_lights, Arrival, Scatterer,
};
use super::volume::VolumeIntegrator;
use super::{bsdf_samples, select_sample, DirectSettings};
use crate::geometry::{Interaction, Ray};
use crate::plugin::Stmt;
use crate::sampler::SampleStream;
use crate::scene::World;
use crate::spectrum::Rgb;
use crate::volume::MediumId;
use glam::Vec3A;

const MAX_PASS_THROUGH: u32 = 64;

#[derive(Clone, Debug)]
pub struct DirectLightingIntegrator {
    pub max_depth: u32,
    pub direct: DirectSettings,
    /// How far media are rendered (the scene's VolumeIntegrator).
    pub volume: VolumeIntegrator,
}

/// A direction sampled at a scattering point for the BSDF (or phase) half of the MIS
/// estimate: the ray, the medium it starts in, its throughput factor f·|cos|/pdf and density.
struct Continuation {
    ray: Ray,
    medium: Option<MediumId>,
    weight: Rgb,
    pdf: f32,
}

impl DirectLightingIntegrator {
    /// Reads a `directlighting` statement.
    pub fn build(s: &mut Stmt) -> Self {
        DirectLightingIntegrator {
            max_depth: s.params().int_or("maxdepth", 5).max(0) as u32,
            direct: DirectSettings::build(s),
            volume: VolumeIntegrator::default(),
        }
    }

    pub fn li(&self, scene: &World, mut ray: Ray, s: &mut SampleStream, l: &mut [Rgb]) -> f32 {
        let mut beta = Rgb::WHITE;
        let mut alpha = 1.0;
        let mut depth = 0;
        let mut pass = 0;
        // The last specular vertex (the camera ray has none).
        let mut prev = Interaction::default();
        let media = scene.media();
        let mut medium = media.and_then(|m| m.camera);
        let scatters = self.volume.max_scatters() > 0;
        loop {
            // Matched by reference: moving the hit out of the Option would copy it.
            let hit = scene.intersect(&ray);
            let arrival = if depth == 0 {
                Arrival::Camera
            } else {
                Arrival::Unweighted(&prev)
            };
            let mut t_hit = hit.as_ref().map_or(f32::INFINITY, |h| h.t);
            let mut scattered = None;
            if let Some(m) = medium.and_then(|id| media.and_then(|ms| ms.get(id))) {
                add_medium_emission(m, &ray, t_hit, beta, l);
                if scatters && m.scatters() {
                    let ms = m.sample(&ray, t_hit, s.next_1d(), s.next_1d());
                    beta *= ms.weight;
                    if let Some(t) = ms.scatter_t {
                        t_hit = t;
                        scattered = Some(ms.phase);
                    }
                } else {
                    beta *= m.tr(&ray, t_hit);
                }
            }
            scene.crossed_lights(&ray, t_hit, |i, c| {
                add_emission(scene, &self.direct, i, c, arrival, beta, l)
            });
            if let Some(phase) = scattered {
                if !beta.is_black() && beta.is_finite() {
                    let it = Interaction {
                        p: ray.at(t_hit),
                        time: ray.time,
                        ..Interaction::default()
                    };
                    let at = Scatterer::Medium {
                        it: &it,
                        d_in: ray.d.normalize_or_zero(),
                        phase,
                    };
                    sample_lights(scene, &self.direct, &at, medium, s, beta, false, depth, l);
                    self.mis_sample(scene, &at, medium, s, beta, depth, l);
                }
                break;
            }
            let Some(si) = &hit else {
                if depth == 0 {
                    alpha = 0.0;
                }
                escaped(scene, &ray, beta, l, |_| 1.0);
                break;
            };
            if let Some((i, _)) = scene.area_light(si.prim) {
                add_emission(scene, &self.direct, i, si, arrival, beta, l);
            }
            let material = scene.material(si.prim);
            if material.is_null() {
                pass += 1;
                if pass > MAX_PASS_THROUGH {
                    break;
                }
                if let Some(ms) = media {
                    medium = ms.after(si.prim, si.it.n, ray.d, medium);
                }
                ray = si.it.spawn_ray(ray.d);
                continue;
            }
            pass = 0;
            let u_select = select_sample(material, s);
            let bsdf = material.bsdf(si, u_select);
            if bsdf.has_non_specular() {
                let at = Scatterer::Surface { si, bsdf: &bsdf };
                sample_lights(scene, &self.direct, &at, medium, s, beta, false, depth, l);
                self.mis_sample(scene, &at, medium, s, beta, depth, l);
            }
            if depth >= self.max_depth {
                break;
            }
            let (u, u2) = bsdf_samples(&bsdf, s);
            match bsdf.sample_f(si.wo, u, u2) {
                Some(bs) if bs.specular && bs.pdf > 0.0 => {
                    beta *= bs.f * (bs.wi.dot(bsdf.frame.n).abs() / bs.pdf);
                    prev = si.it;
                    ray = si.it.spawn_ray(bs.wi);
                    if let Some(ms) = media {
                        medium = ms.after(si.prim, si.it.n, bs.wi, medium);
                    }
                    depth += 1;
                }
                _ => break,
            }
            if !beta.is_finite() || beta.is_black() {
                break;
            }
        }
        alpha
    }

    /// Samples the BSDF (non-specular part) or the phase function at `at` for the MIS
    /// half of direct lighting; `None` when nothing usable was drawn.
    fn continuation(
        at: &Scatterer,
        medium: Option<MediumId>,
        scene: &World,
        s: &mut SampleStream,
    ) -> Option<Continuation> {
        let (u, u2) = (s.next_1d(), s.next_2d());
        match at {
            Scatterer::Surface { si, bsdf } => {
                let bs = bsdf.sample_f(si.wo, u, u2)?;
                if bs.specular || bs.pdf <= 0.0 || bs.f.is_black() {
                    return None;
                }
                let medium = scene
                    .media()
                    .map_or(medium, |ms| ms.after(si.prim, si.it.n, bs.wi, medium));
                Some(Continuation {
                    ray: si.it.spawn_ray(bs.wi),
                    medium,
                    weight: bs.f * (bs.wi.dot(bsdf.frame.n).abs() / bs.pdf),
                    pdf: bs.pdf,
                })
            }
            Scatterer::Medium { it, d_in, phase } => {
                let (wi, pdf) = phase.sample(*d_in, u2);
                if pdf <= 0.0 || wi == Vec3A::ZERO {
                    return None;
                }
                // The phase function is sampled exactly: f / pdf = 1.
                Some(Continuation {
                    ray: it.spawn_ray(wi),
                    medium,
                    weight: Rgb::WHITE,
                    pdf,
                })
            }
        }
    }

    /// The BSDF- (or phase-) sampling half of the direct-lighting MIS estimate at `at`, a
    /// scattering point `depth` specular bounces from the camera in `medium`: the sampled
    /// ray crosses null surfaces (and the media they bound, attenuated) to the emitter it
    /// meets.
    #[allow(clippy::too_many_arguments)]
    fn mis_sample(
        &self,
        scene: &World,
        at: &Scatterer,
        medium: Option<MediumId>,
        s: &mut SampleStream,
        beta: Rgb,
        depth: u32,
        l: &mut [Rgb],
    ) {
        let Some(c) = Self::continuation(at, medium, scene, s) else {
            return;
        };
        let origin = match at {
            Scatterer::Surface { si, .. } => &si.it,
            Scatterer::Medium { it, .. } => *it,
        };
        let media = scene.media();
        let (mut ray, mut medium, mut tp) = (c.ray, c.medium, beta * c.weight);
        let arrival = Arrival::Bsdf(origin, c.pdf, depth);
        for _ in 0..MAX_PASS_THROUGH {
            let hit = scene.intersect(&ray);
            let t_hit = hit.as_ref().map_or(f32::INFINITY, |h| h.t);
            if let Some(m) = medium.and_then(|id| media.and_then(|ms| ms.get(id))) {
                tp *= m.tr(&ray, t_hit);
            }
            if tp.is_black() {
                return;
            }
            scene.crossed_lights(&ray, t_hit, |i, cr| {
                add_emission(scene, &self.direct, i, cr, arrival, tp, l)
            });
            let Some(hit) = &hit else {
                let d = ray.d.normalize_or_zero();
                escaped(scene, &ray, tp, l, |i| {
                    let pl = scene.lights()[i].pdf_li(origin, d, None);
                    bsdf_hit_weight(scene, &self.direct, i, c.pdf, pl, depth)
                });
                return;
            };
            if let Some((i, _)) = scene.area_light(hit.prim) {
                add_emission(scene, &self.direct, i, hit, arrival, tp, l);
            }
            if !scene.material(hit.prim).is_null() {
                return;
            }
            if let Some(ms) = media {
                medium = ms.after(hit.prim, hit.it.n, ray.d, medium);
            }
            ray = hit.it.spawn_ray(ray.d);
        }
    }
}
