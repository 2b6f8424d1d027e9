//! Next-event estimation shared by both integrators: shadow-ray samples of the lights with
//! the selected strategy, and the matching MIS weight for BSDF-sampled hits on a light.

use super::{add_group, DirectSettings};
use crate::geometry::{Ray, SurfaceInteraction};
use crate::light::LightSelector;
use crate::material::Bsdf;
use crate::sampler::SampleStream;
use crate::sampling::power_heuristic;
use crate::scene::World;
use crate::spectrum::Rgb;

/// Expected number of shadow-ray draws on light `i` per estimate (n_i in the module docs).
pub fn light_draws(scene: &World, settings: &DirectSettings, i: usize) -> f32 {
    let n = settings.shadow_rays as f32;
    match scene.selector() {
        LightSelector::All => scene.lights().get(i).map_or(0.0, |l| l.nsamples() as f32) * n,
        LightSelector::One(d) => n * d.discrete_pdf(i),
    }
}

/// MIS weight of a BSDF-sampled direction (density `pdf_bsdf`) that reached light `i`, whose
/// own sampling density for that direction is `pdf_light`.
pub fn bsdf_hit_weight(
    scene: &World,
    settings: &DirectSettings,
    i: usize,
    pdf_bsdf: f32,
    pdf_light: f32,
) -> f32 {
    power_heuristic(pdf_bsdf, light_draws(scene, settings, i) * pdf_light)
}

/// One shadow-ray sample of light `i`: f·L·w/p (not yet divided by the number of draws).
/// `full_weight` gives light samples the whole weight (no BSDF sample will follow).
#[allow(clippy::too_many_arguments)]
fn sample_one(
    scene: &World,
    settings: &DirectSettings,
    i: usize,
    si: &SurfaceInteraction,
    bsdf: &Bsdf,
    s: &mut SampleStream,
    full_weight: bool,
) -> Rgb {
    let u = s.next_2d();
    let u_pick = s.next_1d();
    let Some(light) = scene.lights().get(i) else {
        return Rgb::BLACK;
    };
    let Some(ls) = light.sample_li(&si.it, u, u_pick, scene) else {
        return Rgb::BLACK;
    };
    let (f, pdf_bsdf) = bsdf.f_pdf(si.wo, ls.wi);
    let f = f * ls.wi.dot(bsdf.frame.n).abs();
    if f.is_black() || !scene.unoccluded(&si.it, &ls) {
        return Rgb::BLACK;
    }
    let w = if ls.delta || full_weight {
        1.0
    } else {
        let eff = light_draws(scene, settings, i);
        power_heuristic(eff * ls.pdf, pdf_bsdf)
    };
    f * ls.li * (w / ls.pdf)
}

/// Adds `beta ×` the light-sampled direct lighting at `si` to the light groups in `l`.
#[allow(clippy::too_many_arguments)]
pub fn sample_lights(
    scene: &World,
    settings: &DirectSettings,
    si: &SurfaceInteraction,
    bsdf: &Bsdf,
    s: &mut SampleStream,
    beta: Rgb,
    full_weight: bool,
    l: &mut [Rgb],
) {
    match scene.selector() {
        LightSelector::All => {
            for (i, light) in scene.lights().iter().enumerate() {
                let n = light.nsamples() * settings.shadow_rays;
                let mut sum = Rgb::BLACK;
                for _ in 0..n {
                    sum += sample_one(scene, settings, i, si, bsdf, s, full_weight);
                }
                add_group(l, light.group(), beta * sum / n as f32);
            }
        }
        LightSelector::One(d) => {
            let n = settings.shadow_rays;
            for _ in 0..n {
                let (i, q, _) = d.sample_discrete(s.next_1d());
                if q <= 0.0 || i >= scene.lights().len() {
                    continue;
                }
                let c = sample_one(scene, settings, i, si, bsdf, s, full_weight);
                let g = scene.lights()[i].group();
                add_group(l, g, beta * c / (n as f32 * q));
            }
        }
    }
}

/// Radiance from the infinite lights along an escaped ray, each weighted by `weight(i)`.
pub fn escaped(scene: &World, ray: &Ray, beta: Rgb, l: &mut [Rgb], weight: impl Fn(usize) -> f32) {
    let dir = ray.d.normalize_or_zero();
    for &i in scene.infinite_lights() {
        let light = &scene.lights()[i];
        let le = light.le(dir);
        if !le.is_black() {
            add_group(l, light.group(), beta * le * weight(i));
        }
    }
}
