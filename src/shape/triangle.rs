//! Watertight ray/triangle intersection (Woop et al., as analysed in pbrt) with a conservative
//! lower bound on the hit distance, so that a ray leaving a triangle from outside the hit
//! point's error box never re-hits it, whatever the scene's scale.

use crate::geometry::transform::gamma;
use glam::{DVec3, Vec3A};

/// Hit distance and barycentric coordinates of a ray/triangle intersection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriHit {
    pub t: f32,
    pub b: [f32; 3],
}

#[inline(always)]
fn permute(v: Vec3A, kx: usize, ky: usize, kz: usize) -> Vec3A {
    Vec3A::new(v[kx], v[ky], v[kz])
}

/// Edge function in f64, for the rare exact-zero f32 case (edges through the ray).
#[inline(never)]
fn edge64(a: Vec3A, b: Vec3A) -> f32 {
    let (a, b) = (
        DVec3::new(a.x as f64, a.y as f64, 0.0),
        DVec3::new(b.x as f64, b.y as f64, 0.0),
    );
    (a.x * b.y - a.y * b.x) as f32
}

/// Intersects the ray `o + t d`, `0 < t < t_max`, with triangle (p0, p1, p2).
#[inline(always)]
pub fn intersect(p: &[Vec3A; 3], o: Vec3A, d: Vec3A, t_max: f32) -> Option<TriHit> {
    // Translate to the ray origin, permute so that z is the dominant direction, shear.
    let ad = d.abs();
    let kz = if ad.x > ad.y {
        if ad.x > ad.z {
            0
        } else {
            2
        }
    } else if ad.y > ad.z {
        1
    } else {
        2
    };
    let kx = if kz == 2 { 0 } else { kz + 1 };
    let ky = if kx == 2 { 0 } else { kx + 1 };
    let d = permute(d, kx, ky, kz);
    let mut p0t = permute(p[0] - o, kx, ky, kz);
    let mut p1t = permute(p[1] - o, kx, ky, kz);
    let mut p2t = permute(p[2] - o, kx, ky, kz);
    let sz = 1.0 / d.z;
    let sx = -d.x * sz;
    let sy = -d.y * sz;
    p0t.x += sx * p0t.z;
    p0t.y += sy * p0t.z;
    p1t.x += sx * p1t.z;
    p1t.y += sy * p1t.z;
    p2t.x += sx * p2t.z;
    p2t.y += sy * p2t.z;

    let mut e0 = p1t.x * p2t.y - p1t.y * p2t.x;
    let mut e1 = p2t.x * p0t.y - p2t.y * p0t.x;
    let mut e2 = p0t.x * p1t.y - p0t.y * p1t.x;
    if e0 == 0.0 || e1 == 0.0 || e2 == 0.0 {
        e0 = edge64(p1t, p2t);
        e1 = edge64(p2t, p0t);
        e2 = edge64(p0t, p1t);
    }
    if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
        return None;
    }
    let det = e0 + e1 + e2;
    if det == 0.0 {
        return None;
    }
    p0t.z *= sz;
    p1t.z *= sz;
    p2t.z *= sz;
    let t_scaled = e0 * p0t.z + e1 * p1t.z + e2 * p2t.z;
    if det < 0.0 && (t_scaled >= 0.0 || t_scaled < t_max * det) {
        return None;
    }
    if det > 0.0 && (t_scaled <= 0.0 || t_scaled > t_max * det) {
        return None;
    }
    let inv_det = 1.0 / det;
    let t = t_scaled * inv_det;
    if t >= t_max {
        return None;
    }

    // Conservative bound on the error of t: reject hits that could be behind the origin.
    let max_zt = Vec3A::new(p0t.z, p1t.z, p2t.z).abs().max_element();
    let delta_z = gamma(3) * max_zt;
    let max_xt = Vec3A::new(p0t.x, p1t.x, p2t.x).abs().max_element();
    let max_yt = Vec3A::new(p0t.y, p1t.y, p2t.y).abs().max_element();
    let delta_x = gamma(5) * (max_xt + max_zt);
    let delta_y = gamma(5) * (max_yt + max_zt);
    let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let max_e = Vec3A::new(e0, e1, e2).abs().max_element();
    let delta_t =
        3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv_det.abs();
    if t <= delta_t {
        return None;
    }
    Some(TriHit {
        t,
        b: [e0 * inv_det, e1 * inv_det, e2 * inv_det],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRI: [Vec3A; 3] = [
        Vec3A::new(0.0, 0.0, 0.0),
        Vec3A::new(1.0, 0.0, 0.0),
        Vec3A::new(0.0, 1.0, 0.0),
    ];

    #[test]
    fn hits_inside_misses_outside() {
        let h = intersect(&TRI, Vec3A::new(0.25, 0.25, 1.0), -Vec3A::Z, f32::INFINITY).unwrap();
        assert!((h.t - 1.0).abs() < 1e-6);
        assert!((h.b[0] - 0.5).abs() < 1e-6 && (h.b[1] - 0.25).abs() < 1e-6);
        assert!(intersect(&TRI, Vec3A::new(0.75, 0.75, 1.0), -Vec3A::Z, f32::INFINITY).is_none());
        assert!(intersect(&TRI, Vec3A::new(0.25, 0.25, 1.0), -Vec3A::Z, 0.5).is_none());
        assert!(intersect(&TRI, Vec3A::new(0.25, 0.25, 1.0), Vec3A::Z, f32::INFINITY).is_none());
    }

    #[test]
    fn shared_edge_is_watertight() {
        // Two triangles sharing the diagonal of a unit square: a ray through the diagonal
        // hits exactly one or both, never neither.
        let other = [TRI[1], Vec3A::new(1.0, 1.0, 0.0), TRI[2]];
        for i in 0..1000 {
            let s = 0.01 + 0.98 * i as f32 / 1000.0;
            let o = Vec3A::new(s, 1.0 - s, 1.0);
            let d = Vec3A::new(0.001 * s, -0.002, -1.0);
            let a = intersect(&TRI, o, d, f32::INFINITY).is_some();
            let b = intersect(&other, o, d, f32::INFINITY).is_some();
            assert!(a || b, "ray {i} leaked through the shared edge");
        }
    }
}
