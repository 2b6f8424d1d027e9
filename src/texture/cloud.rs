//! `cloud` texture (float): LuxRender's procedural cloud in the unit cube of a 3D mapping.
//! The cloud is a hemisphere of `radius` (0.5) around (0.5, 0.5, 1/3) whose base fades
//! (`baseflatness` 0.8), or, with `spheres` > 0, a cumulus of that many random spheres
//! (`spheresize` 0.15) placed by LuxRender's Tausworthe generator seeded from `noiseoffset`
//! (0). The point is displaced by `turbulence` (0.01) times a turbulence of `octaves` (1)
//! octaves of noise at scale `noisescale` (0.5) with ratio `omega` (0.75), modulated by
//! `variability` (0.9); the density is min(1, (amount·10^0.7)^`sharpness` (6)).
//!
//! The density function itself, [`CloudModel`], is also the `cloud` region volume's
//! ([`crate::volume::cloud`]), which places it in its box and seeds its spheres otherwise.

use super::mapping::Mapping3D;
use super::noise::noise_p;
use super::{TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::{ParamSet, TextureDesc};
use glam::{Mat3A, Vec3A};
use std::f32::consts::PI;

/// Most cumulus spheres accepted (each one is tested at every evaluation).
pub const MAX_SPHERES: i32 = 10_000;
/// Most noise octaves honoured.
pub const MAX_OCTAVES: i32 = 64;

/// LuxRender's `RandomGenerator` (L'Ecuyer's combined Tausworthe generator "taus113"), with
/// the arithmetic of a 64-bit `unsigned long`.
pub struct Taus113 {
    z: [u64; 4],
}

const MASK: u64 = 0xffff_ffff;

impl Taus113 {
    pub fn new(seed: u64) -> Taus113 {
        let s = if seed == 0 { 1 } else { seed };
        let lcg = |n: u64| 69069u64.wrapping_mul(n);
        let mut z1 = lcg(s);
        if z1 < 2 {
            z1 += 2;
        }
        let mut z2 = lcg(z1);
        if z2 < 8 {
            z2 += 8;
        }
        let mut z3 = lcg(z2);
        if z3 < 16 {
            z3 += 16;
        }
        let mut z4 = lcg(z3);
        if z4 < 128 {
            z4 += 128;
        }
        let mut r = Taus113 {
            z: [z1, z2, z3, z4],
        };
        for _ in 0..10 {
            r.next_u64();
        }
        r
    }

    pub fn next_u64(&mut self) -> u64 {
        let [z1, z2, z3, z4] = &mut self.z;
        let b1 = (((*z1 << 6) & MASK) ^ *z1) >> 13;
        *z1 = (((*z1 & 4_294_967_294) << 18) & MASK) ^ b1;
        let b2 = (((*z2 << 2) & MASK) ^ *z2) >> 27;
        *z2 = (((*z2 & 4_294_967_288) << 2) & MASK) ^ b2;
        let b3 = (((*z3 << 13) & MASK) ^ *z3) >> 21;
        *z3 = (((*z3 & 4_294_967_280) << 7) & MASK) ^ b3;
        let b4 = (((*z4 << 3) & MASK) ^ *z4) >> 12;
        *z4 = (((*z4 & 4_294_967_168) << 13) & MASK) ^ b4;
        *z1 ^ *z2 ^ *z3 ^ *z4
    }

    /// LuxRender's `CloudRand`: (value mod `res`) / `res`.
    fn cloud_rand(&mut self, res: u64) -> f32 {
        (self.next_u64() % res) as f32 / res as f32
    }
}

/// The parameters LuxRender's cloud texture and cloud region volume share, with their
/// defaults.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CloudParams {
    pub radius: f32,
    pub noise_scale: f32,
    pub turbulence: f32,
    pub sharpness: f32,
    pub noise_offset: f32,
    pub spheres: i32,
    pub octaves: i32,
    pub omega: f32,
    pub variability: f32,
    pub base_flatness: f32,
    pub sphere_size: f32,
}

impl CloudParams {
    /// Reads the parameters (marking them used); octaves are clamped to [0, MAX_OCTAVES].
    pub fn read(p: &ParamSet) -> CloudParams {
        CloudParams {
            radius: p.float_or("radius", 0.5),
            noise_scale: p.float_or("noisescale", 0.5),
            turbulence: p.float_or("turbulence", 0.01),
            sharpness: p.float_or("sharpness", 6.0),
            noise_offset: p.float_or("noiseoffset", 0.0),
            spheres: p.int_or("spheres", 0),
            octaves: p.int_or("octaves", 1).clamp(0, MAX_OCTAVES),
            omega: p.float_or("omega", 0.75),
            variability: p.float_or("variability", 0.9),
            base_flatness: p.float_or("baseflatness", 0.8),
            sphere_size: p.float_or("spheresize", 0.15),
        }
    }

    /// `Err((parameter, message))` for values the model cannot use.
    pub fn check(&self) -> Result<(), (&'static str, String)> {
        let all = [
            self.radius,
            self.noise_scale,
            self.turbulence,
            self.sharpness,
            self.noise_offset,
            self.omega,
            self.variability,
            self.base_flatness,
            self.sphere_size,
        ];
        if all.iter().any(|v| !v.is_finite()) {
            return Err(("radius", "cloud parameters must be finite".into()));
        }
        if !(self.radius > 0.0 && self.noise_scale != 0.0) {
            return Err((
                "radius",
                "cloud radius must be positive and noisescale not zero".into(),
            ));
        }
        if !(0..=MAX_SPHERES).contains(&self.spheres) {
            return Err((
                "spheres",
                format!(
                    "cloud spheres must be in 0..={MAX_SPHERES}, got {}",
                    self.spheres
                ),
            ));
        }
        Ok(())
    }
}

/// LuxRender's cloud density function, shared by the texture and the region volume (which
/// place it differently: the texture in the unit cube, the volume in its box).
#[derive(Debug)]
pub struct CloudModel {
    pub radius: f32,
    pub spheres: Vec<(Vec3A, f32)>,
    pub cumulus: bool,
    pub sharpness: f32,
    pub base_fade: f32,
    pub variability: f32,
    pub omega: f32,
    pub noise_scale: f32,
    pub noise_offset: f32,
    pub turbulence: f32,
    pub octaves: i32,
    pub centre: Vec3A,
}

impl CloudModel {
    fn cloud_noise(&self, p: Vec3A, omega: f32, octaves: i32) -> f32 {
        let (mut sum, mut lambda, mut o) = (0.0, 1.0, 1.0);
        for _ in 0..octaves.max(0) {
            sum += o * noise_p(lambda * p);
            lambda *= 1.99;
            o *= omega;
        }
        sum
    }

    fn turbulence_at(&self, p: Vec3A, noise_scale: f32, octaves: i32) -> Vec3A {
        let off = Vec3A::splat(self.noise_offset);
        let c0 = p / noise_scale;
        let c1 = c0 + off;
        let c2 = c1 + off;
        let mut amount = 1.0;
        if self.variability < 1.0 {
            let mask = self.cloud_noise(
                (p + Vec3A::new(self.noise_offset * 4.0, 0.0, 0.0)) / self.radius * 1.4,
                self.omega,
                1,
            );
            amount = (1.0 - self.variability) + self.variability * mask;
        }
        let amount = amount.clamp(0.0, 1.0);
        let mut t = Vec3A::new(
            self.cloud_noise(c0, self.omega, octaves) - 0.15,
            self.cloud_noise(c1, self.omega, octaves) - 0.15,
            -self.cloud_noise(c2, self.omega, octaves),
        );
        if p.z < self.centre.z + self.base_fade {
            t.z *= (p.z - self.centre.z) / (2.0 * self.base_fade);
        }
        t * amount
    }

    fn shape(&self, p: Vec3A) -> f32 {
        if self.cumulus {
            let inside = self.spheres.iter().any(|(c, r)| (p - *c).length() < *r);
            return if inside { 1.0 } else { 0.0 };
        }
        let from = p - self.centre;
        let mut amount = 1.0 - from.length() / self.radius;
        if amount < 0.0 {
            return 0.0;
        }
        if p.z < self.centre.z {
            if p.z < self.centre.z - self.radius * 0.4 {
                return 0.0;
            }
            amount *= 1.0 - ((from.z + self.base_fade) / self.base_fade * PI * 0.5).cos();
        }
        amount.max(0.0)
    }

    /// The density at point `p` of the model's space.
    pub fn density(&self, p: Vec3A) -> f32 {
        let displaced = p + self.turbulence * self.turbulence_at(p, self.noise_scale, self.octaves);
        let amount = self.shape(displaced);
        (amount * 10f32.powf(0.7)).powf(self.sharpness).min(1.0)
    }

    /// Places `n` cumulus spheres of size `sphere_size` around the hemisphere's centre, as
    /// both of LuxRender's clouds do; `rand(res)` is their generator's (value mod res) / res.
    pub fn place_spheres(&mut self, n: i32, sphere_size: f32, mut rand: impl FnMut(u64) -> f32) {
        self.cumulus = n > 0;
        for _ in 0..n.max(0) {
            let r = (rand(10) / 2.0 + 0.5) * sphere_size;
            let on_edge = Vec3A::new(self.radius / 2.0 * rand(1000), 0.0, 0.0);
            let angle_y = (-180.0 * rand(1000)).to_radians();
            let angle_z = (360.0 * rand(1000)).to_radians();
            let on_edge =
                Mat3A::from_rotation_z(angle_z) * (Mat3A::from_rotation_y(angle_y) * on_edge);
            let mut pos = self.centre + on_edge;
            let shift = self.turbulence_at(
                pos + Vec3A::new(self.noise_offset * 4.0, 0.0, 0.0),
                self.radius * 0.7,
                2,
            );
            pos += shift * self.radius * 1.5;
            self.spheres.push((pos, r));
        }
    }
}

#[derive(Debug)]
pub struct CloudTex {
    pub mapping: Mapping3D,
    pub model: CloudModel,
}

impl CloudTex {
    pub fn value(&self, si: &SurfaceInteraction) -> f32 {
        self.model.density(self.mapping.map(si))
    }
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let c = CloudParams::read(&t.entity.params);
    c.check()
        .map_err(|(name, message)| TextureError::param(t, name, message))?;
    let mut model = CloudModel {
        radius: c.radius,
        spheres: Vec::new(),
        cumulus: false,
        sharpness: c.sharpness,
        base_fade: 1.0 - c.base_flatness,
        variability: c.variability,
        omega: c.omega,
        noise_scale: c.noise_scale,
        noise_offset: c.noise_offset,
        turbulence: c.turbulence,
        octaves: c.octaves,
        centre: Vec3A::new(0.5, 0.5, 1.0 / 3.0),
    };
    if c.spheres > 0 {
        // LuxRender seeds with ULONG_MAX · noiseoffset (float arithmetic).
        let mut rng = Taus113::new((u64::MAX as f32 * c.noise_offset) as u64);
        model.place_spheres(c.spheres, c.sphere_size, |res| rng.cloud_rand(res));
    }
    Ok(TexNode::Cloud(Box::new(CloudTex {
        mapping: set.mapping3d(t),
        model,
    })))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// taus113 with seed 1: the first values of the (64-bit `unsigned long`) generator after
    /// its ten warm-up steps are fixed; check the recurrence against a direct computation.
    #[test]
    fn taus113_matches_its_recurrence() {
        let mut a = Taus113::new(0);
        let mut b = Taus113::new(1);
        for _ in 0..5 {
            assert_eq!(a.next_u64(), b.next_u64(), "seed 0 means 1");
        }
        let v: Vec<u64> = (0..1000).map(|_| b.next_u64()).collect();
        assert!(v.iter().all(|x| *x <= MASK));
        let mean = v.iter().map(|x| *x as f64 / MASK as f64).sum::<f64>() / 1000.0;
        assert!((mean - 0.5).abs() < 0.05, "{mean}");
    }

    #[test]
    fn hemisphere_density_peaks_at_the_centre() {
        let tex = CloudModel {
            radius: 0.5,
            spheres: vec![],
            cumulus: false,
            sharpness: 6.0,
            base_fade: 0.2,
            variability: 0.9,
            omega: 0.75,
            noise_scale: 0.5,
            noise_offset: 0.0,
            turbulence: 0.0,
            octaves: 1,
            centre: Vec3A::new(0.5, 0.5, 1.0 / 3.0),
        };
        // At the centre: amount 1, (10^0.7)^6 > 1: clamped to 1.
        assert_eq!(tex.density(Vec3A::new(0.5, 0.5, 1.0 / 3.0)), 1.0);
        // Outside the radius: 0.
        assert_eq!(tex.density(Vec3A::new(0.5, 0.5, 1.0)), 0.0);
        // 0.45 above the centre: amount 0.1, (0.1·10^0.7)^6 = 10^-1.8.
        let d = tex.density(Vec3A::new(0.5, 0.5, 1.0 / 3.0 + 0.45));
        assert!((d - 10f32.powf(-1.8)).abs() < 1e-4, "{d}");
    }
}
