//! The two random walks of bidirectional path tracing: the eye subpath from the camera
//! (radiance) and the light subpath from a light (importance).
//!
//! Each walk stores its vertices with their throughput and densities (see [`super::vertex`]).
//! Null-material surfaces are crossed without a vertex; an eye walk crossing an emitting null
//! surface remembers it (`crossings`), since the eye path sees its light there. Russian
//! roulette follows LuxRender: after the third vertex a subpath continues with probability
//! `min(1, max(threshold, mean(f·|cos| / pdf)))` of the last scattering, so threshold 1 turns
//! it off. Random numbers come from fixed dimensions per vertex ([`Layout`]).

use super::vertex::{to_area, Ctx, Kind, Vertex};
use crate::geometry::{Ray, SurfaceInteraction};
use crate::light::Light;
use crate::sampler::SampleStream;
use crate::spectrum::Rgb;
use glam::Vec3A;

/// Vertices after which Russian roulette may end a subpath (LuxRender's `rrStart`).
const RR_START: usize = 3;
/// Null surfaces one segment may cross.
const MAX_PASS_THROUGH: u32 = 64;

/// Which sample dimensions each vertex draws (the camera's five come first).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Light samples per eye vertex (direct lighting).
    pub direct_count: u32,
    eye_stride: u32,
    light_base: u32,
    light_stride: u32,
}

impl Layout {
    pub fn new(max_eye: u32, max_light: u32, direct_count: u32) -> Layout {
        let eye_stride = 5 + 4 * direct_count;
        Layout {
            direct_count,
            eye_stride,
            light_base: 5 + max_eye.saturating_sub(1) * eye_stride,
            light_stride: 6 + max_light.saturating_sub(1) * 5,
        }
    }

    /// First dimension of eye vertex `i` (1 = the first hit): component, lobe, direction
    /// (2D), roulette, then per light sample: choice, position (2D), mesh triangle.
    pub fn eye(&self, i: usize) -> u32 {
        5 + (i as u32).saturating_sub(1) * self.eye_stride
    }

    /// First dimension of light sample `d` at eye vertex `i`.
    pub fn direct(&self, i: usize, d: u32) -> u32 {
        self.eye(i) + 5 + 4 * d
    }

    /// First dimension of light subpath `p`: choice, position (2D), direction (2D), mesh
    /// triangle.
    pub fn light_origin(&self, p: u32) -> u32 {
        self.light_base + p * self.light_stride
    }

    /// First dimension of vertex `i` >= 1 of light subpath `p`: component, lobe, direction
    /// (2D), roulette.
    pub fn light_vertex(&self, p: u32, i: usize) -> u32 {
        self.light_origin(p) + 6 + (i as u32).saturating_sub(1) * 5
    }

    /// Dimensions a sample uses with `paths` light subpaths.
    pub fn total(&self, paths: u32) -> u32 {
        self.light_base + paths * self.light_stride
    }
}

/// The closest hit that is not a null surface; emitting null surfaces crossed on the way
/// are reported to `crossed`.
fn trace(
    ctx: &Ctx,
    mut ray: Ray,
    mut crossed: impl FnMut(&SurfaceInteraction, u32),
) -> Option<SurfaceInteraction> {
    for _ in 0..MAX_PASS_THROUGH {
        let si = ctx.world.intersect(&ray)?;
        if !ctx.world.material(si.prim).is_null() {
            return Some(si);
        }
        if let Some((i, _)) = ctx.world.area_light(si.prim) {
            crossed(&si, i as u32);
        }
        ray = si.it.spawn_ray(ray.d);
    }
    None
}

fn roulette(n: usize, threshold: f32, weight: Rgb, u: f32) -> Option<f32> {
    if n <= RR_START {
        return Some(1.0);
    }
    let q = weight.average().max(threshold).min(1.0);
    (q > 0.0 && u < q).then_some(q)
}

/// A surface vertex for hit `si` reached with throughput `beta` from `prev` by a direction
/// of solid-angle density `pdf_dir` (or, after a light at infinity, the disc's density).
fn surface(ctx: &Ctx, si: SurfaceInteraction, beta: Rgb, prev: &Vertex, pdf_dir: f32) -> Vertex {
    let emitter = ctx.world.area_light(si.prim).map(|(i, _)| i as u32);
    let mut v = Vertex::new(Kind::Surface { emitter }, si, beta, 0.0);
    v.pdf_fwd = if prev.is_at_infinity() {
        pdf_dir * si.it.n.dot(prev.dir).abs()
    } else {
        to_area(pdf_dir, prev, &v)
    };
    v
}

/// Traces the eye subpath of camera ray `ray` leaving lens point `lens` into `path`;
/// returns the sample's alpha (0 when the camera ray leaves the scene).
pub fn eye_walk(
    ctx: &Ctx,
    ray: Ray,
    lens: Vec3A,
    s: &mut SampleStream,
    layout: &Layout,
    path: &mut Vec<Vertex>,
    crossings: &mut Vec<(usize, Vertex)>,
) -> f32 {
    path.clear();
    crossings.clear();
    let bidir = ctx.bidir;
    let mut cam = Vertex::new(Kind::Camera, SurfaceInteraction::default(), Rgb::WHITE, 1.0);
    cam.si.it.p = lens;
    cam.si.it.time = ray.time;
    path.push(cam);
    let max = bidir.eye_depth as usize;
    let mut alpha = 1.0;
    let mut ray = ray;
    let mut beta = Rgb::WHITE;
    let mut pdf_dir = ctx.camera.dir_pdf(ray.d.normalize_or_zero(), ray.time);
    while path.len() < max {
        let Some(prev) = path.last().cloned() else {
            break;
        };
        let n = path.len();
        let hit = trace(ctx, ray, |si, light| {
            let mut v = Vertex::new(
                Kind::Surface {
                    emitter: Some(light),
                },
                *si,
                beta,
                0.0,
            );
            v.pdf_fwd = to_area(pdf_dir, &prev, &v);
            crossings.push((n, v));
        });
        let Some(si) = hit else {
            if n == 1 {
                alpha = 0.0;
            }
            if !ctx.world.infinite_lights().is_empty() {
                let dir = ray.d.normalize_or_zero();
                path.push(Vertex::at_infinity(Kind::Sky, dir, beta, pdf_dir));
            }
            break;
        };
        let mut v = surface(ctx, si, beta, &prev, pdf_dir);
        s.set_dimension(layout.eye(n));
        v.bsdf = Some(ctx.world.material(si.prim).bsdf(&si, s.next_1d()));
        path.push(v);
        if path.len() >= max {
            break;
        }
        let (u, u2, u_rr) = (s.next_1d(), s.next_2d(), s.next_1d());
        let Some(bsdf) = path.last().and_then(|v| v.bsdf.as_ref()) else {
            break;
        };
        let Some(bs) = bsdf.sample_f(si.wo, u, u2) else {
            break;
        };
        if bs.pdf <= 0.0 || bs.f.is_black() {
            break;
        }
        let weight = bs.f * (bs.wi.dot(bsdf.frame.n).abs() / bs.pdf);
        let mut pdf_rev = bsdf.pdf(bs.wi, si.wo);
        pdf_dir = bs.pdf;
        if bs.specular {
            pdf_dir = 0.0;
            pdf_rev = 0.0;
        }
        let Some(q) = roulette(n + 1, bidir.eye_rr, weight, u_rr) else {
            break;
        };
        beta = beta * weight / q;
        let cur = n;
        if let Some(last) = path.get_mut(cur) {
            last.delta = bs.specular;
        }
        if let (Some(p), Some(here)) = (cur.checked_sub(1), path.get(cur)) {
            let r = to_area(pdf_rev, here, &path[p]);
            path[p].pdf_rev = r;
        }
        if !beta.is_finite() || beta.is_black() {
            break;
        }
        ray = si.it.spawn_ray(bs.wi);
    }
    alpha
}

/// The first vertex of a light subpath from light `index` (chosen with `draws` expected
/// subpaths per sample) and the throughput and direction density its first hit starts with.
fn light_origin(
    ctx: &Ctx,
    index: u32,
    draws: f32,
    s: &mut SampleStream,
    base: u32,
) -> Option<(Vertex, Ray, Rgb, f32)> {
    let light = ctx.light(index)?;
    s.set_dimension(base + 1);
    let (u_pos, u_dir, u_pick) = (s.next_2d(), s.next_2d(), s.next_1d());
    let sphere = ctx.world.bounding_sphere();
    let lr = light.sample_le(u_pos, u_dir, u_pick, ctx.time, ctx.world, sphere)?;
    let d = lr.ray.d;
    let (kind, cos) = match light {
        Light::Area(_) => (Kind::LightPoint(index), lr.n.dot(d).abs()),
        Light::Point(_) | Light::Spot(_) => (Kind::LightPoint(index), 1.0),
        _ if light.is_delta_direction() => (Kind::LightDir(index), 1.0),
        _ => (Kind::Sky, 1.0),
    };
    let mut v = if matches!(kind, Kind::LightPoint(_)) {
        let mut si = SurfaceInteraction::default();
        si.it.p = lr.ray.o;
        si.it.n = lr.n;
        si.it.time = ctx.time;
        Vertex::new(kind, si, lr.le, 0.0)
    } else {
        Vertex::at_infinity(kind, -d, lr.le, 0.0)
    };
    v.pdf_fwd = ctx.origin_density(&v);
    let beta = lr.le * (cos / (draws * lr.pdf_pos * lr.pdf_dir));
    let pdf_next = if v.is_at_infinity() {
        lr.pdf_pos
    } else {
        lr.pdf_dir
    };
    Some((v, lr.ray, beta, pdf_next))
}

/// Traces light subpath `p` from light `index` (drawn `draws` times per sample on average)
/// into `path`.
pub fn light_walk(
    ctx: &Ctx,
    index: u32,
    draws: f32,
    p: u32,
    s: &mut SampleStream,
    layout: &Layout,
    path: &mut Vec<Vertex>,
) {
    path.clear();
    let bidir = ctx.bidir;
    let max = bidir.light_depth as usize;
    if max == 0 || draws <= 0.0 {
        return;
    }
    let Some((origin, mut ray, mut beta, mut pdf_dir)) =
        light_origin(ctx, index, draws, s, layout.light_origin(p))
    else {
        return;
    };
    path.push(origin);
    while path.len() < max {
        if !beta.is_finite() || beta.is_black() {
            break;
        }
        let n = path.len();
        let Some(si) = trace(ctx, ray, |_, _| {}) else {
            break;
        };
        if n == 1 {
            let falloff = ctx.light(index).map_or(1.0, |l| {
                l.falloff_correction((si.it.p - path[n - 1].p()).length_squared())
            });
            beta *= falloff;
        }
        let mut v = surface(ctx, si, beta, &path[n - 1], pdf_dir);
        s.set_dimension(layout.light_vertex(p, n));
        v.bsdf = Some(ctx.world.material(si.prim).bsdf(&si, s.next_1d()));
        path.push(v);
        if path.len() >= max {
            break;
        }
        let (u, u2, u_rr) = (s.next_1d(), s.next_2d(), s.next_1d());
        let Some(bsdf) = path.last().and_then(|v| v.bsdf.as_ref()) else {
            break;
        };
        let wo = si.wo;
        let Some(bs) = bsdf.sample_f(wo, u, u2) else {
            break;
        };
        let cos_o_g = wo.dot(si.it.n).abs();
        if bs.pdf <= 0.0 || bs.f.is_black() || cos_o_g == 0.0 {
            break;
        }
        // Importance: the adjoint BSDF, and the shading-normal correction
        // |wo·ns| |wi·ng| / (|wo·ng| |wi·ns|) times the |wi·ns| of the sample.
        let weight = bs.f
            * (bsdf.adjoint_scale(wo, bs.wi)
                * wo.dot(bsdf.frame.n).abs()
                * bs.wi.dot(si.it.n).abs()
                / (cos_o_g * bs.pdf));
        let mut pdf_rev = bsdf.pdf(bs.wi, wo);
        pdf_dir = bs.pdf;
        if bs.specular {
            pdf_dir = 0.0;
            pdf_rev = 0.0;
        }
        let Some(q) = roulette(n + 1, bidir.light_rr, weight, u_rr) else {
            break;
        };
        beta = beta * weight / q;
        path[n].delta = bs.specular;
        let r = to_area(pdf_rev, &path[n], &path[n - 1]);
        path[n - 1].pdf_rev = r;
        ray = si.it.spawn_ray(bs.wi);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_blocks_do_not_overlap() {
        let l = Layout::new(8, 6, 2);
        assert_eq!(l.eye(1), 5);
        assert_eq!(l.direct(1, 0), 10);
        assert_eq!(l.direct(1, 1) + 4, l.eye(2));
        assert_eq!(l.eye(7) + 13, l.light_origin(0));
        assert_eq!(l.light_vertex(0, 1), l.light_origin(0) + 6);
        assert_eq!(l.light_vertex(0, 5) + 5, l.light_origin(1));
        assert_eq!(l.total(2), l.light_origin(2));
    }
}
