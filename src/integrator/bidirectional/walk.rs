//! The two random walks of bidirectional path tracing: the eye subpath from the camera
//! (radiance) and the light subpath from a light (importance).
//!
//! Each walk stores its vertices with their throughput and densities (see [`super::vertex`]).
//! In a scene with media a walk knows the medium it is in (the camera's; a light's is the
//! exterior named at its statement, else found from the first surface its ray meets), attenuates every segment by it and, in media that
//! scatter (volume integrator `single` or `multi`), samples the segment's end: a scattering
//! point becomes a medium vertex whose phase function is sampled as a surface's BSDF, as
//! long as the subpath has scattering events left (`max_scatters`).
//! Null-material surfaces are crossed without a vertex; an eye walk crossing an emitting null
//! surface remembers it (`crossings`), since the eye path sees its light there. Along every
//! segment of the eye walk (each piece of it, in the medium of that piece) the walk gathers
//! the emission of emitting region volumes seen through the medium, times the throughput at
//! the piece's start, over the whole piece up to its surface (the scattering point sampled on
//! it does not shorten it: the emission integral is exact, distance sampling estimates only
//! the rest); light walks gather none. Russian
//! roulette follows LuxRender: after the third vertex a subpath continues with probability
//! `min(1, max(threshold, mean(f·|cos| / pdf)))` of the last scattering, so threshold 1 turns
//! it off. Random numbers come from fixed dimensions per vertex ([`super::layout::Layout`]).

use super::layout::Layout;
use super::vertex::{to_area, Ctx, Kind, Vertex};
use crate::geometry::{Ray, SurfaceInteraction};
use crate::light::Light;
use crate::sampler::SampleStream;
use crate::spectrum::Rgb;
use crate::volume::{HenyeyGreenstein, MediumId};
use glam::Vec3A;

/// Vertices after which Russian roulette may end a subpath (LuxRender's `rrStart`).
const RR_START: usize = 3;
/// Null surfaces one segment may cross.
const MAX_PASS_THROUGH: u32 = 64;

/// Dimensions of the distance samples of a segment's pieces after its first (a segment
/// crossing null surfaces into other media): outside every vertex block, 2 per piece.
const EXTRA_PIECES: u32 = 1 << 24;

/// The medium a traced ray starts in.
#[derive(Clone, Copy, Debug)]
enum Start {
    Known(Option<MediumId>),
    /// A light's ray whose light names no medium (an area light on a surface that is no
    /// medium boundary, or a `LightSource` with no `Exterior` in effect): the one on the arriving side of the first surface it meets when
    /// that is a medium boundary, else the camera's (the scene's outer medium, as LuxBlend's
    /// "world").
    FirstHit,
}

/// The medium light `index`'s rays start in, for a ray leaving `origin` in direction `d`:
/// for an area light on a medium boundary, the side the ray leaves by (its shape's exterior
/// along the normal, interior against it); for a light at a finite place, the one its
/// statement named (LuxRender 1.x's exterior volume of a `LightSource`); else, and for lights
/// at infinity (whose rays come from outside everything, as the path tracer's shadow rays
/// find them), the one found from the first surface they meet.
fn light_start(ctx: &Ctx, index: u32, origin: &Vertex, d: Vec3A) -> Start {
    if ctx.light(index).is_some_and(Light::is_infinite) {
        return Start::FirstHit;
    }
    let Some(ms) = ctx.world.media() else {
        return Start::FirstHit;
    };
    let own = ms
        .area_light_side(index as usize, origin.si.it.n, d)
        .or_else(|| ms.light_start(index as usize));
    match own {
        Some(m) => Start::Known(m),
        None => Start::FirstHit,
    }
}

/// Where a traced ray stopped.
enum Stop {
    Surface(SurfaceInteraction),
    /// A scattering point in a medium.
    Medium {
        p: Vec3A,
        /// The phase function there.
        phase: HenyeyGreenstein,
    },
    /// It left the scene.
    Escaped,
    /// Distance sampling chose a scattering point the subpath may not use (its scattering
    /// budget is spent): the subpath ends there (unbiased, as Russian roulette).
    Absorbed,
}

/// How [`trace`] runs: whether distance sampling may stop at a scattering point (the
/// subpath has scattering events left), and whether it gathers the media's emission (eye
/// walks only).
#[derive(Clone, Copy, Debug)]
struct Mode {
    may_scatter: bool,
    emission: bool,
}

/// The result of [`trace`]: where it stopped, the medium it arrived in, and the throughput
/// factor of the way there (transmittance over the distance sampling's density).
struct Traced {
    stop: Stop,
    /// The medium the ray started in (resolved for [`Start::FirstHit`]).
    start: Option<MediumId>,
    medium: Option<MediumId>,
    weight: Rgb,
    /// With [`Mode::emission`]: the media's emission along the way, seen through them, each
    /// piece's times the throughput factor up to the piece's start (black otherwise).
    emission: Rgb,
}

/// Traces `ray` to the closest surface that is not null, or to a scattering point in a
/// medium sampled on the way (distance sampling in media that scatter, with dimensions
/// from `dim`; `mode.may_scatter` false when the subpath's scattering budget is spent).
/// Emitting null surfaces crossed on the way are reported to `crossed` with the throughput
/// factor and the medium up to them.
fn trace(
    ctx: &Ctx,
    mut ray: Ray,
    start: Start,
    mode: Mode,
    s: &mut SampleStream,
    dim: u32,
    mut crossed: impl FnMut(&SurfaceInteraction, u32, Rgb, Option<MediumId>),
) -> Traced {
    let media = ctx.world.media();
    let mut weight = Rgb::WHITE;
    let mut emission = Rgb::BLACK;
    let mut medium = match start {
        Start::Known(m) => m,
        Start::FirstHit => None,
    };
    let mut resolve = matches!(start, Start::FirstHit) && media.is_some();
    let mut first = medium;
    for piece in 0..MAX_PASS_THROUGH {
        let hit = ctx.world.intersect(&ray);
        if resolve {
            resolve = false;
            let fallback = media.and_then(|ms| ms.camera);
            medium = match (&hit, media) {
                (Some(h), Some(ms)) => ms.after(h.prim, h.it.n, -ray.d, fallback),
                _ => fallback,
            };
            first = medium;
        }
        let t_hit = hit.as_ref().map_or(f32::INFINITY, |h| h.t);
        if let Some(m) = medium.and_then(|id| media.and_then(|ms| ms.get(id))) {
            if mode.emission && m.emits() {
                emission += weight * m.emission(&ray, t_hit);
            }
            if ctx.samples_distance(m) {
                s.set_dimension(if piece == 0 {
                    dim
                } else {
                    EXTRA_PIECES + dim.saturating_mul(2 * MAX_PASS_THROUGH) + 2 * piece
                });
                let ms = m.sample(&ray, t_hit, s.next_1d(), s.next_1d());
                weight *= ms.weight;
                if let Some(t) = ms.scatter_t {
                    let stop = if mode.may_scatter {
                        Stop::Medium {
                            p: ray.at(t),
                            phase: ms.phase,
                        }
                    } else {
                        Stop::Absorbed
                    };
                    return Traced {
                        stop,
                        start: first,
                        medium,
                        weight,
                        emission,
                    };
                }
            } else {
                weight *= m.tr(&ray, t_hit);
            }
        }
        let Some(si) = hit else {
            return Traced {
                stop: Stop::Escaped,
                start: first,
                medium,
                weight,
                emission,
            };
        };
        if !ctx.world.material(si.prim).is_null() {
            return Traced {
                stop: Stop::Surface(si),
                start: first,
                medium,
                weight,
                emission,
            };
        }
        if let Some((i, _)) = ctx.world.area_light(si.prim) {
            crossed(&si, i as u32, weight, medium);
        }
        if let Some(ms) = media {
            medium = ms.after(si.prim, si.it.n, ray.d, medium);
        }
        ray = si.it.spawn_ray(ray.d);
    }
    Traced {
        stop: Stop::Absorbed,
        start: first,
        medium,
        weight,
        emission,
    }
}

fn roulette(n: usize, threshold: f32, weight: Rgb, u: f32) -> Option<f32> {
    if n <= RR_START {
        return Some(1.0);
    }
    let q = weight.average().max(threshold).min(1.0);
    (q > 0.0 && u < q).then_some(q)
}

/// Sets `v.pdf_fwd` for a vertex reached from `prev` by a direction of solid-angle density
/// `pdf_dir` (or, after a light at infinity, the disc's density), and `v.dist_rev`: both
/// with the distance-sampling factors of the segment between them.
fn set_fwd(ctx: &Ctx, v: &mut Vertex, prev: &Vertex, pdf_dir: f32) {
    let geo = if prev.is_at_infinity() {
        match v.kind {
            Kind::Medium => pdf_dir,
            _ => pdf_dir * v.si.it.n.dot(prev.dir).abs(),
        }
    } else {
        to_area(pdf_dir, prev, v)
    };
    let (fwd, rev) = if ctx.scattering() {
        ctx.segment(prev, v)
            .map_or((0.0, 0.0), |g| (g.a_to_b, g.b_to_a))
    } else {
        (1.0, 1.0)
    };
    v.pdf_fwd = geo * fwd;
    v.dist_rev = rev;
}

/// The vertex where a traced ray stopped (`None`: it left the scene or was absorbed),
/// reached with throughput `beta` from `prev` by a direction of density `pdf_dir`.
fn vertex_at(
    ctx: &Ctx,
    t: Traced,
    ray: &Ray,
    beta: Rgb,
    prev: &Vertex,
    pdf_dir: f32,
) -> Option<Vertex> {
    let mut v = match t.stop {
        Stop::Surface(si) => {
            let emitter = ctx.world.area_light(si.prim).map(|(i, _)| i as u32);
            Vertex::new(Kind::Surface { emitter }, si, beta, 0.0)
        }
        Stop::Medium { p, phase } => {
            let mut si = SurfaceInteraction::default();
            si.it.p = p;
            si.it.time = ray.time;
            si.wo = -ray.d.normalize_or_zero();
            let mut v = Vertex::new(Kind::Medium, si, beta, 0.0);
            v.phase = Some(phase);
            v
        }
        Stop::Escaped | Stop::Absorbed => return None,
    };
    v.medium = t.medium;
    set_fwd(ctx, &mut v, prev, pdf_dir);
    Some(v)
}

/// Gives the path's last vertex, when it is a surface, its BSDF (built in place: a BSDF is
/// large) with component choice `u_comp`; false for a medium point (a scattering event).
fn attach_bsdf(ctx: &Ctx, path: &mut [Vertex], u_comp: f32) -> bool {
    let Some(v) = path.last_mut() else {
        return false;
    };
    if !matches!(v.kind, Kind::Surface { .. }) {
        return false;
    }
    v.bsdf = Some(ctx.world.material(v.si.prim).bsdf(&v.si, u_comp));
    true
}

/// A direction sampled at a vertex: its throughput factor (f·|cos|/pdf, the adjoint's for
/// light subpaths), its density and the reverse one, and whether it was a delta choice.
struct Scattered {
    wi: Vec3A,
    weight: Rgb,
    pdf: f32,
    pdf_rev: f32,
    specular: bool,
}

/// Samples the continuation at vertex `v` (a surface's BSDF, or a medium point's phase
/// function); `adjoint` for light subpaths.
fn scatter(v: &Vertex, adjoint: bool, u: f32, u2: glam::Vec2) -> Option<Scattered> {
    let wo = v.si.wo;
    if let Some(ph) = v.phase {
        let (wi, pdf) = ph.sample(-wo, u2);
        if pdf <= 0.0 || wi == Vec3A::ZERO {
            return None;
        }
        // Sampled exactly (f / pdf = 1) and symmetric (the reverse density is the same).
        return Some(Scattered {
            wi,
            weight: Rgb::WHITE,
            pdf,
            pdf_rev: pdf,
            specular: false,
        });
    }
    let bsdf = v.bsdf.as_ref()?;
    let bs = bsdf.sample_f(wo, u, u2)?;
    if bs.pdf <= 0.0 || bs.f.is_black() {
        return None;
    }
    let weight = if adjoint {
        let cos_o_g = wo.dot(v.si.it.n).abs();
        if cos_o_g == 0.0 {
            return None;
        }
        // Importance: the adjoint BSDF, and the shading-normal correction
        // |wo·ns| |wi·ng| / (|wo·ng| |wi·ns|) times the |wi·ns| of the sample.
        bs.f * (bsdf.adjoint_scale(wo, bs.wi)
            * wo.dot(bsdf.frame.n).abs()
            * bs.wi.dot(v.si.it.n).abs()
            / (cos_o_g * bs.pdf))
    } else {
        bs.f * (bs.wi.dot(bsdf.frame.n).abs() / bs.pdf)
    };
    Some(Scattered {
        wi: bs.wi,
        weight,
        pdf: bs.pdf,
        pdf_rev: bsdf.pdf(bs.wi, wo),
        specular: bs.specular,
    })
}

/// The ray leaving vertex `v` in direction `d`.
fn spawn(v: &Vertex, d: Vec3A) -> Ray {
    v.si.it.spawn_ray(d)
}

/// What an eye walk yields besides its vertices.
#[derive(Clone, Copy, Debug)]
pub struct EyeWalk {
    /// The sample's alpha (0 when the camera ray leaves the scene).
    pub alpha: f32,
    /// The emission of emitting media along the subpath's segments, each segment's times
    /// the throughput at its start: radiance at the sample's position, whole (no other
    /// strategy reaches a point of volume emission, so its MIS weight is 1).
    pub medium_emission: Rgb,
}

/// Traces the eye subpath of camera ray `ray` leaving lens point `lens` into `path`.
pub fn eye_walk(
    ctx: &Ctx,
    ray: Ray,
    lens: Vec3A,
    s: &mut SampleStream,
    layout: &Layout,
    path: &mut Vec<Vertex>,
    crossings: &mut Vec<(usize, Vertex)>,
) -> EyeWalk {
    path.clear();
    crossings.clear();
    let bidir = ctx.bidir;
    let mut cam = Vertex::new(Kind::Camera, SurfaceInteraction::default(), Rgb::WHITE, 1.0);
    cam.si.it.p = lens;
    cam.si.it.time = ray.time;
    cam.medium = ctx.world.media().and_then(|m| m.camera);
    path.push(cam);
    let max = bidir.eye_depth as usize;
    let mut scatters_left = bidir.volume.max_scatters();
    let mut alpha = 1.0;
    let mut medium_emission = Rgb::BLACK;
    let mut ray = ray;
    let mut beta = Rgb::WHITE;
    let mut pdf_dir = ctx.camera.dir_pdf(ray.d.normalize_or_zero(), ray.time);
    while path.len() < max {
        // Borrowed, not cloned: a vertex is large, and the path only grows after the trace.
        let Some(prev) = path.last() else {
            break;
        };
        let n = path.len();
        let start = Start::Known(prev.medium_toward(ctx.world, ray.d));
        let mode = Mode {
            may_scatter: scatters_left > 0,
            emission: true,
        };
        let traced = trace(
            ctx,
            ray,
            start,
            mode,
            s,
            layout.eye(n),
            |si, light, w, medium| {
                let mut v = Vertex::new(
                    Kind::Surface {
                        emitter: Some(light),
                    },
                    *si,
                    beta * w,
                    0.0,
                );
                v.medium = medium;
                set_fwd(ctx, &mut v, prev, pdf_dir);
                crossings.push((n, v));
            },
        );
        medium_emission += beta * traced.emission;
        beta *= traced.weight;
        if matches!(traced.stop, Stop::Escaped) {
            if n == 1 {
                alpha = 0.0;
            }
            if !ctx.world.infinite_lights().is_empty() && !beta.is_black() {
                let dir = ray.d.normalize_or_zero();
                let mut v = Vertex::at_infinity(Kind::Sky, dir, beta, 0.0);
                v.medium = traced.medium;
                set_fwd(ctx, &mut v, prev, pdf_dir);
                path.push(v);
            }
            break;
        }
        let Some(v) = vertex_at(ctx, traced, &ray, beta, prev, pdf_dir) else {
            break;
        };
        s.set_dimension(layout.eye(n) + 2);
        path.push(v);
        if !attach_bsdf(ctx, path, s.next_1d()) {
            scatters_left = scatters_left.saturating_sub(1);
        }
        if path.len() >= max || beta.is_black() {
            break;
        }
        let (u, u2, u_rr) = (s.next_1d(), s.next_2d(), s.next_1d());
        let Some(sc) = path.last().and_then(|v| scatter(v, false, u, u2)) else {
            break;
        };
        let (mut pdf_rev, specular) = (sc.pdf_rev, sc.specular);
        pdf_dir = sc.pdf;
        if specular {
            pdf_dir = 0.0;
            pdf_rev = 0.0;
        }
        let Some(q) = roulette(n + 1, bidir.eye_rr, sc.weight, u_rr) else {
            break;
        };
        beta = beta * sc.weight / q;
        let cur = n;
        if let Some(last) = path.get_mut(cur) {
            last.delta = specular;
        }
        if let (Some(p), Some(here)) = (cur.checked_sub(1), path.get(cur)) {
            let r = to_area(pdf_rev, here, &path[p]) * here.dist_rev;
            path[p].pdf_rev = r;
        }
        if !beta.is_finite() || beta.is_black() {
            break;
        }
        ray = spawn(&path[cur], sc.wi);
    }
    EyeWalk {
        alpha,
        medium_emission,
    }
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
        _ if light.is_delta_position() => (Kind::LightPoint(index), 1.0),
        _ if light.is_delta_direction() => (Kind::LightDir(index), 1.0),
        _ => (Kind::Sky, 1.0),
    };
    let mut v = if matches!(kind, Kind::LightPoint(_)) {
        let mut si = SurfaceInteraction::default();
        si.it.p = lr.ray.o;
        si.it.n = lr.n;
        si.it.time = ctx.time;
        si.uv = lr.uv;
        Vertex::new(kind, si, lr.le, 0.0)
    } else {
        Vertex::at_infinity(kind, -d, lr.le, 0.0)
    };
    v.pdf_fwd = ctx.origin_density(&v);
    let beta = lr.le * (cos / (draws * lr.pdf_pos * lr.pdf_dir));
    let pdf_next = match kind {
        // As the weights see it: the line's density over every light at infinity.
        Kind::Sky => ctx.sky_line_density(lr.ray.o, -d),
        _ if v.is_at_infinity() => lr.pdf_pos,
        _ => lr.pdf_dir,
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
    let mut scatters_left = bidir.volume.max_scatters();
    while path.len() < max {
        if !beta.is_finite() || beta.is_black() {
            break;
        }
        let n = path.len();
        let start = if n == 1 {
            light_start(ctx, index, &path[0], ray.d)
        } else {
            Start::Known(path[n - 1].medium_toward(ctx.world, ray.d))
        };
        let dim = layout.light_vertex(p, n);
        let mode = Mode {
            may_scatter: scatters_left > 0,
            emission: false,
        };
        let traced = trace(ctx, ray, start, mode, s, dim, |_, _, _, _| {});
        if n == 1 {
            path[0].medium = traced.start;
            let falloff = match &traced.stop {
                Stop::Surface(si) => ctx.light(index).map_or(1.0, |l| {
                    l.falloff_correction((si.it.p - path[0].p()).length_squared())
                }),
                _ => 1.0,
            };
            beta *= falloff;
        }
        beta *= traced.weight;
        let Some(v) = vertex_at(ctx, traced, &ray, beta, &path[n - 1], pdf_dir) else {
            break;
        };
        s.set_dimension(dim + 2);
        path.push(v);
        if !attach_bsdf(ctx, path, s.next_1d()) {
            scatters_left = scatters_left.saturating_sub(1);
        }
        if path.len() >= max {
            break;
        }
        let (u, u2, u_rr) = (s.next_1d(), s.next_2d(), s.next_1d());
        let Some(sc) = scatter(&path[n], true, u, u2) else {
            break;
        };
        let (mut pdf_rev, specular) = (sc.pdf_rev, sc.specular);
        pdf_dir = sc.pdf;
        if specular {
            pdf_dir = 0.0;
            pdf_rev = 0.0;
        }
        let Some(q) = roulette(n + 1, bidir.light_rr, sc.weight, u_rr) else {
            break;
        };
        beta = beta * sc.weight / q;
        path[n].delta = specular;
        let r = to_area(pdf_rev, &path[n], &path[n - 1]) * path[n].dist_rev;
        path[n - 1].pdf_rev = r;
        ray = spawn(&path[n], sc.wi);
    }
}
