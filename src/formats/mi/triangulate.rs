//! Triangulation of mental ray polygons: convex ones (`c`) as fans, general ones (`p`, which
//! may be concave and have `hole` loops) by ear clipping in the polygon's plane, holes first
//! bridged into the outer loop. Triangles keep the polygon's winding (its normal side).
//!
//! ```text
//! loop points (outer, then holes) --Newell normal, project to 2D--> bridge holes
//!     --ear clipping--> triangles (indices into the loop points)
//! ```
//!
//! Ear clipping costs O(n²) per polygon: polygons larger than [`MAX_EAR_CLIP`] vertices are
//! fanned instead (correct when convex), and the caller says so.

use glam::{DVec2, DVec3};

/// Largest polygon (with its holes) triangulated by ear clipping.
pub const MAX_EAR_CLIP: usize = 1024;

/// How a polygon was triangulated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    Fan,
    EarClipped,
    /// Too large or degenerate for ear clipping: fanned (holes dropped).
    FannedFallback,
}

/// Triangles over `points` (the outer loop's `outer` points, then each hole's, with the
/// lengths in `holes`), as indices into `points`, in the outer loop's winding.
pub fn triangulate(
    points: &[DVec3],
    outer: usize,
    holes: &[usize],
    convex: bool,
) -> (Vec<[u32; 3]>, Method) {
    let outer = outer.min(points.len());
    if outer < 3 {
        return (Vec::new(), Method::Fan);
    }
    if (convex || outer == 3) && holes.is_empty() {
        return (fan(outer), Method::Fan);
    }
    if points.len() > MAX_EAR_CLIP {
        return (fan(outer), Method::FannedFallback);
    }
    let normal = newell(&points[..outer]);
    let Some(flat) = project(points, normal) else {
        return (fan(outer), Method::FannedFallback);
    };
    // Work counter-clockwise in the projection; hole loops run clockwise.
    let mut ring: Vec<u32> = (0..outer as u32).collect();
    let ccw = signed_area(&flat, &ring) > 0.0;
    if !ccw {
        ring.reverse();
    }
    let mut start = outer;
    let mut hole_rings = Vec::new();
    for &len in holes {
        let end = (start + len).min(points.len());
        let mut h: Vec<u32> = (start as u32..end as u32).collect();
        if h.len() >= 3 {
            if signed_area(&flat, &h) > 0.0 {
                h.reverse();
            }
            hole_rings.push(h);
        }
        start = end;
    }
    // Rightmost holes first, so later bridges do not cross earlier ones.
    hole_rings.sort_by(|a, b| max_x(&flat, b).total_cmp(&max_x(&flat, a)));
    for h in hole_rings {
        if !bridge(&flat, &mut ring, &h) {
            return (fan(outer), Method::FannedFallback);
        }
    }
    let mut tris = ear_clip(&flat, ring);
    if !ccw {
        for t in &mut tris {
            t.swap(1, 2);
        }
    }
    (tris, Method::EarClipped)
}

fn fan(n: usize) -> Vec<[u32; 3]> {
    (1..n as u32 - 1).map(|i| [0, i, i + 1]).collect()
}

/// Newell's normal of a loop (any length; zero when degenerate).
fn newell(p: &[DVec3]) -> DVec3 {
    let mut n = DVec3::ZERO;
    for (i, a) in p.iter().enumerate() {
        let b = p[(i + 1) % p.len()];
        n.x += (a.y - b.y) * (a.z + b.z);
        n.y += (a.z - b.z) * (a.x + b.x);
        n.z += (a.x - b.x) * (a.y + b.y);
    }
    n
}

/// The points in the plane of `normal`, seen from its side (counter-clockwise about it).
fn project(points: &[DVec3], normal: DVec3) -> Option<Vec<DVec2>> {
    let a = normal.abs();
    if !normal.is_finite() || a.max_element() <= 0.0 {
        return None;
    }
    let flat = points.iter().map(|p| {
        if a.z >= a.x && a.z >= a.y {
            DVec2::new(p.x, p.y) * DVec2::new(1.0, normal.z.signum())
        } else if a.x >= a.y {
            DVec2::new(p.y, p.z) * DVec2::new(1.0, normal.x.signum())
        } else {
            DVec2::new(p.z, p.x) * DVec2::new(1.0, normal.y.signum())
        }
    });
    Some(flat.collect())
}

fn signed_area(p: &[DVec2], ring: &[u32]) -> f64 {
    let mut a = 0.0;
    for (i, &k) in ring.iter().enumerate() {
        let (u, v) = (p[k as usize], p[ring[(i + 1) % ring.len()] as usize]);
        a += u.x * v.y - v.x * u.y;
    }
    0.5 * a
}

fn max_x(p: &[DVec2], ring: &[u32]) -> f64 {
    ring.iter()
        .map(|&k| p[k as usize].x)
        .fold(f64::NEG_INFINITY, f64::max)
}

fn cross(o: DVec2, a: DVec2, b: DVec2) -> f64 {
    (a - o).perp_dot(b - o)
}

/// Whether segments ab and cd cross at a point inside both (touching ends do not count).
fn segments_cross(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let d1 = cross(c, d, a);
    let d2 = cross(c, d, b);
    let d3 = cross(a, b, c);
    let d4 = cross(a, b, d);
    (d1 * d2 < 0.0) && (d3 * d4 < 0.0)
}

/// Splices `hole` into `ring` through the shortest segment from the hole's rightmost vertex
/// to a ring vertex that crosses no edge.
fn bridge(p: &[DVec2], ring: &mut Vec<u32>, hole: &[u32]) -> bool {
    let Some(hi) =
        (0..hole.len()).max_by(|&a, &b| p[hole[a] as usize].x.total_cmp(&p[hole[b] as usize].x))
    else {
        return false;
    };
    let m = p[hole[hi] as usize];
    let edges = |ring: &[u32]| -> Vec<(DVec2, DVec2)> {
        let mut e: Vec<(DVec2, DVec2)> = (0..ring.len())
            .map(|i| (p[ring[i] as usize], p[ring[(i + 1) % ring.len()] as usize]))
            .collect();
        e.extend(
            (0..hole.len()).map(|i| (p[hole[i] as usize], p[hole[(i + 1) % hole.len()] as usize])),
        );
        e
    };
    let all = edges(ring);
    let best = (0..ring.len())
        .filter(|&i| {
            let q = p[ring[i] as usize];
            !all.iter().any(|&(a, b)| segments_cross(m, q, a, b))
        })
        .min_by(|&a, &b| {
            let da = (p[ring[a] as usize] - m).length_squared();
            let db = (p[ring[b] as usize] - m).length_squared();
            da.total_cmp(&db)
        });
    let Some(bi) = best else {
        return false;
    };
    let mut spliced = Vec::with_capacity(ring.len() + hole.len() + 2);
    spliced.extend_from_slice(&ring[..=bi]);
    spliced.extend((0..=hole.len()).map(|k| hole[(hi + k) % hole.len()]));
    spliced.push(ring[bi]);
    spliced.extend_from_slice(&ring[bi + 1..]);
    *ring = spliced;
    true
}

/// Whether `q` lies inside or on triangle abc (counter-clockwise).
fn in_triangle(q: DVec2, a: DVec2, b: DVec2, c: DVec2) -> bool {
    cross(a, b, q) >= 0.0 && cross(b, c, q) >= 0.0 && cross(c, a, q) >= 0.0
}

/// Clips ears off a counter-clockwise ring (bridges may repeat vertices).
fn ear_clip(p: &[DVec2], mut ring: Vec<u32>) -> Vec<[u32; 3]> {
    let mut tris = Vec::with_capacity(ring.len().saturating_sub(2));
    let mut guard = 0;
    let mut i = 0;
    while ring.len() > 3 {
        let n = ring.len();
        let (ia, ib, ic) = ((i + n - 1) % n, i % n, (i + 1) % n);
        let (a, b, c) = (ring[ia], ring[ib], ring[ic]);
        let (pa, pb, pc) = (p[a as usize], p[b as usize], p[c as usize]);
        let convex = cross(pa, pb, pc) > 0.0;
        let is_ear = convex
            && !ring.iter().any(|&k| {
                let q = p[k as usize];
                k != a
                    && k != b
                    && k != c
                    && q != pa
                    && q != pb
                    && q != pc
                    && in_triangle(q, pa, pb, pc)
            });
        if is_ear {
            tris.push([a, b, c]);
            ring.remove(ib);
            guard = 0;
            i = ib.min(ring.len() - 1);
        } else {
            i = (i + 1) % n;
            guard += 1;
            if guard > n {
                // No ear (collinear or self-touching remains): fan what is left.
                for k in 1..ring.len() - 1 {
                    tris.push([ring[0], ring[k], ring[k + 1]]);
                }
                return tris;
            }
        }
    }
    if ring.len() == 3 {
        tris.push([ring[0], ring[1], ring[2]]);
    }
    tris
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(points: &[DVec3], tris: &[[u32; 3]]) -> DVec3 {
        tris.iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| points[i as usize]);
                0.5 * (b - a).cross(c - a)
            })
            .sum()
    }

    fn pts(xy: &[(f64, f64)]) -> Vec<DVec3> {
        xy.iter().map(|&(x, y)| DVec3::new(x, y, 1.0)).collect()
    }

    #[test]
    fn concave_polygons_keep_area_and_winding() {
        // An L shape, counter-clockwise seen from +z: area 3.
        let l = pts(&[(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]);
        let (t, m) = triangulate(&l, 6, &[], false);
        assert_eq!(m, Method::EarClipped);
        assert_eq!(t.len(), 4);
        assert!((area(&l, &t) - DVec3::new(0.0, 0.0, 3.0)).length() < 1e-12);
        // The same loop clockwise: the area vector flips with it.
        let mut r = l.clone();
        r.reverse();
        let (t, _) = triangulate(&r, 6, &[], false);
        assert!((area(&r, &t) - DVec3::new(0.0, 0.0, -3.0)).length() < 1e-12);
    }

    #[test]
    fn holes_are_cut_out() {
        // A 4×4 square with a 2×2 hole: area 12, in a plane facing −x.
        let yz = |y: f64, z: f64| DVec3::new(5.0, y, z);
        let mut p = vec![yz(0., 0.), yz(0., 4.), yz(4., 4.), yz(4., 0.)];
        p.extend([yz(1., 1.), yz(3., 1.), yz(3., 3.), yz(1., 3.)]);
        let (t, m) = triangulate(&p, 4, &[4], false);
        assert_eq!(m, Method::EarClipped);
        let a = area(&p, &t);
        assert!((a.length() - 12.0).abs() < 1e-9, "{a}");
        assert!(a.x < 0.0, "keeps the outer loop's facing: {a}");
        // No triangle covers the hole's centre.
        for tri in &t {
            let [a, b, c] = tri.map(|i| DVec2::new(p[i as usize].y, p[i as usize].z));
            let q = DVec2::new(2.0, 2.0);
            let s = [cross(a, b, q), cross(b, c, q), cross(c, a, q)];
            assert!(!(s.iter().all(|x| *x > 0.0) || s.iter().all(|x| *x < 0.0)));
        }
    }

    #[test]
    fn degenerate_and_convex_polygons() {
        let line = pts(&[(0., 0.), (1., 0.), (2., 0.), (3., 0.)]);
        let (t, m) = triangulate(&line, 4, &[], false);
        assert_eq!((t.len(), m), (2, Method::FannedFallback));
        let quad = pts(&[(0., 0.), (1., 0.), (1., 1.), (0., 1.)]);
        assert_eq!(
            triangulate(&quad, 4, &[], true),
            (vec![[0, 1, 2], [0, 2, 3]], Method::Fan)
        );
        assert!(triangulate(&quad, 2, &[], false).0.is_empty());
    }
}
