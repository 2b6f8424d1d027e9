//! Next-event estimation shared by both integrators: shadow-ray samples of the lights with
//! the selected strategy, the matching MIS weight for BSDF-sampled hits on a light, and the
//! emission a ray picks up where it meets an emitter ([`add_emission`]: an area light's
//! surface, or a crossing of an area primitive, which rays pass through).
//!
//! Light is scattered toward the path at a surface (its BSDF) or at a point of a participating
//! medium (its phase function), [`Scatterer`]; in a scene with media, shadow rays carry the
//! transmittance of the media they cross ([`World::transmittance`], which walks the segment
//! through null surfaces and medium boundaries with [`World::walk_segment`], the walk that
//! bidirectional connections use too).
//!
//! `depth` is the number of bounces before a shading point (0 at the camera ray's hit): a
//! light's shadow-ray count may drop from a depth on (`lownsamples` at `lowlevel`).

use super::{add_group, DirectSettings};
use crate::geometry::{Interaction, Ray, SurfaceInteraction};
use crate::light::LightSelector;
use crate::material::Bsdf;
use crate::sampler::SampleStream;
use crate::sampling::power_heuristic;
use crate::scene::World;
use crate::spectrum::Rgb;
use crate::volume::{HenyeyGreenstein, MediaSet, Medium, MediumId};
use glam::Vec3A;

/// Expected number of shadow-ray draws on light `i` per estimate at a shading point `depth`
/// bounces down the path (n_i in the integrators' module docs).
pub fn light_draws(scene: &World, settings: &DirectSettings, i: usize, depth: u32) -> f32 {
    let n = settings.shadow_rays as f32;
    match scene.selector() {
        LightSelector::All => {
            scene
                .lights()
                .get(i)
                .map_or(0.0, |l| l.nsamples_at(depth) as f32)
                * n
        }
        sel => n * sel.pdf(i),
    }
}

/// MIS weight of a BSDF-sampled direction (density `pdf_bsdf`) from a shading point at
/// `depth` that reached light `i`, whose own sampling density for it is `pdf_light`.
pub fn bsdf_hit_weight(
    scene: &World,
    settings: &DirectSettings,
    i: usize,
    pdf_bsdf: f32,
    pdf_light: f32,
    depth: u32,
) -> f32 {
    power_heuristic(pdf_bsdf, light_draws(scene, settings, i, depth) * pdf_light)
}

/// How a ray reached an emitter: it decides the MIS weight and whether illumination falls
/// off with distance.
#[derive(Clone, Copy, Debug)]
pub enum Arrival<'a> {
    /// A camera ray (through pass-through surfaces only): full weight, no distance falloff,
    /// and lights that are not `visible` are not seen.
    Camera,
    /// From this shading point after a specular bounce, or with light sampling off there:
    /// full weight.
    Unweighted(&'a Interaction),
    /// A BSDF sample with this solid-angle density from a shading point at this depth:
    /// weighted against light sampling.
    Bsdf(&'a Interaction, f32, u32),
}

/// Adds `beta ×` the emission of medium `m` along [0, `t_max`] of `ray` (seen through the
/// medium: [`Medium::emission`]) to the first light group, where LuxRender 1.x puts its
/// volume integrator's emission (the group current at the VolumeIntegrator statement, before
/// any LightGroup). Free for media that do not emit: one flag is checked.
pub fn add_medium_emission(m: &Medium, ray: &Ray, t_max: f32, beta: Rgb, l: &mut [Rgb]) {
    if !m.emits() {
        return;
    }
    let e = beta * m.emission(ray, t_max);
    if let Some(g) = l.first_mut().filter(|_| e.is_finite()) {
        *g += e;
    }
}

/// Adds `beta ×` the emission of light `i` at `si` (a point of its surface or a crossing),
/// toward `si.wo`, to the light groups in `l`.
#[allow(clippy::too_many_arguments)]
pub fn add_emission(
    scene: &World,
    settings: &DirectSettings,
    i: usize,
    si: &SurfaceInteraction,
    arrival: Arrival,
    beta: Rgb,
    l: &mut [Rgb],
) {
    let Some(light) = scene.lights().get(i) else {
        return;
    };
    let from = match arrival {
        Arrival::Camera if !light.visible() => return,
        Arrival::Camera => None,
        Arrival::Unweighted(p) | Arrival::Bsdf(p, _, _) => Some(p),
    };
    let le = light.le_at(si, from.map(|p| (si.it.p - p.p).length_squared()));
    if le.is_black() {
        return;
    }
    let w = match arrival {
        Arrival::Bsdf(p, pdf, depth) => {
            let pl = light.pdf_li(p, -si.wo, Some(si));
            bsdf_hit_weight(scene, settings, i, pdf, pl, depth)
        }
        _ => 1.0,
    };
    add_group(l, light.group(), beta * le * w);
}

/// Where light is scattered toward the path: a surface point with its BSDF, or a point in a
/// medium with its phase function.
#[derive(Clone, Copy)]
pub enum Scatterer<'a> {
    Surface {
        si: &'a SurfaceInteraction,
        bsdf: &'a Bsdf,
    },
    Medium {
        it: &'a Interaction,
        /// The path's propagation direction arriving at the point.
        d_in: Vec3A,
        phase: HenyeyGreenstein,
    },
}

impl Scatterer<'_> {
    fn it(&self) -> &Interaction {
        match self {
            Scatterer::Surface { si, .. } => &si.it,
            Scatterer::Medium { it, .. } => it,
        }
    }

    /// f·|cos| (the phase value in a medium) toward the light direction `wi`, and the density
    /// with which the path would have sampled `wi`.
    fn f_pdf(&self, wi: Vec3A) -> (Rgb, f32) {
        match self {
            Scatterer::Surface { si, bsdf } => {
                let (f, pdf) = bsdf.f_pdf(si.wo, wi);
                (f * wi.dot(bsdf.frame.n).abs(), pdf)
            }
            Scatterer::Medium { d_in, phase, .. } => {
                let p = phase.eval(*d_in, wi);
                (Rgb::splat(p), p)
            }
        }
    }

    /// The medium a shadow ray toward `wi` starts in, the path being in `medium`.
    fn medium_toward(
        &self,
        media: &MediaSet,
        wi: Vec3A,
        medium: Option<MediumId>,
    ) -> Option<MediumId> {
        match self {
            Scatterer::Surface { si, .. } => media.after(si.prim, si.it.n, wi, medium),
            Scatterer::Medium { .. } => medium,
        }
    }
}

/// One shadow-ray sample of light `i`: f·L·Tr·w/p (not yet divided by the number of draws).
/// `full_weight` gives light samples the whole weight (no BSDF sample will follow); `medium`
/// is the medium the path is in (always `None` in a scene without media).
#[allow(clippy::too_many_arguments)]
fn sample_one(
    scene: &World,
    settings: &DirectSettings,
    i: usize,
    at: &Scatterer,
    medium: Option<MediumId>,
    s: &mut SampleStream,
    full_weight: bool,
    depth: u32,
) -> Rgb {
    let u = s.next_2d();
    let Some(light) = scene.lights().get(i) else {
        return Rgb::BLACK;
    };
    // Drawn only when some light reads it: an unread dimension costs a sampler evaluation.
    let u_pick = if scene.lights_read_pick() {
        s.next_1d()
    } else {
        0.5
    };
    let Some(ls) = light.sample_li(at.it(), u, u_pick, scene) else {
        return Rgb::BLACK;
    };
    let (f, pdf_bsdf) = at.f_pdf(ls.wi);
    if f.is_black() {
        return Rgb::BLACK;
    }
    let f = match scene.media() {
        None if scene.unoccluded(at.it(), &ls) => f,
        None => return Rgb::BLACK,
        Some(media) => {
            let start = at.medium_toward(media, ls.wi, medium);
            let tr = scene.transmittance(at.it(), &ls, start);
            if tr.is_black() {
                return Rgb::BLACK;
            }
            f * tr
        }
    };
    let w = if ls.delta || full_weight {
        1.0
    } else {
        let eff = light_draws(scene, settings, i, depth);
        power_heuristic(eff * ls.pdf, pdf_bsdf)
    };
    f * ls.li * (w / ls.pdf)
}

/// Adds `beta ×` the light-sampled direct lighting at `at` (a scattering point `depth`
/// bounces down the path, in `medium`) to the light groups in `l`.
#[allow(clippy::too_many_arguments)]
pub fn sample_lights(
    scene: &World,
    settings: &DirectSettings,
    at: &Scatterer,
    medium: Option<MediumId>,
    s: &mut SampleStream,
    beta: Rgb,
    full_weight: bool,
    depth: u32,
    l: &mut [Rgb],
) {
    match scene.selector() {
        LightSelector::All => {
            for (i, light) in scene.lights().iter().enumerate() {
                let n = light.nsamples_at(depth) * settings.shadow_rays;
                let mut sum = Rgb::BLACK;
                for _ in 0..n {
                    sum += sample_one(scene, settings, i, at, medium, s, full_weight, depth);
                }
                add_group(l, light.group(), beta * sum / n as f32);
            }
        }
        sel => {
            let n = settings.shadow_rays;
            let picks = sel.count(scene.lights().len());
            for _ in 0..n {
                for k in 0..picks {
                    let Some((i, q)) = sel.pick(k, s.next_1d()) else {
                        continue;
                    };
                    if i >= scene.lights().len() {
                        continue;
                    }
                    let c = sample_one(scene, settings, i, at, medium, s, full_weight, depth);
                    let g = scene.lights()[i].group();
                    add_group(l, g, beta * c / (n as f32 * q));
                }
            }
        }
    }
}

/// Radiance from the infinite lights along an escaped ray, each weighted by `weight(i)`.
pub fn escaped(scene: &World, ray: &Ray, beta: Rgb, l: &mut [Rgb], weight: impl Fn(usize) -> f32) {
    let dir = ray.d.normalize_or_zero();
    for &i in scene.infinite_lights() {
        let light = &scene.lights()[i];
        let le = light.le(dir, ray.time);
        if !le.is_black() {
            add_group(l, light.group(), beta * le * weight(i));
        }
    }
}
