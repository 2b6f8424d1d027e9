//! LuxRender's procedural noise (`core/texture.cpp`): Perlin's improved gradient noise over
//! Ken Perlin's permutation table with the quintic fade 6t⁵ − 15t⁴ + 10t³, and the fractal sums
//! built on it. LuxRender 1.x calls `FBm` and `Turbulence` with zero ray differentials, so every
//! octave is summed: `FBm(P) = Σ_{i<octaves} ωⁱ · noise(1.99ⁱ · P)` and `Turbulence` the same sum
//! of `|noise|` (the anti-aliasing terms vanish). `fbm`, `wrinkled`, `windy`, `marble` and
//! `dots` evaluate through these functions.

use glam::Vec3A;

/// Ken Perlin's permutation of 0..=255 (LuxRender's `NoisePerm`, stored once and indexed
/// modulo 256).
#[rustfmt::skip]
const PERM: [u8; 256] = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69,
    142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252,
    219, 203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168,
    68, 175, 74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60, 211,
    133, 230, 220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216, 80,
    73, 209, 76, 132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100,
    109, 198, 173, 186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82,
    85, 212, 207, 206, 59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248,
    152, 2, 44, 154, 163, 70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108,
    110, 79, 113, 224, 232, 178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238, 210,
    144, 12, 191, 179, 162, 241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199,
    106, 157, 184, 84, 204, 176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114,
    67, 29, 24, 72, 243, 141, 128, 195, 78, 66, 215, 61, 156, 180,
];

/// The doubled table (`NoisePerm[i]` for 0 ≤ i < 512) without the modulo.
#[inline(always)]
fn perm(i: usize) -> usize {
    PERM[i & 255] as usize
}

/// Gradient of lattice point (x, y, z) dotted with the offset (Perlin's 16-direction hash).
#[inline(always)]
fn grad(x: usize, y: usize, z: usize, dx: f32, dy: f32, dz: f32) -> f32 {
    let h = perm(perm(perm(x) + y) + z) & 15;
    let u = if h < 8 || h == 12 || h == 13 { dx } else { dy };
    let v = if h < 4 || h == 12 || h == 13 { dy } else { dz };
    (if h & 1 != 0 { -u } else { u }) + (if h & 2 != 0 { -v } else { v })
}

/// The quintic fade curve.
#[inline(always)]
fn weight(t: f32) -> f32 {
    let t3 = t * t * t;
    let t4 = t3 * t;
    6.0 * t4 * t - 15.0 * t4 + 10.0 * t3
}

#[inline(always)]
fn lerp(t: f32, a: f32, b: f32) -> f32 {
    (1.0 - t) * a + t * b
}

/// LuxRender's `Floor2Int` for the lattice cell (saturating for huge coordinates).
#[inline(always)]
fn floor_int(v: f32) -> i32 {
    v.floor() as i32
}

/// Perlin noise at (x, y, z), in about [-1, 1], zero on the integer lattice.
pub fn noise(x: f32, y: f32, z: f32) -> f32 {
    let (ix, iy, iz) = (floor_int(x), floor_int(y), floor_int(z));
    let (dx, dy, dz) = (x - ix as f32, y - iy as f32, z - iz as f32);
    if !(dx.is_finite() && dy.is_finite() && dz.is_finite()) {
        return 0.0;
    }
    let (ix, iy, iz) = (
        (ix & 255) as usize,
        (iy & 255) as usize,
        (iz & 255) as usize,
    );
    let w000 = grad(ix, iy, iz, dx, dy, dz);
    let w100 = grad(ix + 1, iy, iz, dx - 1.0, dy, dz);
    let w010 = grad(ix, iy + 1, iz, dx, dy - 1.0, dz);
    let w110 = grad(ix + 1, iy + 1, iz, dx - 1.0, dy - 1.0, dz);
    let w001 = grad(ix, iy, iz + 1, dx, dy, dz - 1.0);
    let w101 = grad(ix + 1, iy, iz + 1, dx - 1.0, dy, dz - 1.0);
    let w011 = grad(ix, iy + 1, iz + 1, dx, dy - 1.0, dz - 1.0);
    let w111 = grad(ix + 1, iy + 1, iz + 1, dx - 1.0, dy - 1.0, dz - 1.0);
    let (wx, wy, wz) = (weight(dx), weight(dy), weight(dz));
    let x00 = lerp(wx, w000, w100);
    let x10 = lerp(wx, w010, w110);
    let x01 = lerp(wx, w001, w101);
    let x11 = lerp(wx, w011, w111);
    let y0 = lerp(wy, x00, x10);
    let y1 = lerp(wy, x01, x11);
    lerp(wz, y0, y1)
}

/// [`noise`] at a point.
#[inline]
pub fn noise_p(p: Vec3A) -> f32 {
    noise(p.x, p.y, p.z)
}

/// Fractional Brownian motion: `octaves` octaves of noise, each 1.99 times finer and `omega`
/// times weaker than the one before.
pub fn fbm(p: Vec3A, omega: f32, octaves: i32) -> f32 {
    let (mut sum, mut lambda, mut o) = (0.0, 1.0, 1.0);
    for _ in 0..octaves.max(0) {
        sum += o * noise_p(lambda * p);
        lambda *= 1.99;
        o *= omega;
    }
    sum
}

/// Turbulence: [`fbm`] of the absolute value of the noise.
pub fn turbulence(p: Vec3A, omega: f32, octaves: i32) -> f32 {
    let (mut sum, mut lambda, mut o) = (0.0, 1.0, 1.0);
    for _ in 0..octaves.max(0) {
        sum += o * noise_p(lambda * p).abs();
        lambda *= 1.99;
        o *= omega;
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_vanishes_on_the_lattice_and_is_bounded() {
        for (x, y, z) in [(0.0, 0.0, 0.0), (3.0, -7.0, 12.0), (255.0, 256.0, -1.0)] {
            assert_eq!(noise(x, y, z), 0.0);
        }
        let mut max = 0.0f32;
        for i in 0..2000 {
            let t = i as f32 * 0.0137;
            let v = noise(t * 3.1, t * 1.7 + 0.3, t * 0.9 - 2.0);
            max = max.max(v.abs());
        }
        assert!(max < 1.1 && max > 0.3, "{max}");
    }

    /// A hand-computed value: at (0.5, 0, 0) the fade weights are 0.5 in x and 0 in y and z,
    /// so only the lattice points (0,0,0) and (1,0,0) contribute. Their hashes:
    /// perm[perm[perm[0]]] = perm[perm[151]] = perm[17] = 4 (gradient dx + dz → 0.5) and
    /// perm[perm[perm[1]]] & 15 = 6 (dx − dz → −0.5): the noise is 0 there. At (0.5, 0.5, 0)
    /// four corners contribute with weight 1/4 each.
    #[test]
    fn noise_matches_a_hand_computed_value() {
        assert_eq!(PERM[0], 151);
        assert_eq!(PERM[151], 17);
        assert_eq!(PERM[17] & 15, 4);
        assert_eq!(noise(0.5, 0.0, 0.0), 0.0);
        // (0.5, 0.5, 0): eight corners with the quintic weights 0.5; compute them directly.
        let g = |h: usize, dx: f32, dy: f32, dz: f32| {
            let u = if h < 8 || h == 12 || h == 13 { dx } else { dy };
            let v = if h < 4 || h == 12 || h == 13 { dy } else { dz };
            (if h & 1 != 0 { -u } else { u }) + (if h & 2 != 0 { -v } else { v })
        };
        let h = |x: usize, y: usize, z: usize| {
            PERM[(PERM[(PERM[x] as usize + y) & 255] as usize + z) & 255] as usize & 15
        };
        let mut expect = 0.0;
        for (x, y) in [(0usize, 0usize), (1, 0), (0, 1), (1, 1)] {
            let (dx, dy) = (0.5 - x as f32, 0.5 - y as f32);
            expect += 0.25 * g(h(x, y, 0), dx, dy, 0.0);
        }
        assert!((noise(0.5, 0.5, 0.0) - expect).abs() < 1e-6);
        assert!(expect != 0.0);
    }

    #[test]
    fn fbm_sums_octaves_and_turbulence_is_positive() {
        let p = Vec3A::new(0.3, 1.7, -2.2);
        let one = fbm(p, 0.5, 1);
        assert_eq!(one, noise_p(p));
        let two = fbm(p, 0.5, 2);
        assert!((two - (noise_p(p) + 0.5 * noise_p(1.99 * p))).abs() < 1e-7);
        assert!(turbulence(p, 0.5, 8) >= 0.0);
        assert_eq!(fbm(p, 0.5, 0), 0.0);
        assert_eq!(fbm(p, 0.5, -3), 0.0);
    }
}
