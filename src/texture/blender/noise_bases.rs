//! The noise bases of Blender's noise library (`blender_noiselib.cpp`): Blender's original
//! gradient noise over `hash` and `hashvectf`, Perlin's original and improved noises, the
//! Worley/Voronoi feature points with seven distance metrics, and cell noise. The tables are
//! in [`super::tables`]; [`super::noiselib`] picks a basis by name and builds the generic
//! noise, turbulence and Musgrave's fractals on these.

use super::tables::{HASH, HASHPNTF, HASHVECTF};

/// Voronoi distance metrics (`distmetric`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Distance {
    Actual,
    Squared,
    Manhattan,
    Chebychev,
    MinkowskiHalf,
    MinkowskiFour,
    Minkowski,
}

impl Distance {
    pub fn from_name(name: &str) -> Option<Distance> {
        Some(match name {
            "actual_distance" => Distance::Actual,
            "distance_squared" => Distance::Squared,
            "manhattan" => Distance::Manhattan,
            "chebychev" => Distance::Chebychev,
            "minkovsky_half" => Distance::MinkowskiHalf,
            "minkovsky_four" => Distance::MinkowskiFour,
            "minkovsky" => Distance::Minkowski,
            _ => return None,
        })
    }

    fn eval(self, x: f32, y: f32, z: f32, e: f32) -> f32 {
        match self {
            Distance::Actual => (x * x + y * y + z * z).sqrt(),
            Distance::Squared => x * x + y * y + z * z,
            Distance::Manhattan => x.abs() + y.abs() + z.abs(),
            Distance::Chebychev => x.abs().max(y.abs()).max(z.abs()),
            Distance::MinkowskiHalf => {
                let d = x.abs().sqrt() + y.abs().sqrt() + z.abs().sqrt();
                d * d
            }
            Distance::MinkowskiFour => {
                let (x, y, z) = (x * x, y * y, z * z);
                (x * x + y * y + z * z).sqrt().sqrt()
            }
            Distance::Minkowski => {
                (x.abs().powf(e) + y.abs().powf(e) + z.abs().powf(e)).powf(1.0 / e)
            }
        }
    }
}

#[inline(always)]
fn hash(i: i32) -> i32 {
    HASH[(i & 255) as usize] as i32
}

#[inline(always)]
fn vect(i: i32) -> [f32; 3] {
    let k = (i & 255) as usize * 3;
    [HASHVECTF[k], HASHVECTF[k + 1], HASHVECTF[k + 2]]
}

/// A feature point of lattice cell (x, y, z) (Blender's `HASHPNT`).
#[inline(always)]
fn hashpnt(x: i32, y: i32, z: i32) -> [f32; 3] {
    let k = hash(hash(hash(z).wrapping_add(y)).wrapping_add(x)) as usize * 3;
    [HASHPNTF[k], HASHPNTF[k + 1], HASHPNTF[k + 2]]
}

#[inline(always)]
fn lerp(t: f32, a: f32, b: f32) -> f32 {
    a + t * (b - a)
}

/// Blender's original noise in [0, 1] (`orgBlenderNoise`).
pub fn org_blender_noise(x: f32, y: f32, z: f32) -> f32 {
    let (fx, fy, fz) = (x.floor(), y.floor(), z.floor());
    let (ix, iy, iz) = (fx as i32, fy as i32, fz as i32);
    let (ox, oy, oz) = (x - fx, y - fy, z - fz);
    let (jx, jy, jz) = (ox - 1.0, oy - 1.0, oz - 1.0);
    let c = |o: f32| 1.0 - 3.0 * o * o + 2.0 * o * o * o;
    let cj = |j: f32| 1.0 - 3.0 * j * j - 2.0 * j * j * j;
    let (cn1, cn2, cn3) = (c(ox), c(oy), c(oz));
    let (cn4, cn5, cn6) = (cj(jx), cj(jy), cj(jz));
    // Far from the origin the cell indices saturate; only their low 8 bits matter.
    let (ix1, iy1, iz1) = (ix.wrapping_add(1), iy.wrapping_add(1), iz.wrapping_add(1));
    let b00 = hash(hash(ix & 255) + (iy & 255));
    let b10 = hash(hash(ix1 & 255) + (iy & 255));
    let b01 = hash(hash(ix & 255) + (iy1 & 255));
    let b11 = hash(hash(ix1 & 255) + (iy1 & 255));
    let (b20, b21) = (iz & 255, iz1 & 255);
    let term = |w: f32, b: i32, px: f32, py: f32, pz: f32| {
        let h = vect(hash(b));
        w * (h[0] * px + h[1] * py + h[2] * pz)
    };
    let mut n = 0.5;
    n += term(cn1 * cn2 * cn3, b20 + b00, ox, oy, oz);
    n += term(cn1 * cn2 * cn6, b21 + b00, ox, oy, jz);
    n += term(cn1 * cn5 * cn3, b20 + b01, ox, jy, oz);
    n += term(cn1 * cn5 * cn6, b21 + b01, ox, jy, jz);
    n += term(cn4 * cn2 * cn3, b20 + b10, jx, oy, oz);
    n += term(cn4 * cn2 * cn6, b21 + b10, jx, oy, jz);
    n += term(cn4 * cn5 * cn3, b20 + b11, jx, jy, oz);
    n += term(cn4 * cn5 * cn6, b21 + b11, jx, jy, jz);
    n.clamp(0.0, 1.0)
}

fn improved_grad(h: i32, x: f32, y: f32, z: f32) -> f32 {
    let h = h & 15;
    let u = if h < 8 { x } else { y };
    let v = if h < 4 {
        y
    } else if h == 12 || h == 14 {
        x
    } else {
        z
    };
    (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
}

/// Perlin's improved noise over Blender's `hash` (`newPerlin`), signed.
pub fn new_perlin(x: f32, y: f32, z: f32) -> f32 {
    let (u, v, w) = (x.floor(), y.floor(), z.floor());
    let (xi, yi, zi) = ((u as i32) & 255, (v as i32) & 255, (w as i32) & 255);
    let (x, y, z) = (x - u, y - v, z - w);
    let fade = |t: f32| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
    let (u, v, w) = (fade(x), fade(y), fade(z));
    let a = hash(xi) + yi;
    let (aa, ab) = (hash(a) + zi, hash(a + 1) + zi);
    let b = hash(xi + 1) + yi;
    let (ba, bb) = (hash(b) + zi, hash(b + 1) + zi);
    let g = |h: i32, dx: f32, dy: f32, dz: f32| improved_grad(hash(h), dx, dy, dz);
    lerp(
        w,
        lerp(
            v,
            lerp(u, g(aa, x, y, z), g(ba, x - 1.0, y, z)),
            lerp(u, g(ab, x, y - 1.0, z), g(bb, x - 1.0, y - 1.0, z)),
        ),
        lerp(
            v,
            lerp(u, g(aa + 1, x, y, z - 1.0), g(ba + 1, x - 1.0, y, z - 1.0)),
            lerp(
                u,
                g(ab + 1, x, y - 1.0, z - 1.0),
                g(bb + 1, x - 1.0, y - 1.0, z - 1.0),
            ),
        ),
    )
}

/// Perlin's original noise (`noise3_perlin`), signed, scaled by 1.5 as Blender does.
pub fn org_perlin(x: f32, y: f32, z: f32) -> f32 {
    let setup = |v: f32| {
        let t = v + 10000.0;
        let it = t as i32;
        let b0 = it & 255;
        let r0 = t - it as f32;
        (b0, (b0 + 1) & 255, r0, r0 - 1.0)
    };
    let (bx0, bx1, rx0, rx1) = setup(x);
    let (by0, by1, ry0, ry1) = setup(y);
    let (bz0, bz1, rz0, rz1) = setup(z);
    let (i, j) = (hash(bx0), hash(bx1));
    let (b00, b10) = (hash(i + by0), hash(j + by0));
    let (b01, b11) = (hash(i + by1), hash(j + by1));
    let s = |t: f32| t * t * (3.0 - 2.0 * t);
    let (sx, sy, sz) = (s(rx0), s(ry0), s(rz0));
    let at = |k: i32, rx: f32, ry: f32, rz: f32| {
        let q = vect(k);
        rx * q[0] + ry * q[1] + rz * q[2]
    };
    let a = lerp(
        sx,
        at(b00 + bz0, rx0, ry0, rz0),
        at(b10 + bz0, rx1, ry0, rz0),
    );
    let b = lerp(
        sx,
        at(b01 + bz0, rx0, ry1, rz0),
        at(b11 + bz0, rx1, ry1, rz0),
    );
    let c = lerp(sy, a, b);
    let a = lerp(
        sx,
        at(b00 + bz1, rx0, ry0, rz1),
        at(b10 + bz1, rx1, ry0, rz1),
    );
    let b = lerp(
        sx,
        at(b01 + bz1, rx0, ry1, rz1),
        at(b11 + bz1, rx1, ry1, rz1),
    );
    let d = lerp(sy, a, b);
    1.5 * lerp(sz, c, d)
}

/// The four nearest feature points: distances and positions (Blender's `voronoi`).
pub fn voronoi(x: f32, y: f32, z: f32, e: f32, metric: Distance) -> ([f32; 4], [[f32; 3]; 4]) {
    let (xi, yi, zi) = (x.floor() as i32, y.floor() as i32, z.floor() as i32);
    let mut da = [1e10f32; 4];
    let mut pa = [[0.0f32; 3]; 4];
    for dx in -1..=1 {
        let xx = xi.wrapping_add(dx);
        for dy in -1..=1 {
            let yy = yi.wrapping_add(dy);
            for dz in -1..=1 {
                let zz = zi.wrapping_add(dz);
                let p = hashpnt(xx, yy, zz);
                let pt = [p[0] + xx as f32, p[1] + yy as f32, p[2] + zz as f32];
                let d = metric.eval(x - pt[0], y - pt[1], z - pt[2], e);
                if let Some(slot) = da.iter().position(|&di| d < di) {
                    for k in (slot + 1..4).rev() {
                        da[k] = da[k - 1];
                        pa[k] = pa[k - 1];
                    }
                    da[slot] = d;
                    pa[slot] = pt;
                }
            }
        }
    }
    (da, pa)
}

/// Cell noise in [0, 1) (`cellNoiseU`): an integer hash of the lattice cell.
pub fn cell_noise_u(x: f32, y: f32, z: f32) -> f32 {
    let (xi, yi, zi) = (x.floor() as i32, y.floor() as i32, z.floor() as i32);
    let mut n = (xi as u32)
        .wrapping_add((yi as u32).wrapping_mul(1301))
        .wrapping_add((zi as u32).wrapping_mul(314_159));
    n ^= n << 13;
    let v = n
        .wrapping_mul(n.wrapping_mul(n).wrapping_mul(15731).wrapping_add(789_221))
        .wrapping_add(1_376_312_589);
    v as f32 / 4_294_967_296.0
}

/// The colour of a cell (`cellNoiseV`): its feature point's offsets.
pub fn cell_noise_v(x: f32, y: f32, z: f32) -> [f32; 3] {
    hashpnt(x.floor() as i32, y.floor() as i32, z.floor() as i32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_are_blenders() {
        // Values as published in Blender's noise.c / LuxRender's blender_noiselib.cpp.
        let mut seen = [false; 256];
        for &h in HASH.iter() {
            seen[h as usize] = true;
        }
        assert!(seen.iter().all(|&s| s), "hash is a permutation of 0..=255");
        assert_eq!(HASH[..4], [0xA2, 0xA0, 0x19, 0x3B]);
        assert_eq!(HASH[255], 0x5D);
        assert_eq!(HASHPNTF[..3], [0.536902, 0.020915, 0.501445]);
        assert_eq!(HASHPNTF[767], 0.951333);
        assert_eq!(HASHVECTF[..3], [0.33783, 0.715698, -0.611206]);
        assert_eq!(HASHVECTF[765..], [0.966003, 0.244873, -0.082764]);
    }

    #[test]
    fn far_points_do_not_overflow_the_lattice() {
        for v in [3.0e9f32, -3.0e9, f32::INFINITY, f32::NAN] {
            let _ = org_blender_noise(v, 0.5, v);
            let _ = org_perlin(v, v, 0.5);
            let _ = new_perlin(v, 0.5, v);
            let _ = voronoi(v, v, v, 2.5, Distance::Actual);
            let _ = cell_noise_u(v, v, v);
            let _ = cell_noise_v(v, 0.0, v);
        }
    }

    #[test]
    fn original_noise_hand_values() {
        // On the lattice every offset vanishes: 0.5.
        assert_eq!(org_blender_noise(3.0, 4.0, 5.0), 0.5);
        // Along x at (0.5, 0, 0): cn1 = cn4 = 0.5, cn2 = cn3 = 1, cn5 = cn6 = 0, so only the
        // corners (0,0,0) and (1,0,0) count: 0.5 + 0.5·(h0.x·0.5) + 0.5·(h1.x·(−0.5)).
        let h0 = vect(hash(hash(hash(0))));
        let h1 = vect(hash(hash(hash(1))));
        let expect = (0.5 + 0.25 * h0[0] - 0.25 * h1[0]).clamp(0.0, 1.0);
        assert!((org_blender_noise(0.5, 0.0, 0.0) - expect).abs() < 1e-6);
    }

    #[test]
    fn perlin_noises_vanish_on_the_lattice() {
        assert_eq!(new_perlin(2.0, 7.0, -3.0), 0.0);
        assert!(org_perlin(2.0, 7.0, -3.0).abs() < 1e-3);
        let mut max = 0.0f32;
        for i in 0..500 {
            let t = i as f32 * 0.173;
            max = max.max(new_perlin(t, 0.37 * t, 1.3 - t).abs());
        }
        assert!(max > 0.3 && max <= 1.05, "{max}");
    }

    #[test]
    fn voronoi_distances_are_sorted_and_use_the_feature_points() {
        let (da, pa) = voronoi(0.3, 0.6, 0.2, 1.0, Distance::Actual);
        assert!(da[0] <= da[1] && da[1] <= da[2] && da[2] <= da[3]);
        let d0 =
            ((0.3 - pa[0][0]).powi(2) + (0.6 - pa[0][1]).powi(2) + (0.2 - pa[0][2]).powi(2)).sqrt();
        assert!((d0 - da[0]).abs() < 1e-6);
        // The cell (0, 0, 0)'s point is HASHPNTF[3·hash[hash[hash[0]]]].
        let k = hash(hash(hash(0))) as usize * 3;
        assert_eq!(
            hashpnt(0, 0, 0),
            [HASHPNTF[k], HASHPNTF[k + 1], HASHPNTF[k + 2]]
        );
        let sq = voronoi(0.3, 0.6, 0.2, 1.0, Distance::Squared).0;
        assert!((sq[0] - da[0] * da[0]).abs() < 1e-5);
    }

    #[test]
    fn cell_noise_hand_value() {
        // Cell (0, 0, 0): n = 0, so the value is 1376312589 / 2^32.
        assert!((cell_noise_u(0.5, 0.5, 0.5) - 1_376_312_589.0 / 4_294_967_296.0).abs() < 1e-7);
        // Cell (1, 0, 0): n = 1 ^ (1 << 13) = 8193.
        let n: u32 = 8193;
        let v = n
            .wrapping_mul(n.wrapping_mul(n).wrapping_mul(15731).wrapping_add(789_221))
            .wrapping_add(1_376_312_589);
        assert_eq!(cell_noise_u(1.2, 0.1, 0.9), v as f32 / 4_294_967_296.0);
    }
}
