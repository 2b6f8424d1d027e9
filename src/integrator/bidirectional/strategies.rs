//! The connection strategies of bidirectional path tracing and their weights.
//!
//! With an eye subpath E₀ (camera) … and a light subpath L₀ (light) …, a strategy (s, t)
//! uses the first s light vertices and the first t eye vertices:
//! - s = 0: the eye path met a light (an emitting surface, or the sky when it escaped);
//! - s = 1: direct lighting: a light sampled from eye vertex E_{t−1};
//! - s ≥ 2, t ≥ 2: L_{s−1} joined to E_{t−1} by a shadow ray;
//! - s ≥ 2, t = 1: L_{s−1} joined to the camera: a splat at another film position.
//!
//! [`weight`] gathers the path's densities into [`PathDensities`] — the stored walk
//! densities, recomputed near the connection — and returns the power-heuristic weight.
//!
//! In a scene with media, connections (shadow rays, and the joins of s ≥ 2) carry the
//! transmittance of the media between their two ends, walked through null surfaces and
//! medium boundaries by [`Ctx::segment`]; the connection's distance-sampling factors go
//! into the recomputed densities. A medium vertex scatters with its phase function (no
//! cosine), on either side of a connection.

use super::mis::{Limits, PathDensities};
use super::vertex::{cos_toward, Ctx, Kind, Vertex};
use crate::integrator::{SampleOut, Splat};
use crate::light::Light;
use crate::sampler::SampleStream;
use crate::spectrum::Rgb;
use glam::Vec2;

/// The light vertex j of a strategy with s light vertices (the resampled one for s = 1).
fn light_at<'a>(light: &'a [Vertex], sampled: Option<&'a Vertex>, j: usize) -> Option<&'a Vertex> {
    if j == 0 {
        if let Some(v) = sampled {
            return Some(v);
        }
    }
    light.get(j)
}

/// The distance-sampling factors of a connection (1 without scattering media): of the light
/// side generating E_{t−1} from L_{s−1}, and of the eye side generating L_{s−1} from E_{t−1}.
#[derive(Clone, Copy, Debug)]
pub struct Link {
    pub to_eye: f32,
    pub to_light: f32,
}

impl Link {
    /// No connection segment (s = 0).
    pub const NONE: Link = Link {
        to_eye: 1.0,
        to_light: 1.0,
    };
}

/// The power-heuristic weight of strategy (s, t); `sampled` replaces L₀ for s = 1.
#[allow(clippy::too_many_arguments)]
pub fn weight(
    ctx: &Ctx,
    dens: &mut PathDensities,
    eye: &[Vertex],
    t: usize,
    light: &[Vertex],
    s: usize,
    sampled: Option<&Vertex>,
    link: Link,
) -> f32 {
    let k = s + t;
    if k < 2 || t == 0 || t > eye.len() {
        return 0.0;
    }
    dens.reset(k);
    let x = |j: usize| -> Option<&Vertex> {
        if j >= k {
            None
        } else if j < s {
            light_at(light, sampled, j)
        } else {
            eye.get(k - 1 - j)
        }
    };
    for j in 0..k {
        let Some(v) = x(j) else {
            return 0.0;
        };
        if j < s {
            dens.pl[j] = v.pdf_fwd;
            dens.pe[j] = v.pdf_rev;
        } else {
            dens.pe[j] = v.pdf_fwd;
            dens.pl[j] = v.pdf_rev;
        }
        dens.delta[j] = v.delta;
        dens.medium[j] = v.kind == Kind::Medium;
    }
    let (Some(x0), Some(xs)) = (x(0), x(s)) else {
        return 0.0;
    };
    dens.pl[0] = ctx.origin_density(x0);
    // s = 1 in a path of two vertices is the origin joined to the camera, not direct lighting.
    dens.pdir0 = if k == 2 {
        dens.pl[0]
    } else {
        ctx.direct_density(x0, x(1))
    };
    dens.light_delta = !ctx.hittable(x0);
    dens.area_origin = area_of(ctx, x0).is_some();
    dens.delta[s] = false;
    if s == 0 {
        if let Some(x1) = x(1) {
            dens.pl[1] = ctx.emit_pdf(x0, x1) * x0.dist_rev;
        }
    } else {
        dens.delta[s - 1] = false;
        let Some(ls) = x(s - 1) else {
            return 0.0;
        };
        // The camera side reaching x_{s-1} and x_{s-2}.
        dens.pe[s - 1] = link.to_light
            * match x(s + 1) {
                Some(e_prev) if t >= 2 => ctx.scatter_pdf(xs, e_prev, ls),
                _ => ctx.camera_pdf(xs, ls),
            };
        if s >= 2 {
            if let Some(l2) = x(s - 2) {
                dens.pe[s - 2] = ctx.scatter_pdf(ls, xs, l2) * ls.dist_rev;
            }
        }
        // The light side reaching x_s and x_{s+1}.
        dens.pl[s] = link.to_eye
            * if s == 1 {
                ctx.emit_pdf(ls, xs)
            } else {
                x(s - 2).map_or(0.0, |l2| ctx.scatter_pdf(ls, l2, xs))
            };
        if t >= 2 {
            if let Some(e_prev) = x(s + 1) {
                dens.pl[s + 1] = ctx.scatter_pdf(xs, ls, e_prev) * xs.dist_rev;
            }
        }
    }
    bridge_specular_chains(dens, &x, k);
    let lim = Limits {
        max_light: ctx.bidir.light_depth as usize,
        max_eye: ctx.bidir.eye_depth as usize,
        camera: ctx.camera.connectable(),
        max_scatters: ctx.bidir.volume.max_scatters() as usize,
    };
    dens.weight(s, &lim)
}

/// Densities across specular chains: runs of delta vertices x_{i+1} … x_{m−1} between two
/// scattering vertices a = x_i and b = x_m.
///
/// Neither side samples a delta vertex's position: the light side reaches b from a by the
/// solid angle density pdf(a) of its direction out of a, carried through the chain; the eye
/// side reaches a from b by pdf(b). Their area densities are pdf(a) × J(a → b) and pdf(b) ×
/// J(b → a), the chain's generalized geometry term, which for mirrors and flat interfaces is
/// |cos| at the far end over the squared length of the unfolded chain. The walks store
/// instead the densities of the chain's first vertex on each side (area densities at a
/// delta vertex, whose distances to a and to b can differ by orders of magnitude: a floor
/// point 2 cm below a glass sphere and a lamp 1.6 m above it) and nothing at a and b; left
/// as they are, the weights give the eye path that hits a small lamp through glass a large
/// share of the caustic light tracing finds far more easily, and the image fireflies.
/// Here pl(b) and pe(a) become those chain densities and the delta vertices' own densities
/// drop out of the ratios. Any consistent choice keeps the weights summing to one; this one
/// keeps them close to the strategies' true densities.
fn bridge_specular_chains<'a>(
    dens: &mut PathDensities,
    x: &impl Fn(usize) -> Option<&'a Vertex>,
    k: usize,
) {
    let mut i = 0;
    while i + 2 < k {
        if dens.delta[i] || !dens.delta[i + 1] {
            i += 1;
            continue;
        }
        let mut m = i + 1;
        while m < k && dens.delta[m] {
            m += 1;
        }
        if m >= k {
            return;
        }
        let ends = (x(i), x(i + 1), x(m - 1), x(m));
        let (Some(a), Some(a1), Some(b1), Some(b)) = ends else {
            return;
        };
        if !(a.is_at_infinity() || b.is_at_infinity()) {
            let len: f32 = (i..m)
                .filter_map(|j| Some((x(j)?.p() - x(j + 1)?.p()).length()))
                .sum();
            let len2 = len * len;
            let from_a = solid_angle(dens.pl[i + 1], a, a1);
            let from_b = solid_angle(dens.pe[m - 1], b, b1);
            if len2 > 0.0 && from_a > 0.0 && from_b > 0.0 {
                dens.pl[m] = from_a * cos_toward(b, b1) / len2;
                dens.pe[i] = from_b * cos_toward(a, a1) / len2;
                for j in i + 1..m {
                    dens.pl[j] = 0.0;
                    dens.pe[j] = 0.0;
                }
            }
        }
        i = m;
    }
}

/// The solid-angle density at `from` behind an area density `area` at `to`.
fn solid_angle(area: f32, from: &Vertex, to: &Vertex) -> f32 {
    let d2 = (to.p() - from.p()).length_squared();
    let cos = cos_toward(to, from);
    if area > 0.0 && cos > 0.0 {
        area * d2 / cos
    } else {
        0.0
    }
}

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
                let le = l.le(v.dir);
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

/// The area light a vertex lies on: a light subpath's origin on it, or a surface hit on it.
fn area_of<'c>(ctx: &'c Ctx, v: &Vertex) -> Option<&'c crate::light::AreaLight> {
    let i = match v.kind {
        Kind::LightPoint(i) => i,
        Kind::Surface { emitter: Some(i) } => i,
        _ => return None,
    };
    match ctx.light(i)? {
        Light::Area(a) => Some(a),
        _ => None,
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Interaction, SurfaceInteraction};
    use crate::spectrum::Rgb;
    use glam::Vec3A;

    fn surface(p: [f32; 3], n: [f32; 3], delta: bool) -> Vertex {
        let si = SurfaceInteraction {
            it: Interaction {
                p: Vec3A::from_array(p),
                n: Vec3A::from_array(n),
                ..Interaction::default()
            },
            ..SurfaceInteraction::default()
        };
        let mut v = Vertex::new(Kind::Surface { emitter: None }, si, Rgb::WHITE, 0.0);
        v.delta = delta;
        v
    }

    /// A flat mirror (z = 0) between a = (0, 0, 1) and b = (2, 0, 1), both facing down: the
    /// unfolded chain is 2√2 long and meets b at 45°, so the light side reaches b with area
    /// density pdf(a) · cos 45° / 8, and the eye side reaches a with pdf(b) · cos 45° / 8
    /// (the mirror image's exact Jacobian). The walks' densities at the mirror point (2 away
    /// from both) drop out.
    #[test]
    fn specular_chains_get_the_unfolded_densities() {
        let verts = [
            surface([0.0, 0.0, 1.0], [0.0, 0.0, -1.0], false),
            surface([1.0, 0.0, 0.0], [0.0, 0.0, 1.0], true),
            surface([2.0, 0.0, 1.0], [0.0, 0.0, -1.0], false),
        ];
        let x = |j: usize| verts.get(j);
        let c45 = std::f32::consts::FRAC_1_SQRT_2;
        let (pdf_a, pdf_b) = (0.3f32, 0.5f32);
        let mut d = PathDensities::default();
        d.reset(3);
        d.delta = vec![false, true, false];
        // What the walks store: area densities at the mirror point, 2 (squared) away.
        d.pl = vec![1.0, pdf_a * c45 / 2.0, 0.0];
        d.pe = vec![0.0, pdf_b * c45 / 2.0, 1.0];
        bridge_specular_chains(&mut d, &x, 3);
        let want_b = pdf_a * c45 / 8.0;
        let want_a = pdf_b * c45 / 8.0;
        assert!(
            (d.pl[2] - want_b).abs() < 1e-6 * want_b.max(1.0),
            "{:?}",
            d.pl
        );
        assert!((d.pe[0] - want_a).abs() < 1e-6, "{:?}", d.pe);
        assert_eq!((d.pl[1], d.pe[1]), (0.0, 0.0));
        // A path without delta vertices is left as it is.
        let plain = [
            verts[0].clone(),
            surface([1.0, 0.0, 0.0], [0.0, 0.0, 1.0], false),
        ];
        let y = |j: usize| plain.get(j);
        let mut e = PathDensities::default();
        e.reset(2);
        e.pl = vec![1.0, 0.2];
        e.pe = vec![0.3, 1.0];
        let before = e.clone();
        bridge_specular_chains(&mut e, &y, 2);
        assert_eq!((e.pl, e.pe), (before.pl, before.pe));
    }
}
