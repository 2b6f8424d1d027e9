//! LuxRender 1.x's `subdivscheme "microdisplacement"` (its `MeshMicroDisplacementTriangle`,
//! after Smits, Shirley and Stark's direct ray tracing of displacement-mapped triangles).
//!
//! LuxRender intersects, on the fly, the surface made by splitting each triangle into an
//! N × N grid of its barycentric coordinates (N = `nsubdivlevels`, segments per edge, not a
//! number of halvings) and moving every grid point along the interpolated vertex normal
//! (the face normal when the mesh has none):
//!
//! ```text
//! grid point (u, v, w) = (a, b, c) / N, a + b + c = N
//! base  = u·p1 + v·p2 + w·p3          n̂ = normalize(u·n1 + v·n2 + w·n3)
//! point = base + n̂ · (clamp(map(uv), -1, 1) · dmscale + dmoffset)
//! ```
//!
//! with the map evaluated at the interpolated uv, on the base point with normal n̂ and the
//! triangle's dpdu/dpdv. The micro-triangles between the points are flat. luxfarm builds
//! that same surface once, as a mesh of N² triangles per triangle (each triangle's grid of its
//! own, as LuxRender computes each triangle alone), so a shape is refused past
//! `loopsubdiv::MAX_TRIANGLES` where LuxRender would spend time instead of memory.
//!
//! Shading (`dmnormalsmooth`, default true, and only for a mesh with normals, as LuxRender):
//! the interpolated normal tilted by the map's derivatives, LuxRender's `GetDuv` with step
//! 0.001: dpdu' = ss + (∂map/∂u)·n̂, dpdv' = ts + (∂map/∂v)·n̂, turned to n̂'s side (ss, ts
//! the shading tangents of length |dpdu|, |dpdv|). The tilt uses the map's raw derivative,
//! not times `dmscale`, as in LuxRender. LuxRender computes it at each hit; here at the grid
//! points, interpolated across each micro-triangle. Without smoothing, or without normals,
//! the micro-triangles are flat shaded.

use super::mesh_arrays::{evaluate_in, MeshArrays, DEFAULT_UV};
use crate::geometry::frame::coordinate_system;
use crate::geometry::{Interaction, Shading, SurfaceInteraction};
use crate::texture::FloatTex;
use glam::{DVec2, DVec3, Vec2};

/// LuxRender's sample distance for the map's derivatives.
const DUV_DELTA: f32 = 0.001;

/// The displacement settings of one shape.
#[derive(Clone, Copy, Debug)]
pub struct Micro {
    /// Grid segments per edge (N ≥ 1).
    pub segments: u32,
    pub scale: f64,
    pub offset: f64,
    /// Smooth shading normals (`dmnormalsmooth`).
    pub smooth: bool,
}

/// The displaced mesh and the grid points whose map value was not finite (left on the base
/// surface).
pub struct Displaced {
    pub mesh: MeshArrays,
    pub bad: usize,
}

/// The micro-triangle count of `tris` triangles at `segments` per edge, or `None` when it or
/// the number of grid points (each triangle's grid has its own) passes `limit`.
pub fn micro_count(tris: usize, segments: u32, limit: u64) -> Option<u64> {
    let n = u64::from(segments);
    let per = n.checked_mul(n)?;
    let points = (n + 1).checked_mul(n + 2)? / 2;
    (tris as u64).checked_mul(points).filter(|&p| p <= limit)?;
    (tris as u64).checked_mul(per).filter(|&t| t <= limit)
}

/// One base triangle's corners.
struct Base {
    p: [DVec3; 3],
    n: [DVec3; 3],
    uv: [DVec2; 3],
    dpdu: DVec3,
    dpdv: DVec3,
}

/// Displaces `mesh` as LuxRender's microdisplacement ray traces it; `flip` is the mesh's
/// geometric-normal flip (the face normal of a mesh without normals follows it).
pub fn displace(mesh: &MeshArrays, flip: bool, map: &FloatTex, m: Micro) -> Displaced {
    let n_seg = m.segments.max(1);
    let per_tri = ((n_seg + 1) * (n_seg + 2) / 2) as usize;
    let smooth = m.smooth && mesh.n.is_some();
    let mut out = MeshArrays {
        p: Vec::with_capacity(mesh.tris.len() * per_tri),
        n: smooth.then(Vec::new),
        uv: mesh.uv.as_ref().map(|_| Vec::new()),
        cols: mesh.cols.as_ref().map(|_| Vec::new()),
        alphas: mesh.alphas.as_ref().map(|_| Vec::new()),
        tris: Vec::with_capacity(mesh.tris.len() * (n_seg * n_seg) as usize),
    };
    let mut bad = 0;
    for &t in &mesh.tris {
        let first = out.p.len() as u32;
        let base = base_of(mesh, t, flip);
        for k in 0..=n_seg {
            for j in 0..=n_seg - k {
                let w = [
                    f64::from(n_seg - j - k) / f64::from(n_seg),
                    f64::from(j) / f64::from(n_seg),
                    f64::from(k) / f64::from(n_seg),
                ];
                bad += push_point(&mut out, mesh, t, &base, w, map, m, smooth);
            }
        }
        push_grid(&mut out.tris, first, n_seg);
    }
    Displaced { mesh: out, bad }
}

/// The corners of triangle `t`, its normals (the face normal without vertex normals) and
/// LuxRender's dpdu/dpdv from its uvs.
fn base_of(mesh: &MeshArrays, t: [u32; 3], flip: bool) -> Base {
    let at = |i: usize| t[i] as usize;
    let p = [0, 1, 2].map(|i| mesh.p[at(i)].as_dvec3());
    let mut face = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
    if flip {
        face = -face;
    }
    let n = match &mesh.n {
        Some(n) => [0, 1, 2].map(|i| n[at(i)].as_dvec3()),
        None => [face; 3],
    };
    let uv = match &mesh.uv {
        Some(uv) => [0, 1, 2].map(|i| uv[at(i)].as_dvec2()),
        None => DEFAULT_UV.map(|t| t.as_dvec2()),
    };
    let (du1, du2) = (uv[0].x - uv[2].x, uv[1].x - uv[2].x);
    let (dv1, dv2) = (uv[0].y - uv[2].y, uv[1].y - uv[2].y);
    let (dp1, dp2) = (p[0] - p[2], p[1] - p[2]);
    let det = du1 * dv2 - dv1 * du2;
    let (dpdu, dpdv) = if det == 0.0 {
        let (a, b) = coordinate_system(face.as_vec3a());
        (a.as_dvec3(), b.as_dvec3())
    } else {
        let inv = 1.0 / det;
        (
            (dv2 * dp1 - dv1 * dp2) * inv,
            (-du2 * dp1 + du1 * dp2) * inv,
        )
    };
    Base {
        p,
        n,
        uv,
        dpdu,
        dpdv,
    }
}

/// Appends the grid point of barycentric weights `w`: its displaced position and the
/// interpolated channels. Returns 1 when the map's value there is not finite.
#[allow(clippy::too_many_arguments)]
fn push_point(
    out: &mut MeshArrays,
    mesh: &MeshArrays,
    t: [u32; 3],
    b: &Base,
    w: [f64; 3],
    map: &FloatTex,
    m: Micro,
    smooth: bool,
) -> usize {
    let lerp3 = |v: [DVec3; 3]| v[0] * w[0] + v[1] * w[1] + v[2] * w[2];
    let base = lerp3(b.p);
    let n = lerp3(b.n).try_normalize().unwrap_or(b.n[0]);
    let uv = b.uv[0] * w[0] + b.uv[1] * w[1] + b.uv[2] * w[2];
    let value = evaluate_in(map, base, n, uv, (b.dpdu, b.dpdv));
    let bad = usize::from(!value.is_finite());
    let moved = if value.is_finite() {
        value.clamp(-1.0, 1.0) * m.scale + m.offset
    } else {
        0.0
    };
    out.p.push((base + n * moved).as_vec3a());
    if let Some(ns) = out.n.as_mut().filter(|_| smooth) {
        ns.push(tilted_normal(map, base, n, uv, b).as_vec3a());
    }
    let at = |i: usize| t[i] as usize;
    if let (Some(o), Some(_)) = (out.uv.as_mut(), mesh.uv.as_ref()) {
        o.push(uv.as_vec2());
    }
    if let (Some(o), Some(c)) = (out.cols.as_mut(), mesh.cols.as_ref()) {
        let c = [0, 1, 2].map(|i| DVec3::from_array(c[at(i)].map(f64::from)));
        o.push(lerp3(c).as_vec3().to_array());
    }
    if let (Some(o), Some(a)) = (out.alphas.as_mut(), mesh.alphas.as_ref()) {
        let a = [0, 1, 2].map(|i| f64::from(a[at(i)]));
        o.push((a[0] * w[0] + a[1] * w[1] + a[2] * w[2]) as f32);
    }
    bad
}

/// LuxRender's shading normal of a microdisplaced hit at a grid point: `n` tilted by the
/// map's (u, v) derivatives.
fn tilted_normal(map: &FloatTex, base: DVec3, n: DVec3, uv: DVec2, b: &Base) -> DVec3 {
    let ts = n.cross(b.dpdu).try_normalize().unwrap_or(DVec3::ZERO);
    if ts == DVec3::ZERO {
        return n;
    }
    let ss = ts.cross(n) * b.dpdu.length();
    let ts = if b.dpdv.dot(ts) < 0.0 {
        -ts * b.dpdv.length()
    } else {
        ts * b.dpdv.length()
    };
    let nf = n.as_vec3a();
    let (ssf, tsf) = (ss.as_vec3a(), ts.as_vec3a());
    let si = SurfaceInteraction {
        it: Interaction {
            p: base.as_vec3a(),
            n: nf,
            ..Interaction::default()
        },
        wo: nf,
        uv: uv.as_vec2(),
        dpdu: ssf,
        dpdv: tsf,
        shading: Shading {
            n: nf,
            dpdu: ssf,
            dpdv: tsf,
        },
        ..SurfaceInteraction::default()
    };
    let d: Vec2 = map.duv(&si, DUV_DELTA);
    if !(d.x.is_finite() && d.y.is_finite()) {
        return n;
    }
    let du = ss + n * f64::from(d.x);
    let dv = ts + n * f64::from(d.y);
    match du.cross(dv).try_normalize() {
        Some(t) if t.dot(n) < 0.0 => -t,
        Some(t) => t,
        None => n,
    }
}

/// The micro-triangles of one grid whose points start at index `first`, in the base
/// triangle's winding: row k holds the points (j, k), j = 0..=N − k.
fn push_grid(tris: &mut Vec<[u32; 3]>, first: u32, n_seg: u32) {
    // Rows before k hold (N + 1) + N + ... + (N + 2 − k) points.
    let row_start = |k: u32| first + k * (n_seg + 1) - k * k.saturating_sub(1) / 2;
    let index = |j: u32, k: u32| row_start(k) + j;
    for k in 0..n_seg {
        for j in 0..n_seg - k {
            tris.push([index(j, k), index(j + 1, k), index(j, k + 1)]);
            if j + k + 1 < n_seg {
                tris.push([index(j + 1, k), index(j + 1, k + 1), index(j, k + 1)]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::FloatTex;
    use glam::Vec3A;

    fn flat_mesh(normals: bool) -> MeshArrays {
        MeshArrays {
            p: vec![
                Vec3A::new(0.0, 0.0, 0.0),
                Vec3A::new(2.0, 0.0, 0.0),
                Vec3A::new(0.0, 2.0, 0.0),
            ],
            n: normals.then(|| vec![Vec3A::Z; 3]),
            uv: Some(vec![Vec2::ZERO, Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0)]),
            cols: None,
            alphas: None,
            tris: vec![[0, 1, 2]],
        }
    }

    #[test]
    fn grid_has_n_squared_triangles_over_every_point() {
        for n in 1..6u32 {
            let mut tris = Vec::new();
            push_grid(&mut tris, 10, n);
            assert_eq!(tris.len() as u32, n * n);
            let points = (n + 1) * (n + 2) / 2;
            let mut seen = vec![false; points as usize];
            for t in &tris {
                for &i in t {
                    assert!((10..10 + points).contains(&i), "n {n}: index {i}");
                    seen[(i - 10) as usize] = true;
                }
            }
            assert!(seen.iter().all(|&s| s), "n {n}: a point is in no triangle");
        }
    }

    #[test]
    fn a_constant_map_lifts_the_grid_by_scale_times_the_clamped_value_plus_offset() {
        let mesh = flat_mesh(true);
        let m = Micro {
            segments: 4,
            scale: 0.5,
            offset: 0.1,
            smooth: true,
        };
        // 3 is clamped to 1: 1 · 0.5 + 0.1.
        let d = displace(&mesh, false, &FloatTex::constant(3.0), m);
        assert_eq!(d.bad, 0);
        assert_eq!(d.mesh.tris.len(), 16);
        assert_eq!(d.mesh.p.len(), 15);
        for p in &d.mesh.p {
            assert!((p.z - 0.6).abs() < 1e-6, "{p}");
            assert!(p.x >= -1e-6 && p.y >= -1e-6 && p.x + p.y <= 2.0 + 1e-5);
        }
        // A constant map does not tilt the normals; winding stays the base triangle's.
        let ns = d.mesh.n.as_ref().expect("smooth normals");
        assert!(ns.iter().all(|n| (*n - Vec3A::Z).length() < 1e-6));
        for t in &d.mesh.tris {
            let [a, b, c] = t.map(|i| d.mesh.p[i as usize]);
            assert!((b - a).cross(c - a).z > 0.0);
        }
    }

    /// With no displacement the micro-triangles tile the base triangle exactly: their areas
    /// add up to its area, for any number of segments (a wrong index would overlap or leave
    /// holes and change the sum).
    #[test]
    fn undisplaced_micro_triangles_tile_the_base_triangle() {
        let mesh = flat_mesh(false);
        for n in [1, 2, 3, 7] {
            let m = Micro {
                segments: n,
                scale: 0.0,
                offset: 0.0,
                smooth: false,
            };
            let d = displace(&mesh, false, &FloatTex::constant(0.0), m);
            let area: f32 = d
                .mesh
                .tris
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|i| d.mesh.p[i as usize]);
                    0.5 * (b - a).cross(c - a).length()
                })
                .sum();
            assert!((area - 2.0).abs() < 1e-4, "{n} segments: area {area}");
            assert!(d
                .mesh
                .tris
                .iter()
                .all(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2]));
        }
    }

    #[test]
    fn without_normals_the_face_normal_follows_the_flip_and_shading_is_flat() {
        let mesh = flat_mesh(false);
        let m = Micro {
            segments: 2,
            scale: 1.0,
            offset: 0.0,
            smooth: true,
        };
        let up = displace(&mesh, false, &FloatTex::constant(0.25), m);
        let down = displace(&mesh, true, &FloatTex::constant(0.25), m);
        assert!(up.mesh.n.is_none());
        assert!(up.mesh.p.iter().all(|p| (p.z - 0.25).abs() < 1e-6));
        assert!(down.mesh.p.iter().all(|p| (p.z + 0.25).abs() < 1e-6));
    }

    #[test]
    fn counts_are_checked_before_anything_is_built() {
        assert_eq!(micro_count(10, 3, 1000), Some(90));
        assert_eq!(micro_count(10, 11, 1000), None);
        // One segment: 3 points per triangle, over the limit before the triangles are.
        assert_eq!(micro_count(400, 1, 1000), None);
        assert_eq!(micro_count(usize::MAX, u32::MAX, u64::MAX), None);
    }
}
