//! The connection strategies of bidirectional path tracing and their weights.
//!
//! With an eye subpath E₀ (camera) … and a light subpath L₀ (light) …, a strategy (s, t)
//! uses the first s light vertices and the first t eye vertices:
//! - s = 0: the eye path met a light (an emitting surface, or the sky when it escaped);
//! - s = 1: direct lighting: a light sampled from eye vertex E_{t−1};
//! - s ≥ 2, t ≥ 2: L_{s−1} joined to E_{t−1} by a shadow ray;
//! - s ≥ 2, t = 1: L_{s−1} joined to the camera: a splat at another film position.
//!
//! [`weight`] (in `weight.rs`) gathers the path's densities into [`PathDensities`] — the
//! stored walk densities, recomputed near the connection — and returns the power-heuristic
//! weight.
//!
//! In a scene with media, connections (shadow rays, and the joins of s ≥ 2) carry the
//! transmittance of the media between their two ends, walked through null surfaces and
//! medium boundaries by [`Ctx::segment`]; the connection's distance-sampling factors go
//! into the recomputed densities. A medium vertex scatters with its phase function (no
//! cosine), on either side of a connection.

use super::mis::PathDensities;
use super::vertex::{Ctx, Kind, Vertex};
use super::weight::area_of;
pub use super::weight::{weight, Link};
use crate::integrator::{SampleOut, Splat};
use crate::light::Light;
use crate::sampler::SampleStream;
use crate::spectrum::Rgb;
use glam::Vec2;

/// Adds an eye-buffer contribution `c` (already weighted by `w`) to light group `g`.
pub(super) fn add_eye(out: &mut SampleOut, g: usize, c: Rgb, w: f32) {
    if !c.is_finite() || c.is_black() {
        return;
    }
    if let Some(slot) = out.l.get_mut(g) {
        *slot += c;
    }
    if let Some(v) = out.weight_lum.get_mut(g) {
        *v += w * crate::spectrum::rgb_to_xyz(c)[1];
    }
}

/// s = 0: eye vertex E_{t−1} is on a light.
pub fn emission(
    ctx: &Ctx,
    dens: &mut PathDensities,
    eye: &[Vertex],
    t: usize,
    out: &mut SampleOut,
) {
    let Some(v) = eye.get(t - 1) else {
        return;
    };
    match v.kind {
        Kind::Sky => {
            let lights = ctx.world.lights();
            let mut w = None;
            for &i in ctx.world.infinite_lights() {
                let Some(l) = lights.get(i) else {
                    continue;
                };
                let le = l.le(v.dir, ctx.time);
                if le.is_black() {
                    continue;
                }
                let w =
                    *w.get_or_insert_with(|| weight(ctx, dens, eye, t, &[], 0, None, Link::NONE));
                add_eye(out, l.group(), v.beta * le * w, w);
            }
        }
        Kind::Surface { emitter: Some(_) } => {
            let Some((_, area)) = ctx.world.area_light(v.si.prim) else {
                return;
            };
            let le = area.le(&v.si, v.si.wo, None);
            if le.is_black() {
                return;
            }
            let w = weight(ctx, dens, eye, t, &[], 0, None, Link::NONE);
            add_eye(out, area.common.group, v.beta * le * w, w);
        }
        _ => {}
    }
}

/// s = 0 for an emitting null surface the eye path crossed after `n` vertices.
pub fn crossing(
    ctx: &Ctx,
    dens: &mut PathDensities,
    eye: &mut Vec<Vertex>,
    n: usize,
    v: &Vertex,
    out: &mut SampleOut,
) {
    if n > eye.len() || n + 1 > ctx.bidir.eye_depth as usize {
        return;
    }
    let rest: Vec<Vertex> = eye.drain(n..).collect();
    eye.push(v.clone());
    emission(ctx, dens, eye, n + 1, out);
    eye.pop();
    eye.extend(rest);
}

/// s = 1: direct lighting at eye vertex E_{t−1} with the light samples of its dimensions.
pub fn direct(
    ctx: &Ctx,
    dens: &mut PathDensities,
    eye: &[Vertex],
    t: usize,
    stream: &mut SampleStream,
    out: &mut SampleOut,
) {
    let Some(v) = eye.get(t - 1).filter(|v| v.connectable()) else {
        return;
    };
    let layout = &ctx.bidir.layout;
    let lights = ctx.world.lights();
    for d in 0..layout.direct_count {
        stream.set_dimension(layout.direct(t - 1, d));
        let (u_pick, u, u_shape) = (stream.next_1d(), stream.next_2d(), stream.next_1d());
        let Some((i, q)) = ctx.world.selector().pick(d, u_pick) else {
            continue;
        };
        let Some(light) = lights.get(i) else {
            continue;
        };
        if q <= 0.0 {
            continue;
        }
        let Some(ls) = light.sample_li(&v.si.it, u, u_shape, ctx.world) else {
            continue;
        };
        let f = v.f_eye(ls.wi);
        if f.is_black() {
            continue;
        }
        let sampled = sampled_light(i as u32, light, &ls);
        let Some(g) = ctx.segment(v, &sampled).filter(|g| !g.tr.is_black()) else {
            continue;
        };
        let link = Link {
            to_eye: g.b_to_a,
            to_light: g.a_to_b,
        };
        let w = weight(ctx, dens, eye, t, &[], 1, Some(&sampled), link);
        let c = v.beta * f * g.tr * ls.li * (w / (ls.pdf * q));
        add_eye(out, light.group(), c, w);
    }
}

/// The light vertex a direct-lighting sample stands for.
fn sampled_light(i: u32, light: &Light, ls: &crate::light::LightSample) -> Vertex {
    if ls.infinite {
        let kind = if light.is_delta_direction() {
            Kind::LightDir(i)
        } else {
            Kind::Sky
        };
        return Vertex::at_infinity(kind, ls.wi, Rgb::WHITE, 0.0);
    }
    let si = crate::geometry::SurfaceInteraction {
        it: ls.p_light,
        ..Default::default()
    };
    Vertex::new(Kind::LightPoint(i), si, Rgb::WHITE, 0.0)
}

/// The light that started a light subpath, for its group.
fn group_of(ctx: &Ctx, index: u32) -> usize {
    ctx.light(index).map_or(0, Light::group)
}

/// s ≥ 2, t ≥ 2: joins light vertex L_{s−1} to eye vertex E_{t−1}.
#[allow(clippy::too_many_arguments)]
pub fn connect(
    ctx: &Ctx,
    dens: &mut PathDensities,
    eye: &[Vertex],
    t: usize,
    light: &[Vertex],
    s: usize,
    index: u32,
    out: &mut SampleOut,
) {
    let (Some(e), Some(l)) = (eye.get(t - 1), light.get(s - 1)) else {
        return;
    };
    if !(e.connectable() && l.connectable()) {
        return;
    }
    let d = l.p() - e.p();
    let d2 = d.length_squared();
    if d2 == 0.0 {
        return;
    }
    let w_el = d / d2.sqrt();
    let fe = e.f_eye(w_el);
    if fe.is_black() {
        return;
    }
    let fl = f_light(l, -w_el);
    if fl.is_black() {
        return;
    }
    let c = e.beta * fe * fl * l.beta * (1.0 / d2);
    if c.is_black() || !c.is_finite() {
        return;
    }
    let Some(g) = ctx.segment(e, l).filter(|g| !g.tr.is_black()) else {
        return;
    };
    let c = c * g.tr;
    let link = Link {
        to_eye: g.b_to_a,
        to_light: g.a_to_b,
    };
    let w = weight(ctx, dens, eye, t, light, s, None, link);
    add_eye(out, group_of(ctx, index), c * w, w);
}

/// The light side's value of light vertex `l` scattering the light that reached it toward
/// unit direction `w`: the adjoint BSDF with its shading-normal factor at a surface, the
/// phase function at a medium point.
fn f_light(l: &Vertex, w: glam::Vec3A) -> Rgb {
    if let Some(ph) = l.phase {
        return Rgb::splat(ph.eval(-l.si.wo, w));
    }
    match &l.bsdf {
        Some(b) => b.f(w, l.si.wo) * shading_correction(l, w),
        None => Rgb::BLACK,
    }
}

/// At light vertex `l` scattering toward `w` (unit): the adjoint's shading-normal factor
/// |wo·ns| |w·ng| / |wo·ng|, which also holds the |cos| of the connection at `l`; ns is
/// the normal of the BSDF's shading frame (bump mapping included), as the walks use.
fn shading_correction(l: &Vertex, w: glam::Vec3A) -> f32 {
    let Some(ns) = l.bsdf.as_ref().map(|b| b.frame.n) else {
        return 0.0;
    };
    let (ng, wo) = (l.si.it.n, l.si.wo);
    let c = wo.dot(ng).abs();
    if c == 0.0 {
        return 0.0;
    }
    wo.dot(ns).abs() * w.dot(ng).abs() / c
}

/// s = t = 1: the light subpath's origin L₀ on an area light joined to the camera, as
/// LuxRender's bidirectional joins it (so a light tracer, `eyedepth` 1, sees emitters too);
/// a splat. Weighted against s = 0 (the eye ray meeting the emitter).
pub fn origin_to_camera(
    ctx: &Ctx,
    dens: &mut PathDensities,
    eye: &[Vertex],
    light: &[Vertex],
    index: u32,
    out: &mut SampleOut,
) {
    let (Some(cam), Some(l)) = (eye.first(), light.first()) else {
        return;
    };
    let Some(area) = area_of(ctx, l) else {
        return;
    };
    let pl0 = ctx.origin_density(l);
    if pl0.is_nan() || pl0 <= 0.0 {
        return;
    }
    let Some(hit) = ctx.camera.connect(cam.p(), l.p(), ctx.time) else {
        return;
    };
    let w_lc = -hit.dir;
    let le = area.le(&l.si, w_lc, None);
    let c = le * (l.si.it.n.dot(w_lc).abs() / pl0) * hit.weight;
    if c.is_black() || !c.is_finite() {
        return;
    }
    let Some(g) = ctx.segment(cam, l).filter(|g| !g.tr.is_black()) else {
        return;
    };
    let link = Link {
        to_eye: g.b_to_a,
        to_light: g.a_to_b,
    };
    let w = weight(ctx, dens, eye, 1, light, 1, None, link);
    let c = c * g.tr * w;
    if c.is_black() || !c.is_finite() {
        return;
    }
    out.splats.push(Splat {
        p_film: Vec2::new(hit.raster.x, hit.raster.y),
        group: group_of(ctx, index) as u32,
        l: c,
        weight: w,
    });
}

/// s ≥ 2, t = 1: joins light vertex L_{s−1} to the camera vertex E₀; a splat.
pub fn to_camera(
    ctx: &Ctx,
    dens: &mut PathDensities,
    eye: &[Vertex],
    light: &[Vertex],
    s: usize,
    index: u32,
    out: &mut SampleOut,
) {
    let (Some(cam), Some(l)) = (eye.first(), light.get(s - 1)) else {
        return;
    };
    if !l.connectable() {
        return;
    }
    let Some(hit) = ctx.camera.connect(cam.p(), l.p(), ctx.time) else {
        return;
    };
    let w_lc = -hit.dir;
    let fl = f_light(l, w_lc);
    let c = l.beta * fl * hit.weight;
    if c.is_black() || !c.is_finite() {
        return;
    }
    let Some(g) = ctx.segment(cam, l).filter(|g| !g.tr.is_black()) else {
        return;
    };
    let c = c * g.tr;
    let link = Link {
        to_eye: g.b_to_a,
        to_light: g.a_to_b,
    };
    let w = weight(ctx, dens, eye, 1, light, s, None, link);
    let c = c * w;
    if c.is_black() || !c.is_finite() {
        return;
    }
    out.splats.push(Splat {
        p_film: Vec2::new(hit.raster.x, hit.raster.y),
        group: group_of(ctx, index) as u32,
        l: c,
        weight: w,
    });
}
