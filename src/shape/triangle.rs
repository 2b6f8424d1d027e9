//! Watertight ray/triangle intersection (Woop et al., as analysed in pbrt) with a conservative
//! lower bound on the hit distance, so that a ray leaving a triangle from outside the hit
//! point's error box never re-hits it, whatever the scene's scale.

use crate::geometry::transform::gamma;
use glam::{Mat3A, Vec3A, Vec3Swizzles};

/// Hit distance and barycentric coordinates of a ray/triangle intersection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriHit {
    pub t: f32,
    pub b: [f32; 3],
}

/// Edge function in f64, for the rare exact-zero f32 case (edges through the ray).
#[inline(never)]
fn edge64(ax: f32, ay: f32, bx: f32, by: f32) -> f32 {
    (f64::from(ax) * f64::from(by) - f64::from(ay) * f64::from(bx)) as f32
}

/// Permutes `(x, y, z)` so that axis `kz` comes last, keeping the cyclic order (the
/// permutation pbrt's test uses: kx = kz + 1, ky = kx + 1, mod 3).
#[inline(always)]
fn cycle<T>(kz: usize, x: T, y: T, z: T) -> (T, T, T) {
    match kz {
        0 => (y, z, x),
        1 => (z, x, y),
        _ => (x, y, z),
    }
}

/// The axis of the largest component of `d` (the test's z after permutation; ties go to
/// the later axis).
#[inline(always)]
pub fn dominant_axis(d: Vec3A) -> usize {
    let ad = d.abs();
    if ad.x > ad.y {
        if ad.x > ad.z {
            0
        } else {
            2
        }
    } else if ad.y > ad.z {
        1
    } else {
        2
    }
}

/// The test's (x, y, z) axes for dominant axis `kz`: the cyclic permutation the scalar test uses.
#[inline(always)]
pub fn ray_axes(kz: usize) -> [usize; 3] {
    let (x, y, z) = cycle(kz, 0, 1, 2);
    [x, y, z]
}

/// Intersects the ray `o + t d`, `0 < t < t_max`, with triangle (p0, p1, p2).
///
/// The three vertices are processed as columns (lane i of `xs`, `ys`, `zs` is vertex i in
/// ray space), so the shear and the edge functions are vector operations; every lane does the
/// same f32 operations in the same order as the scalar formulation, and the inside test is
/// branch-free (mispredicted sign branches dominated the scalar version's profile).
#[inline(always)]
pub fn intersect(p: &[Vec3A; 3], o: Vec3A, d: Vec3A, t_max: f32) -> Option<TriHit> {
    // Translate to the ray origin, permute so that z is the dominant direction, shear.
    let kz = dominant_axis(d);
    let cols = Mat3A::from_cols(p[0] - o, p[1] - o, p[2] - o).transpose();
    let (mut xs, mut ys, zs) = cycle(kz, cols.x_axis, cols.y_axis, cols.z_axis);
    let (dx, dy, dz) = cycle(kz, d.x, d.y, d.z);
    let sz = 1.0 / dz;
    let sx = -dx * sz;
    let sy = -dy * sz;
    xs += Vec3A::splat(sx) * zs;
    ys += Vec3A::splat(sy) * zs;

    // Lane i: the edge function of the edge opposite vertex i.
    let mut e = xs.yzx() * ys.zxy() - ys.yzx() * xs.zxy();
    if e.cmpeq(Vec3A::ZERO).any() {
        e = Vec3A::new(
            edge64(xs.y, ys.y, xs.z, ys.z),
            edge64(xs.z, ys.z, xs.x, ys.x),
            edge64(xs.x, ys.x, xs.y, ys.y),
        );
    }
    let outside = e.cmplt(Vec3A::ZERO).any() & e.cmpgt(Vec3A::ZERO).any();
    let det = e.x + e.y + e.z;
    if outside | (det == 0.0) {
        return None;
    }
    let zs = zs * sz;
    let ez = e * zs;
    let t_scaled = ez.x + ez.y + ez.z;
    let bad_neg = (det < 0.0) & ((t_scaled >= 0.0) | (t_scaled < t_max * det));
    let bad_pos = (det > 0.0) & ((t_scaled <= 0.0) | (t_scaled > t_max * det));
    if bad_neg | bad_pos {
        return None;
    }
    let inv_det = 1.0 / det;
    let t = t_scaled * inv_det;
    // Written so that a NaN distance (or t_max) is a miss, as in the SIMD packet test.
    let in_range = t < t_max;
    if !in_range {
        return None;
    }

    // Conservative bound on the error of t: reject hits that could be behind the origin.
    let max_zt = zs.abs().max_element();
    let delta_z = gamma(3) * max_zt;
    let max_xt = xs.abs().max_element();
    let max_yt = ys.abs().max_element();
    let delta_x = gamma(5) * (max_xt + max_zt);
    let delta_y = gamma(5) * (max_yt + max_zt);
    let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let max_e = e.abs().max_element();
    let delta_t =
        3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv_det.abs();
    if t <= delta_t {
        return None;
    }
    Some(TriHit {
        t,
        b: [e.x * inv_det, e.y * inv_det, e.z * inv_det],
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
