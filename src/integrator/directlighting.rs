//! The `directlighting` integrator: emission plus direct lighting (light samples and one BSDF
//! sample, combined with MIS) at the first hit, and recursion along perfectly specular
//! reflection/refraction up to `maxdepth` (5) times.

use super::direct::{add_emission, bsdf_hit_weight, escaped, sample_lights, Arrival, Scatterer};
use super::DirectSettings;
use crate::geometry::{Interaction, Ray, SurfaceInteraction};
use crate::material::Bsdf;
use crate::plugin::Stmt;
use crate::sampler::SampleStream;
use crate::scene::World;
use crate::spectrum::Rgb;

const MAX_PASS_THROUGH: u32 = 64;

#[derive(Clone, Debug)]
pub struct DirectLightingIntegrator {
    pub max_depth: u32,
    pub direct: DirectSettings,
}

impl DirectLightingIntegrator {
    /// Reads a `directlighting` statement.
    pub fn build(s: &mut Stmt) -> Self {
        DirectLightingIntegrator {
            max_depth: s.params().int_or("maxdepth", 5).max(0) as u32,
            direct: DirectSettings::build(s),
        }
    }

    pub fn li(&self, scene: &World, mut ray: Ray, s: &mut SampleStream, l: &mut [Rgb]) -> f32 {
        let mut beta = Rgb::WHITE;
        let mut alpha = 1.0;
        let mut depth = 0;
        let mut pass = 0;
        // The last specular vertex (the camera ray has none).
        let mut prev = Interaction::default();
        loop {
            // Matched by reference: moving the hit out of the Option would copy it.
            let hit = scene.intersect(&ray);
            let arrival = if depth == 0 {
                Arrival::Camera
            } else {
                Arrival::Unweighted(&prev)
            };
            let t_hit = hit.as_ref().map_or(f32::INFINITY, |h| h.t);
            scene.crossed_lights(&ray, t_hit, |i, c| {
                add_emission(scene, &self.direct, i, c, arrival, beta, l)
            });
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
                ray = si.it.spawn_ray(ray.d);
                continue;
            }
            pass = 0;
            let bsdf = material.bsdf(si, s.next_1d());
            if bsdf.has_non_specular() {
                let at = Scatterer::Surface { si, bsdf: &bsdf };
                sample_lights(scene, &self.direct, &at, None, s, beta, false, depth, l);
                self.bsdf_sample(scene, si, &bsdf, s, beta, depth, l);
            }
            if depth >= self.max_depth {
                break;
            }
            let (u, u2) = (s.next_1d(), s.next_2d());
            match bsdf.sample_f(si.wo, u, u2) {
                Some(bs) if bs.specular && bs.pdf > 0.0 => {
                    beta *= bs.f * (bs.wi.dot(bsdf.frame.n).abs() / bs.pdf);
                    prev = si.it;
                    ray = si.it.spawn_ray(bs.wi);
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

    /// The BSDF-sampling half of the direct-lighting MIS estimate at a shading point `depth`
    /// specular bounces from the camera.
    #[allow(clippy::too_many_arguments)]
    fn bsdf_sample(
        &self,
        scene: &World,
        si: &SurfaceInteraction,
        bsdf: &Bsdf,
        s: &mut SampleStream,
        beta: Rgb,
        depth: u32,
        l: &mut [Rgb],
    ) {
        let (u, u2) = (s.next_1d(), s.next_2d());
        let Some(bs) = bsdf.sample_f(si.wo, u, u2) else {
            return;
        };
        if bs.specular || bs.pdf <= 0.0 || bs.f.is_black() {
            return;
        }
        let tp = beta * bs.f * (bs.wi.dot(bsdf.frame.n).abs() / bs.pdf);
        let ray = si.it.spawn_ray(bs.wi);
        let hit = scene.intersect(&ray);
        let arrival = Arrival::Bsdf(&si.it, bs.pdf, depth);
        let t_hit = hit.as_ref().map_or(f32::INFINITY, |h| h.t);
        scene.crossed_lights(&ray, t_hit, |i, c| {
            add_emission(scene, &self.direct, i, c, arrival, tp, l)
        });
        match &hit {
            Some(hit) => {
                if let Some((i, _)) = scene.area_light(hit.prim) {
                    add_emission(scene, &self.direct, i, hit, arrival, tp, l);
                }
            }
            None => escaped(scene, &ray, tp, l, |i| {
                let pl = scene.lights()[i].pdf_li(&si.it, bs.wi, None);
                bsdf_hit_weight(scene, &self.direct, i, bs.pdf, pl, depth)
            }),
        }
    }
}
