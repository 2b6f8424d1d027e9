//! The weight of a connection strategy (s, t): the densities of the whole path gathered from
//! the two subpaths into [`PathDensities`] (the walks' stored densities, recomputed near the
//! connection, and across specular chains from their unfolded length), then the power
//! heuristic of [`super::mis`]. `strategies.rs` computes each strategy's contribution and
//! calls [`weight`].

use super::mis::{Limits, PathDensities};
use super::vertex::{cos_toward, Ctx, Kind, Vertex};
use crate::light::Light;

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

/// The area light a vertex lies on: a light subpath's origin on it, or a surface hit on it.
pub(super) fn area_of<'c>(ctx: &'c Ctx, v: &Vertex) -> Option<&'c crate::light::AreaLight> {
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
