//! Triangulating n-gons, concave and non-planar ones included.
//!
//! ```text
//! polygon corners (3-D) --Newell normal--> plane --project--> 2-D polygon --ear clipping-->
//!   triangles (indices into the corner list, in the polygon's own rotational order)
//! ```
//!
//! The plane is the one Newell's method fits to the corners, which is well defined for
//! non-planar polygons too. Ear clipping removes, one at a time, a convex corner whose
//! triangle holds no other corner, so concave polygons come out right. A polygon without a
//! usable plane (collinear or repeated corners) is fanned from its first corner; degenerate
//! ears are dropped rather than emitted. Triangles keep the polygon's winding: callers that
//! mirror the coordinates reverse each triangle themselves.

use glam::{DVec2, DVec3};

/// Newell's normal of a polygon (not normalised; zero when the polygon has no area).
pub fn newell_normal(pts: &[DVec3]) -> DVec3 {
    let mut n = DVec3::ZERO;
    for (i, a) in pts.iter().enumerate() {
        let b = pts[(i + 1) % pts.len()];
        n.x += (a.y - b.y) * (a.z + b.z);
        n.y += (a.z - b.z) * (a.x + b.x);
        n.z += (a.x - b.x) * (a.y + b.y);
    }
    n
}

/// Triangles of the polygon with corners `pts`, as index triples into `pts`.
pub fn triangulate(pts: &[DVec3]) -> Vec<[usize; 3]> {
    let n = pts.len();
    if n < 3 {
        return Vec::new();
    }
    if n == 3 {
        return vec![[0, 1, 2]];
    }
    let normal = newell_normal(pts);
    let len = normal.length();
    if len <= 0.0 || !len.is_finite() {
        return fan(n);
    }
    let w = normal / len;
    let u = w.any_orthonormal_vector();
    let v = w.cross(u);
    let p2: Vec<DVec2> = pts.iter().map(|p| DVec2::new(p.dot(u), p.dot(v))).collect();
    ear_clip(&p2)
}

/// Triangles fanned from corner 0.
fn fan(n: usize) -> Vec<[usize; 3]> {
    (1..n - 1).map(|i| [0, i, i + 1]).collect()
}

/// Twice the signed area of triangle abc.
fn cross(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

fn ear_clip(p: &[DVec2]) -> Vec<[usize; 3]> {
    let n = p.len();
    let area: f64 = (0..n).map(|i| p[i].perp_dot(p[(i + 1) % n])).sum();
    if area == 0.0 {
        return fan(n);
    }
    let sign = area.signum();
    let scale = p
        .iter()
        .map(|q| q.abs().max_element())
        .fold(0.0f64, f64::max)
        .max(1e-300);
    let eps = 1e-12 * scale * scale;
    let mut ring: Vec<usize> = (0..n).collect();
    let mut out = Vec::with_capacity(n - 2);
    let mut guard = 0usize;
    while ring.len() > 3 && guard < 2 * n * n {
        guard += 1;
        let m = ring.len();
        let mut clipped = false;
        for k in 0..m {
            let (a, b, c) = (ring[(k + m - 1) % m], ring[k], ring[(k + 1) % m]);
            let turn = cross(p[a], p[b], p[c]) * sign;
            if turn <= eps {
                continue;
            }
            let blocked = ring
                .iter()
                .any(|&q| q != a && q != b && q != c && inside(p[q], p[a], p[b], p[c], sign));
            if blocked {
                continue;
            }
            out.push([a, b, c]);
            ring.remove(k);
            clipped = true;
            break;
        }
        if !clipped {
            // Numerically stuck (self-intersecting or degenerate input): drop a corner that
            // adds no area, else clip the most convex corner.
            let m = ring.len();
            let best = (0..m)
                .max_by(|&i, &j| {
                    let t = |k: usize| {
                        cross(p[ring[(k + m - 1) % m]], p[ring[k]], p[ring[(k + 1) % m]]) * sign
                    };
                    t(i).total_cmp(&t(j))
                })
                .unwrap_or(0);
            let (a, b, c) = (ring[(best + m - 1) % m], ring[best], ring[(best + 1) % m]);
            if cross(p[a], p[b], p[c]).abs() > eps {
                out.push([a, b, c]);
            }
            ring.remove(best);
        }
    }
    if ring.len() == 3 && cross(p[ring[0]], p[ring[1]], p[ring[2]]).abs() > eps {
        out.push([ring[0], ring[1], ring[2]]);
    }
    out
}

/// Whether q is inside or on triangle abc (oriented by `sign`).
fn inside(q: DVec2, a: DVec2, b: DVec2, c: DVec2, sign: f64) -> bool {
    cross(a, b, q) * sign >= 0.0 && cross(b, c, q) * sign >= 0.0 && cross(c, a, q) * sign >= 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(pts: &[DVec3], tris: &[[usize; 3]]) -> f64 {
        tris.iter()
            .map(|t| {
                0.5 * (pts[t[1]] - pts[t[0]])
                    .cross(pts[t[2]] - pts[t[0]])
                    .length()
            })
            .sum()
    }

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    #[test]
    fn concave_polygon_is_covered_exactly_once() {
        // An L shape of area 3 (unit squares), concave at (1, 1).
        let pts = [
            v(0.0, 0.0, 0.0),
            v(2.0, 0.0, 0.0),
            v(2.0, 1.0, 0.0),
            v(1.0, 1.0, 0.0),
            v(1.0, 2.0, 0.0),
            v(0.0, 2.0, 0.0),
        ];
        let tris = triangulate(&pts);
        assert_eq!(tris.len(), 4);
        assert!((area(&pts, &tris) - 3.0).abs() < 1e-12);
        // every triangle keeps the polygon's orientation (+z here)
        for t in &tris {
            let n = (pts[t[1]] - pts[t[0]]).cross(pts[t[2]] - pts[t[0]]);
            assert!(n.z > 0.0, "{t:?}");
        }
    }

    #[test]
    fn clockwise_polygons_keep_their_winding() {
        let pts = [
            v(0.0, 0.0, 0.0),
            v(0.0, 1.0, 0.0),
            v(1.0, 1.0, 0.0),
            v(1.0, 0.0, 0.0),
        ];
        for t in triangulate(&pts) {
            let n = (pts[t[1]] - pts[t[0]]).cross(pts[t[2]] - pts[t[0]]);
            assert!(n.z < 0.0);
        }
    }

    #[test]
    fn non_planar_quad_gives_two_triangles() {
        let pts = [
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.2),
            v(1.0, 1.0, 0.0),
            v(0.0, 1.0, 0.3),
        ];
        let tris = triangulate(&pts);
        assert_eq!(tris.len(), 2);
        let mut used: Vec<usize> = tris.iter().flatten().copied().collect();
        used.sort_unstable();
        used.dedup();
        assert_eq!(used, vec![0, 1, 2, 3]);
    }

    #[test]
    fn degenerate_polygons_do_not_panic() {
        assert!(triangulate(&[v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0)]).is_empty());
        let line = [
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(2.0, 0.0, 0.0),
            v(3.0, 0.0, 0.0),
        ];
        assert_eq!(triangulate(&line).len(), 2);
        let same = [v(1.0, 1.0, 1.0); 5];
        assert_eq!(triangulate(&same).len(), 3);
        // a bow tie (self-intersecting)
        let bow = [
            v(0.0, 0.0, 0.0),
            v(1.0, 1.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(0.0, 1.0, 0.0),
        ];
        assert!(triangulate(&bow).len() <= 2);
    }
}
