//! Vertex masks: Loop's even-vertex rule (shared by a refinement level and the final push to
//! the limit surface, which differ only in their weights), the limit tangents that give each
//! vertex its normal, and the displacement along those normals.

use super::topology::{next_corner, prev_corner};
use super::{attr_sum, limit_gamma, Attr, Split, SubdivMesh, Topology};
use glam::{DVec2, DVec3};
use std::f64::consts::PI;

/// Writes into `out` the new position of topological vertex `v` of `m` and the attributes of
/// its attribute vertices: an interior vertex of valence n takes `1 - n w` of itself and `w`
/// of each neighbour, a boundary vertex `1 - 2 w` of itself and `w` of its two boundary
/// neighbours (or stays put when `sharp`). An attribute channel with a seam at the vertex
/// keeps each corner's own value.
pub(super) fn smooth_vertex(
    m: &SubdivMesh,
    topo: &Topology,
    v: usize,
    w: f64,
    sharp: bool,
    out: &mut SubdivMesh,
) {
    let fan = topo.fan(v);
    let Some(&first) = fan.first() else {
        return;
    };
    let boundary = topo.is_boundary(v);
    if boundary && sharp {
        return;
    }
    let pos_of = |c: u32| m.pos[m.topo(c as usize / 3, c as usize % 3)];
    let attr_of = |c: u32| m.attr[m.faces[c as usize / 3][c as usize % 3] as usize];
    let ring = topo.ring(v);
    let used: Vec<u32> = match (boundary, ring.first(), ring.last()) {
        (true, Some(&a), Some(&b)) => vec![a, b],
        _ => ring.clone(),
    };
    let center_w = 1.0 - used.len() as f64 * w;
    out.pos[v] = center_w * m.pos[v] + used.iter().map(|&c| w * pos_of(c)).sum::<DVec3>();

    let mut split = Split::default();
    let center = attr_of(first);
    for &c in fan {
        split.note(&center, &attr_of(c));
    }
    let pairs = if boundary { fan.len() - 1 } else { fan.len() };
    for i in 0..pairs {
        let (a, b) = (fan[i], fan[(i + 1) % fan.len()]);
        split.note(&attr_of(next_corner(a)), &attr_of(prev_corner(b)));
    }
    let mut terms = vec![(center_w, center)];
    terms.extend(used.iter().map(|&c| (w, attr_of(c))));
    let smooth = attr_sum(&terms);
    for &c in fan {
        let a = m.faces[c as usize / 3][c as usize % 3] as usize;
        out.attr[a] = split.pick(m.attr[a], smooth);
    }
}

/// Pushes every vertex to its position on the limit surface (LuxRender's weights: γ(n) for an
/// interior vertex, 1/5 for a boundary one).
pub(super) fn to_limit(m: &mut SubdivMesh, topo: &Topology, sharp: bool) {
    let mut out = m.clone();
    for v in 0..m.pos.len() {
        let w = if topo.is_boundary(v) {
            1.0 / 5.0
        } else {
            limit_gamma(topo.ring(v).len())
        };
        smooth_vertex(m, topo, v, w, sharp, &mut out);
    }
    *m = out;
}

/// The limit-surface normal of every topological vertex (zero for a vertex no face uses).
pub(super) fn normals(m: &SubdivMesh, topo: &Topology) -> Vec<DVec3> {
    (0..m.pos.len())
        .map(|v| vertex_normal(m, topo, v))
        .collect()
}

fn vertex_normal(m: &SubdivMesh, topo: &Topology, v: usize) -> DVec3 {
    let p = m.pos[v];
    let d: Vec<DVec3> = topo
        .ring(v)
        .iter()
        .map(|&c| m.pos[m.topo(c as usize / 3, c as usize % 3)] - p)
        .collect();
    let (s, t) = if topo.is_boundary(v) {
        boundary_tangents(&d)
    } else {
        interior_tangents(&d)
    };
    let faces: DVec3 = topo
        .fan(v)
        .iter()
        .map(|&c| {
            let f = c as usize / 3;
            let [a, b, e] = [0, 1, 2].map(|k| m.pos[m.topo(f, k)]);
            (b - a).cross(e - a)
        })
        .sum();
    let n = t.cross(s);
    let n = if n.dot(faces) < 0.0 { -n } else { n };
    match n.try_normalize() {
        Some(n) if n.is_finite() => n,
        _ => faces.try_normalize().unwrap_or(DVec3::ZERO),
    }
}

/// Limit tangents of an interior vertex from its ring (offsets from the vertex).
fn interior_tangents(d: &[DVec3]) -> (DVec3, DVec3) {
    let n = d.len() as f64;
    let mut s = DVec3::ZERO;
    let mut t = DVec3::ZERO;
    for (k, dk) in d.iter().enumerate() {
        let a = 2.0 * PI * k as f64 / n;
        s += a.cos() * *dk;
        t += a.sin() * *dk;
    }
    (s, t)
}

/// Limit tangents of a boundary vertex: along the boundary, and across it with the masks
/// for each valence (the ring runs from one boundary neighbour to the other).
fn boundary_tangents(d: &[DVec3]) -> (DVec3, DVec3) {
    let n = d.len();
    let (Some(&first), Some(&last)) = (d.first(), d.last()) else {
        return (DVec3::ZERO, DVec3::ZERO);
    };
    let s = last - first;
    let t = match n {
        1 => DVec3::ZERO,
        2 => first + last,
        3 => d[1],
        4 => -d[0] + 2.0 * d[1] + 2.0 * d[2] - d[3],
        _ => {
            let theta = PI / (n - 1) as f64;
            let mut t = theta.sin() * (first + last);
            for (k, dk) in d.iter().enumerate().take(n - 1).skip(1) {
                t += (2.0 * theta.cos() - 2.0) * (k as f64 * theta).sin() * *dk;
            }
            t
        }
    };
    (s, t)
}

/// Displaces each vertex along its normal; returns how many vertices got a non-finite
/// displacement (left in place).
pub(super) fn displace(
    m: &mut SubdivMesh,
    topo: &Topology,
    normals: &[DVec3],
    map: &dyn Fn(DVec3, DVec3, DVec2) -> f64,
    scale: f64,
    offset: f64,
) -> usize {
    let mut bad = 0;
    let moved: Vec<DVec3> = (0..m.pos.len())
        .map(|v| {
            let fan = topo.fan(v);
            let (p, n) = (m.pos[v], normals.get(v).copied().unwrap_or(DVec3::ZERO));
            if fan.is_empty() {
                return p;
            }
            let sum: f64 = fan
                .iter()
                .map(|&c| {
                    let a: Attr = m.attr[m.faces[c as usize / 3][c as usize % 3] as usize];
                    map(p, n, a.uv)
                })
                .sum();
            let dl = sum * scale / fan.len() as f64 + offset;
            if dl.is_finite() {
                p + n * dl
            } else {
                bad += 1;
                p
            }
        })
        .collect();
    m.pos = moved;
    bad
}
