//! Four triangles against one ray at once: the watertight test of [`triangle::intersect`]
//! with one triangle per SIMD lane.
//!
//! Every lane does the same f32 operations in the same order as the scalar test, so a lane's
//! verdict, distance and barycentrics are the scalar test's bit for bit. The rare case the
//! scalar test settles in f64 (an edge function exactly zero: an edge through the ray) is
//! handed to it for the whole packet. The per-ray part of the test (dominant axis, shear)
//! is computed once per ray in [`RayTri`].
//!
//! BVH leaves of up to four triangles become one packet (see [`super::blas`]): a leaf costs
//! one vector test instead of one scalar test per triangle, which also makes larger leaves
//! (fewer node visits) pay.

use crate::geometry::transform::gamma;
use crate::shape::triangle::{self, dominant_axis, ray_axes, TriHit};
use glam::{Vec3A, Vec4};

/// Triangles per packet.
pub const LANES: usize = 4;

/// Per-ray constants of the packet test.
pub struct RayTri {
    pub o: Vec3A,
    pub d: Vec3A,
    /// The test's x, y and z axes (z dominant in `d`).
    k: [usize; 3],
    /// The origin's coordinates on those axes.
    ok: [Vec4; 3],
    /// The shear: -dx/dz, -dy/dz and 1/dz.
    s: [Vec4; 3],
}

impl RayTri {
    pub fn new(o: Vec3A, d: Vec3A) -> RayTri {
        let k = ray_axes(dominant_axis(d));
        let sz = 1.0 / d[k[2]];
        let sx = -d[k[0]] * sz;
        let sy = -d[k[1]] * sz;
        RayTri {
            o,
            d,
            k,
            ok: k.map(|a| Vec4::splat(o[a])),
            s: [Vec4::splat(sx), Vec4::splat(sy), Vec4::splat(sz)],
        }
    }
}

/// Up to four triangles, coordinates in SoA lanes.
#[derive(Clone, Debug)]
pub struct Tri4 {
    /// `p[i][a]`: coordinate `a` of vertex `i`, one triangle per lane (NaN in empty lanes).
    p: [[Vec4; 3]; 3],
    /// Lanes holding a triangle.
    valid: u32,
}

/// The closest triangle of a packet hit by a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tri4Hit {
    pub lane: usize,
    pub t: f32,
    pub b: [f32; 3],
}

/// Lane results of the packet test.
struct Lanes {
    hit: u32,
    t: Vec4,
    e: [Vec4; 3],
    inv_det: Vec4,
}

impl Tri4 {
    /// A packet of `tris[lane]` (None: an empty lane). A triangle with two equal vertices
    /// is kept (for [`Self::vertices`]) but never tested: the scalar test cannot hit it (the
    /// edge between the equal vertices is exactly zero and the other two cancel), and its
    /// zero edge function would send every ray through the packet to the f64 fallback.
    pub fn new(tris: [Option<[Vec3A; 3]>; LANES]) -> Tri4 {
        let mut p = [[Vec4::NAN; 3]; 3];
        let mut valid = 0;
        for (lane, v) in tris.iter().enumerate() {
            let Some(v) = v else { continue };
            if v[0] != v[1] && v[1] != v[2] && v[2] != v[0] {
                valid |= 1 << lane;
            }
            for (i, vi) in v.iter().enumerate() {
                for a in 0..3 {
                    p[i][a][lane] = vi[a];
                }
            }
        }
        Tri4 { p, valid }
    }

    /// The lanes tested (holding a triangle with three distinct vertices), as a bit mask.
    pub fn lanes(&self) -> u32 {
        self.valid
    }

    /// The vertices of the triangle in `lane` (NaN for an empty lane).
    pub fn vertices(&self, lane: usize) -> [Vec3A; 3] {
        let p = &self.p;
        [0, 1, 2].map(|i| Vec3A::new(p[i][0][lane], p[i][1][lane], p[i][2][lane]))
    }

    /// The closest hit with 0 < t < t_max (the lowest lane among equal distances).
    #[inline(always)]
    pub fn closest(&self, r: &RayTri, t_max: f32) -> Option<Tri4Hit> {
        let Some(l) = self.test(r, t_max) else {
            return self.closest_scalar(r, t_max);
        };
        let mut mask = l.hit;
        if mask == 0 {
            return None;
        }
        let ts = l.t.to_array();
        let mut lane = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        while mask != 0 {
            let k = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            if ts[k] < ts[lane] {
                lane = k;
            }
        }
        let inv = l.inv_det[lane];
        Some(Tri4Hit {
            lane,
            t: ts[lane],
            b: [l.e[0][lane] * inv, l.e[1][lane] * inv, l.e[2][lane] * inv],
        })
    }

    /// Whether any triangle is hit with 0 < t < t_max.
    #[inline(always)]
    pub fn any(&self, r: &RayTri, t_max: f32) -> bool {
        match self.test(r, t_max) {
            Some(l) => l.hit != 0,
            None => self.closest_scalar(r, t_max).is_some(),
        }
    }

    /// The scalar test lane by lane (for packets with an exactly zero edge function).
    #[inline(never)]
    fn closest_scalar(&self, r: &RayTri, t_max: f32) -> Option<Tri4Hit> {
        let mut best: Option<Tri4Hit> = None;
        for lane in (0..LANES).filter(|l| self.valid & (1 << l) != 0) {
            let bound = best.map_or(t_max, |b| b.t);
            if let Some(TriHit { t, b }) =
                triangle::intersect(&self.vertices(lane), r.o, r.d, t_max)
            {
                if t < bound {
                    best = Some(Tri4Hit { lane, t, b });
                }
            }
        }
        best
    }

    /// The scalar test's steps on all lanes; None when a valid lane has an edge function
    /// that is exactly zero (the scalar test recomputes those in f64).
    #[inline(always)]
    fn test(&self, r: &RayTri, t_max: f32) -> Option<Lanes> {
        let [kx, ky, kz] = r.k;
        let [sx, sy, sz] = r.s;
        let mut xs = [Vec4::ZERO; 3];
        let mut ys = [Vec4::ZERO; 3];
        let mut zs = [Vec4::ZERO; 3];
        for i in 0..3 {
            let pz = self.p[i][kz] - r.ok[2];
            xs[i] = (self.p[i][kx] - r.ok[0]) + sx * pz;
            ys[i] = (self.p[i][ky] - r.ok[1]) + sy * pz;
            zs[i] = pz;
        }
        // Lane-wise edge functions: e[i] is the edge opposite vertex i.
        let e = [
            xs[1] * ys[2] - ys[1] * xs[2],
            xs[2] * ys[0] - ys[2] * xs[0],
            xs[0] * ys[1] - ys[0] * xs[1],
        ];
        let zero = Vec4::ZERO;
        let any_zero = e[0].cmpeq(zero) | e[1].cmpeq(zero) | e[2].cmpeq(zero);
        if any_zero.bitmask() & self.valid != 0 {
            return None;
        }
        let neg = e[0].cmplt(zero) | e[1].cmplt(zero) | e[2].cmplt(zero);
        let pos = e[0].cmpgt(zero) | e[1].cmpgt(zero) | e[2].cmpgt(zero);
        let det = e[0] + e[1] + e[2];
        let miss = Lanes {
            hit: 0,
            t: Vec4::ZERO,
            e,
            inv_det: Vec4::ZERO,
        };
        // Most packets miss: leave before the distance when no lane is inside its edges.
        let inside = !((neg & pos) | det.cmpeq(zero));
        if inside.bitmask() & self.valid == 0 {
            return Some(miss);
        }
        let zs = zs.map(|z| z * sz);
        let t_scaled = e[0] * zs[0] + e[1] * zs[1] + e[2] * zs[2];
        let t_det = Vec4::splat(t_max) * det;
        let bad_neg = det.cmplt(zero) & (t_scaled.cmpge(zero) | t_scaled.cmplt(t_det));
        let bad_pos = det.cmpgt(zero) & (t_scaled.cmple(zero) | t_scaled.cmpgt(t_det));
        let inv_det = Vec4::ONE / det;
        let t = t_scaled * inv_det;
        let in_range = inside & !(bad_neg | bad_pos) & t.cmplt(Vec4::splat(t_max));
        if in_range.bitmask() & self.valid == 0 {
            return Some(miss);
        }

        // The scalar test's conservative bound on the error of t.
        let max3 = |v: [Vec4; 3]| v[0].abs().max(v[1].abs()).max(v[2].abs());
        let max_zt = max3(zs);
        let max_xt = max3(xs);
        let max_yt = max3(ys);
        let delta_z = gamma(3) * max_zt;
        let delta_x = gamma(5) * (max_xt + max_zt);
        let delta_y = gamma(5) * (max_yt + max_zt);
        let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
        let max_e = max3(e);
        let delta_t =
            3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv_det.abs();

        let hit = in_range & !t.cmple(delta_t);
        Some(Lanes {
            hit: hit.bitmask() & self.valid,
            t,
            e,
            inv_det,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::tests::fixtures::Rng;

    fn random_tri(rng: &mut Rng, scale: f32) -> [Vec3A; 3] {
        let c = rng.in_box(Vec3A::splat(-1.0), Vec3A::splat(1.0)) * scale;
        [0, 1, 2].map(|_| c + rng.direction() * scale * 0.5)
    }

    /// Each lane agrees with the scalar test bit for bit, including empty lanes, axis-aligned
    /// directions, shared edges (exact zeros) and every scale.
    #[test]
    fn packets_match_the_scalar_test() {
        let mut rng = Rng::new(3);
        let mut hits = 0;
        for round in 0..4000 {
            let scale = [1e-4f32, 1.0, 1e5][round % 3];
            let mut tris: [Option<[Vec3A; 3]>; LANES] = [None; LANES];
            for (lane, t) in tris.iter_mut().enumerate() {
                if (round + lane) % 5 != 0 {
                    *t = Some(random_tri(&mut rng, scale));
                }
            }
            // Two triangles sharing an edge through the ray's path now and then.
            if round % 7 == 0 {
                if let (Some(a), Some(_)) = (tris[0], tris[1]) {
                    tris[1] = Some([a[1], a[0], a[0] + (a[2] - a[0]) * -1.0]);
                }
            }
            let o = rng.in_box(Vec3A::splat(-1.5), Vec3A::splat(1.5)) * scale;
            // Mostly aimed at a point of one of the triangles (or its neighbourhood).
            let aim = tris.iter().flatten().nth(round % 3).map(|v| {
                let (u, w) = (rng.f32() * 1.2 - 0.1, rng.f32() * 0.6);
                v[0] + (v[1] - v[0]) * u + (v[2] - v[0]) * w
            });
            let d = match (round % 11, aim) {
                (0, _) => Vec3A::X,
                (1, _) => -Vec3A::Z,
                (2, _) | (_, None) => rng.direction(),
                (_, Some(a)) => (a - o).normalize(),
            };
            let t_max = [f32::INFINITY, 1.5 * scale][round % 2];
            let pack = Tri4::new(tris);
            let ray = RayTri::new(o, d);
            let mut want: Option<Tri4Hit> = None;
            for (lane, t) in tris.iter().enumerate() {
                let Some(v) = t else { continue };
                let bound = want.map_or(t_max, |w| w.t);
                if let Some(h) = triangle::intersect(v, o, d, t_max) {
                    if h.t < bound {
                        want = Some(Tri4Hit {
                            lane,
                            t: h.t,
                            b: h.b,
                        });
                    }
                }
            }
            let got = pack.closest(&ray, t_max);
            assert_eq!(
                got.map(|h| (h.lane, h.t.to_bits(), h.b.map(f32::to_bits))),
                want.map(|h| (h.lane, h.t.to_bits(), h.b.map(f32::to_bits))),
                "round {round}"
            );
            assert_eq!(pack.any(&ray, t_max), want.is_some(), "round {round}");
            hits += usize::from(want.is_some());
        }
        assert!(hits > 1000, "too few hits to mean anything: {hits}");
    }

    /// Hit as comparable bits (NaN-safe).
    fn bits(h: Option<Tri4Hit>) -> Option<(usize, u32, [u32; 3])> {
        h.map(|h| (h.lane, h.t.to_bits(), h.b.map(f32::to_bits)))
    }

    /// The scalar test over the lanes, closest first-lane-on-ties.
    fn scalar(tris: &[Option<[Vec3A; 3]>], o: Vec3A, d: Vec3A, t_max: f32) -> Option<Tri4Hit> {
        let mut want: Option<Tri4Hit> = None;
        for (lane, v) in tris.iter().enumerate() {
            let Some(v) = v else { continue };
            if let Some(h) = triangle::intersect(v, o, d, t_max) {
                if want.is_none_or(|w| h.t < w.t) {
                    want = Some(Tri4Hit {
                        lane,
                        t: h.t,
                        b: h.b,
                    });
                }
            }
        }
        want
    }

    /// Rays through the shared vertices and along the shared edges of an integer fan have
    /// exactly zero edge functions: the packet hands them to the f64 path, with the scalar
    /// test's results bit for bit, and no ray falls between the triangles (watertight).
    #[test]
    fn zero_edge_rays_take_the_f64_path_with_the_same_results() {
        let ring = [
            (1, 0),
            (1, 1),
            (0, 1),
            (-1, 1),
            (-1, 0),
            (-1, -1),
            (0, -1),
            (1, -1),
        ]
        .map(|(x, y)| Vec3A::new(x as f32, y as f32, 0.0));
        let fan: Vec<Option<[Vec3A; 3]>> = (0..8)
            .map(|i| Some([Vec3A::ZERO, ring[i], ring[(i + 1) % 8]]))
            .collect();
        // The second packet has an empty lane (and its triangle in the first one).
        let mut packets = vec![fan[..4].to_vec(), fan[4..7].to_vec()];
        packets[1].push(None);
        packets[0][3] = fan[3];
        let packs: Vec<Tri4> = packets
            .iter()
            .map(|p| Tri4::new([p[0], p[1], p[2], p[3]]))
            .collect();
        let mut fallbacks = 0;
        for (x, y) in [
            (0.0, 0.0),
            (1.0, 0.0),
            (1.0, 1.0),
            (0.5, 0.0),
            (0.5, 0.5),
            (0.0, -0.5),
        ] {
            let o = Vec3A::new(x, y, 2.0);
            let ray = RayTri::new(o, -Vec3A::Z);
            let mut hit = false;
            for (p, lanes) in packs.iter().zip(&packets) {
                fallbacks += usize::from(p.test(&ray, f32::INFINITY).is_none());
                let got = p.closest(&ray, f32::INFINITY);
                assert_eq!(bits(got), bits(scalar(lanes, o, -Vec3A::Z, f32::INFINITY)));
                assert_eq!(p.any(&ray, f32::INFINITY), got.is_some());
                hit |= got.is_some_and(|h| h.t == 2.0);
            }
            assert!(hit, "ray at ({x}, {y}) fell through the fan");
        }
        assert!(fallbacks >= 6, "only {fallbacks} packets took the f64 path");
    }

    /// Overflowing, infinite, NaN and degenerate triangles and odd t_max values: a lane
    /// alone in its packet gives exactly the scalar test's answer (a NaN distance is a miss
    /// in both).
    #[test]
    fn extreme_inputs_match_the_scalar_test() {
        let big = 3.0e38f32;
        let v = Vec3A::new;
        let tris = [
            [v(-big, -big, 1.0), v(big, -big, 1.0), v(0.0, big, 1.0)],
            [v(-big, 0.0, -big), v(big, 0.0, big), v(big, 1.0, -big)],
            [
                v(-1.0, -1.0, 1.0),
                v(f32::INFINITY, -1.0, 1.0),
                v(0.0, 1.0, 1.0),
            ],
            [v(-1.0, -1.0, 1.0), v(f32::NAN, -1.0, 1.0), v(0.0, 1.0, 1.0)],
            [v(-1.0, -1.0, 1.0), v(-1.0, -1.0, 1.0), v(0.0, 1.0, 1.0)],
            [v(0.2, 0.1, 1.0), v(0.2, 0.1, 1.0), v(0.2, 0.1, 1.0)],
            [v(-1.0, -1.0, 1.0), v(0.0, 0.0, 1.0), v(1.0, 1.0, 1.0)],
            [
                v(-1e-30, -1e-30, 1e-30),
                v(1e-30, -1e-30, 1e-30),
                v(0.0, 1e-30, 1e-30),
            ],
            [v(-1.0, -1.0, 1.0), v(1.0, -1.0, 1.0), v(0.0, 1.0, 1.0)],
        ];
        let rays = [
            (Vec3A::ZERO, Vec3A::Z),
            (Vec3A::ZERO, Vec3A::new(0.6, 0.1, 0.8).normalize()),
            (v(0.2, 0.1, -1.0), Vec3A::Z),
            (v(0.0, 0.0, 1.0), Vec3A::X),
            (v(1e-31, 0.0, 0.0), Vec3A::Z),
        ];
        let mut hits = 0;
        for tri in tris {
            for (o, d) in rays {
                for t_max in [f32::INFINITY, 1.5, 1.0, 1e-30, 0.0, f32::NAN] {
                    let lanes = [None, Some(tri), None, None];
                    let pack = Tri4::new(lanes);
                    let ray = RayTri::new(o, d);
                    let want = scalar(&lanes, o, d, t_max);
                    let got = pack.closest(&ray, t_max);
                    assert_eq!(bits(got), bits(want), "{tri:?} {o} {d} {t_max}");
                    assert_eq!(pack.any(&ray, t_max), want.is_some());
                    hits += usize::from(want.is_some());
                }
            }
        }
        assert!(hits >= 4, "too few hits to mean anything: {hits}");
    }
}
