//! The `path` integrator: unidirectional path tracing with next-event estimation, MIS
//! between light and BSDF sampling, and Russian roulette (none / probability / efficiency).
//! Rendering a `distributedpath` scene it also applies the materials' `compo_*` flags as
//! LuxRender's distributedpath does ([`crate::material::Compositing`]): hidden emission or
//! surfaces, overridden alpha.
//!
//! In a scene with participating media ([`crate::volume`]) the path knows the medium it is in
//! (the camera's, changed where it crosses a medium boundary): each segment is attenuated by
//! it, and with the `single`/`multi` volume integrator may scatter in it, the scattering point
//! then being a path vertex with direct lighting through the phase function. Along every
//! segment in an emitting region volume the path adds the region's emission seen through the
//! medium (as LuxRender 1.x's path integrator adds its volume integrator's `Li` per
//! segment; no other strategy samples it, so it counts fully). A scene without media never
//! has a current medium and takes none of these branches.
//!
//! In a scene whose materials disperse light, a path that meets a dispersing surface is given
//! a wavelength there ([`super::spectral`]); other scenes and paths stay RGB.

use super::direct::{
    add_emission, add_medium_emission, bsdf_hit_weight, escaped, sample_lights, Arrival, Scatterer,
};
use super::spectral::sample_wavelength;
use super::volume::VolumeIntegrator;
use super::{bsdf_samples, select_sample, DirectSettings};
use crate::geometry::{Interaction, Ray};
use crate::plugin::{BuildError, Stmt};
use crate::sampler::SampleStream;
use crate::scene::World;
use crate::spectrum::Rgb;
use glam::Vec3A;

/// Russian roulette after this many vertices (LuxRender starts at path length 3).
const RR_START: u32 = 3;
/// Null (pass-through) surfaces crossed by one path segment before giving up.
const MAX_PASS_THROUGH: u32 = 64;

/// Whether a path goes on from its last vertex (the one at depth `maxdepth - 1`) after
/// sampling its BSDF there. LuxRender 1.x samples lights at path vertices 0..maxdepth-1 and
/// adds emission at vertex `maxdepth` only for what light sampling cannot reach: a specular
/// bounce, or every bounce when light sampling is off. So a path has at most `maxdepth + 1`
/// segments (LuxCore's `pathdepth.total` and Mitsuba's `max_depth` of `maxdepth + 1`).
fn continues_past_last(direct_light_sampling: bool, specular_bounce: bool) -> bool {
    !direct_light_sampling || specular_bounce
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Roulette {
    None,
    /// Continue with a fixed probability.
    Probability(f32),
    /// Continue with probability min(1, throughput), LuxRender's "efficiency".
    Efficiency,
}

#[derive(Clone, Debug)]
pub struct PathIntegrator {
    pub max_depth: u32,
    pub roulette: Roulette,
    pub include_environment: bool,
    pub direct_light_sampling: bool,
    pub direct: DirectSettings,
    /// Apply the materials' compositing flags (set when standing in for distributedpath).
    pub compositing: bool,
    /// How far media are rendered (the scene's VolumeIntegrator).
    pub volume: VolumeIntegrator,
}

impl PathIntegrator {
    /// Reads a `path` statement.
    pub fn build(s: &mut Stmt) -> Result<Self, BuildError> {
        let p = s.params();
        let max_depth = p.int_or("maxdepth", 16).max(0) as u32;
        let prob = p.float_or("rrcontinueprob", 0.65).clamp(0.0, 1.0);
        let roulette = match p.string_or("rrstrategy", "efficiency") {
            "none" => Roulette::None,
            "probability" => Roulette::Probability(prob),
            "efficiency" => Roulette::Efficiency,
            other => {
                return Err(s.err(format!(
                    "unknown rrstrategy \"{other}\" (none, probability, efficiency)"
                )))
            }
        };
        Ok(PathIntegrator {
            max_depth,
            roulette,
            include_environment: p.bool_or("includeenvironment", true),
            direct_light_sampling: p.bool_or("directlightsampling", true),
            direct: DirectSettings::build(s),
            compositing: false,
            volume: VolumeIntegrator::default(),
        })
    }

    pub fn li(&self, scene: &World, mut ray: Ray, s: &mut SampleStream, l: &mut [Rgb]) -> f32 {
        let mut beta = Rgb::WHITE;
        let mut alpha = 1.0;
        // Whether the last bounce was specular (or the camera ray): emission counts fully.
        let mut specular = true;
        let mut prev_pdf = 0.0f32;
        let mut prev = Interaction::default();
        let mut depth = 0u32;
        let mut pass = 0u32;
        let dls = self.direct_light_sampling;
        let media = scene.media();
        let mut medium = media.and_then(|m| m.camera);
        let mut scatters_left = self.volume.max_scatters();
        // The path's wavelength once it met a dispersing surface (see `super::spectral`).
        let mut lambda: Option<f32> = None;
        loop {
            // Matched by reference: moving the hit out of the Option would copy it.
            let hit = scene.intersect(&ray);
            let arrival = if depth == 0 {
                Arrival::Camera
            } else if specular || !dls {
                Arrival::Unweighted(&prev)
            } else {
                Arrival::Bsdf(&prev, prev_pdf, depth - 1)
            };
            let mut t_hit = hit.as_ref().map_or(f32::INFINITY, |h| h.t);
            let mut scattered = None;
            if let Some(m) = medium.and_then(|id| media.and_then(|ms| ms.get(id))) {
                add_medium_emission(m, &ray, t_hit, beta, l);
                if scatters_left > 0 && m.scatters() {
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
                // A scattering vertex in the medium.
                if depth >= self.max_depth || beta.is_black() {
                    break;
                }
                let it = Interaction {
                    p: ray.at(t_hit),
                    time: ray.time,
                    ..Interaction::default()
                };
                let d_in = ray.d.normalize_or_zero();
                let last = depth + 1 >= self.max_depth;
                if dls {
                    let at = Scatterer::Medium {
                        it: &it,
                        d_in,
                        phase,
                    };
                    sample_lights(scene, &self.direct, &at, medium, s, beta, last, depth, l);
                }
                // A phase function has no specular lobe: the last vertex ends the path once
                // its light was sampled.
                if last && !continues_past_last(dls, false) {
                    break;
                }
                // The phase function is sampled exactly: the throughput is unchanged.
                let (wi, pdf) = phase.sample(d_in, s.next_2d());
                if pdf <= 0.0 || wi == Vec3A::ZERO {
                    break;
                }
                scatters_left -= 1;
                specular = false;
                prev_pdf = pdf;
                prev = it;
                ray = Ray {
                    o: it.p,
                    d: wi,
                    t_max: f32::INFINITY,
                    time: ray.time,
                };
                depth += 1;
                if !self.roulette(depth, &mut beta, s) {
                    break;
                }
                continue;
            }
            let Some(si) = &hit else {
                if depth == 0 {
                    alpha = 0.0;
                }
                if depth > 0 || self.include_environment {
                    escaped(scene, &ray, beta, l, |i| {
                        if specular || !dls {
                            return 1.0;
                        }
                        let light = &scene.lights()[i];
                        let pl = light.pdf_li(&prev, ray.d.normalize_or_zero(), None);
                        bsdf_hit_weight(scene, &self.direct, i, prev_pdf, pl, depth - 1)
                    });
                }
                break;
            };
            let material = scene.material(si.prim);
            let vis = self.compositing.then(|| {
                if depth == 0 {
                    material.compositing.camera_hit()
                } else {
                    material.compositing.indirect_hit()
                }
            });
            if let Some(a) = vis.and_then(|v| v.alpha) {
                alpha = a;
            }
            let emission = vis.is_none_or(|v| v.emission);
            if let Some((i, _)) = scene.area_light(si.prim).filter(|_| emission) {
                add_emission(scene, &self.direct, i, si, arrival, beta, l);
            }
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
            if depth >= self.max_depth || !vis.is_none_or(|v| v.material) {
                break;
            }
            let last = depth + 1 >= self.max_depth;
            let u_select = select_sample(material, s);
            let mut bsdf = material.bsdf(si, u_select);
            if scene.spectral() {
                if let Some(b) = material.dispersion(si, u_select) {
                    let nm = match lambda {
                        Some(nm) => nm,
                        None => {
                            let (nm, w) = sample_wavelength(s.next_1d());
                            beta *= w;
                            lambda = Some(nm);
                            nm
                        }
                    };
                    bsdf.disperse(b.shift(nm));
                }
            }
            if dls && bsdf.has_non_specular() {
                let at = Scatterer::Surface { si, bsdf: &bsdf };
                sample_lights(scene, &self.direct, &at, medium, s, beta, last, depth, l);
            }
            if last && !continues_past_last(dls, bsdf.may_be_specular()) {
                break;
            }
            let (u, u2) = bsdf_samples(&bsdf, s);
            let Some(bs) = bsdf.sample_f(si.wo, u, u2) else {
                break;
            };
            if bs.pdf <= 0.0 || bs.f.is_black() || (last && !continues_past_last(dls, bs.specular))
            {
                break;
            }
            beta *= bs.f * (bs.wi.dot(bsdf.frame.n).abs() / bs.pdf);
            specular = bs.specular;
            prev_pdf = bs.pdf;
            prev = si.it;
            ray = si.it.spawn_ray(bs.wi);
            if let Some(ms) = media {
                medium = ms.after(si.prim, si.it.n, bs.wi, medium);
            }
            depth += 1;
            if !self.roulette(depth, &mut beta, s) {
                break;
            }
        }
        alpha
    }

    /// Russian roulette after a bounce to `depth`: false when the path ends; a surviving
    /// path's throughput is divided by its continuation probability.
    fn roulette(&self, depth: u32, beta: &mut Rgb, s: &mut SampleStream) -> bool {
        if depth >= RR_START {
            let q = match self.roulette {
                Roulette::None => 1.0,
                Roulette::Probability(p) => p,
                Roulette::Efficiency => beta.max_component().min(1.0),
            };
            if q < 1.0 {
                if s.next_1d() >= q {
                    return false;
                }
                *beta = *beta / q;
            }
        }
        beta.is_finite() && !beta.is_black()
    }
}
