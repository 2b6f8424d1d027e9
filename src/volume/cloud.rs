//! The `cloud` region volume (LuxRender 1.x's `Cloud` density region): the density of
//! LuxRender's cloud ([`crate::texture::cloud::CloudModel`], the same function as the `cloud`
//! texture) placed in the region's box `p0`–`p1` instead of the unit cube, scaling the
//! region's `sigma_a`, `sigma_s` and `Le`. It reads the texture's parameters with the same
//! defaults — `radius` (0.5), `noisescale` (0.5), `turbulence` (0.01), `sharpness` (6),
//! `noiseoffset` (0), `spheres` (0), `octaves` (1), `omega` (0.75), `variability` (0.9),
//! `baseflatness` (0.8), `spheresize` (0.15) — and, as LuxRender's volume does, sizes them by
//! the box (w its x extent, d its z extent):
//!
//! - the hemisphere's centre is ((x0 + x1)/2, (y0 + y1)/2, 0.33·(z1 + 2·z0)) and its radius
//!   `radius`·w; `noisescale` and `turbulence` are multiplied by w; the base fades over
//!   d·(1 − `baseflatness`);
//! - with `spheres` > 0 the cumulus spheres (radius (0.5 + k/20)·`spheresize`, k in 0..10,
//!   not scaled by the box) are placed with the C library's `rand()` seeded by
//!   `srand(int(noiseoffset))`: this is glibc's generator ([`GlibcRand`]), so clouds match
//!   LuxRender built on Linux (other C libraries place them elsewhere);
//! - the density is 0 outside the box.
//!
//! Like `exponential` and `volumegrid` regions it is ray marched in steps of `stepsize`.

use crate::plugin::{BuildError, Stmt};
use crate::texture::cloud::{CloudModel, CloudParams};
use crate::texture::param_loc;
use glam::{Affine3A, Vec3A};

/// A cloud density placed in a region's box.
#[derive(Debug)]
pub struct CloudRegion {
    /// World space to the volume's space.
    to_volume: Affine3A,
    lo: Vec3A,
    hi: Vec3A,
    model: CloudModel,
}

impl CloudRegion {
    /// Reads the cloud's parameters for the box `lo`–`hi` of the space `to_volume` maps
    /// world points into; a value the model cannot use is an error at its parameter.
    pub fn build(
        s: &mut Stmt,
        to_volume: Affine3A,
        lo: Vec3A,
        hi: Vec3A,
    ) -> Result<CloudRegion, BuildError> {
        let c = CloudParams::read(s.params());
        c.check()
            .map_err(|(name, m)| BuildError::new(&param_loc(s.params(), name, s.loc()), m))?;
        let width = hi.x - lo.x;
        let radius = c.radius * width;
        if !(radius > 0.0 && radius.is_finite()) {
            return Err(s.err("cloud region: radius × the box's x extent must be positive"));
        }
        let mut model = CloudModel {
            radius,
            spheres: Vec::new(),
            cumulus: false,
            sharpness: c.sharpness,
            base_fade: (hi.z - lo.z) * (1.0 - c.base_flatness),
            variability: c.variability,
            omega: c.omega,
            noise_scale: c.noise_scale * width,
            noise_offset: c.noise_offset,
            turbulence: c.turbulence * width,
            octaves: c.octaves,
            centre: Vec3A::new(
                (hi.x + lo.x) * 0.5,
                (hi.y + lo.y) * 0.5,
                (hi.z + 2.0 * lo.z) * 0.33,
            ),
        };
        if c.spheres > 0 {
            let mut rng = GlibcRand::new(c.noise_offset as i32 as u32);
            model.place_spheres(c.spheres, c.sphere_size, |res| {
                (rng.rand() as u64 % res) as f32 / res as f32
            });
        }
        Ok(CloudRegion {
            to_volume,
            lo,
            hi,
            model,
        })
    }

    /// The density at world point `p` (0 outside the box).
    pub fn density(&self, p: Vec3A) -> f32 {
        let q = self.to_volume.transform_point3a(p);
        if q.cmplt(self.lo).any() || q.cmpgt(self.hi).any() {
            return 0.0;
        }
        self.model.density(q)
    }
}

/// glibc's `rand()` after `srand(seed)` (its default additive feedback generator of 34
/// words: r[i] = r[i-31] + r[i-3], outputs r >> 1 after 310 discarded values).
pub struct GlibcRand {
    r: [u32; 34],
    i: usize,
}

impl GlibcRand {
    pub fn new(seed: u32) -> GlibcRand {
        let mut r = [0u32; 34];
        r[0] = if seed == 0 { 1 } else { seed };
        for i in 1..31 {
            // 16807 · r mod (2^31 - 1) on signed 32-bit words (Schrage's method).
            let prev = r[i - 1] as i32 as i64;
            let (hi, lo) = (prev / 127_773, prev % 127_773);
            let mut word = 16_807 * lo - 2_836 * hi;
            if word < 0 {
                word += 2_147_483_647;
            }
            r[i] = word as u32;
        }
        for i in 31..34 {
            r[i] = r[i - 31];
        }
        let mut g = GlibcRand { r, i: 0 };
        for _ in 0..310 {
            g.step();
        }
        g
    }

    fn step(&mut self) -> u32 {
        // The ring holds the last 34 words; slot i is the oldest (r[i-34]).
        let n = self.r.len();
        let v = self.r[(self.i + n - 31) % n].wrapping_add(self.r[(self.i + n - 3) % n]);
        self.r[self.i] = v;
        self.i = (self.i + 1) % n;
        v
    }

    /// The next value of `rand()`, in [0, 2^31).
    pub fn rand(&mut self) -> u32 {
        self.step() >> 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lxs::{Entity, ParamSet, ParamValue};

    #[test]
    fn glibc_rand_matches_its_known_outputs() {
        // glibc: srand(1); rand() → 1804289383, 846930886, 1681692777, 1714636915.
        let mut g = GlibcRand::new(1);
        let v: Vec<u32> = (0..4).map(|_| g.rand()).collect();
        assert_eq!(v, [1804289383, 846930886, 1681692777, 1714636915]);
        // srand(0) seeds as srand(1).
        assert_eq!(GlibcRand::new(0).rand(), 1804289383);
    }

    fn region(params: ParamSet, lo: Vec3A, hi: Vec3A) -> CloudRegion {
        let e = Entity {
            kind: "cloud".into(),
            params,
            ..Default::default()
        };
        let mut w = Vec::new();
        let mut s = Stmt::new("volume", &e, &mut w);
        CloudRegion::build(&mut s, Affine3A::IDENTITY, lo, hi).expect("builds")
    }

    /// Without turbulence, the hemisphere: amount = 1 − |p − c| / (radius·w) above the
    /// centre, density min(1, (amount·10^0.7)^sharpness), computed here by hand.
    #[test]
    fn the_hemisphere_is_sized_by_the_box() {
        let mut p = ParamSet::default();
        p.add("turbulence", ParamValue::Float(vec![0.0]));
        // Box 4 wide, 2 deep, from z = 1: centre (2, 0.5, 0.33·(3 + 2)) = (2, 0.5, 1.65),
        // radius 0.5·4 = 2.
        let r = region(p, Vec3A::new(0.0, -1.5, 1.0), Vec3A::new(4.0, 2.5, 3.0));
        let c = Vec3A::new(2.0, 0.5, 1.65);
        assert_eq!(r.density(c), 1.0);
        // 1.8 above the centre: amount 0.1, (0.1·10^0.7)^6 = 10^-1.8.
        let d = r.density(c + Vec3A::new(0.0, 0.0, 1.3));
        let amount: f64 = 1.0 - 1.3 / 2.0;
        let want = (amount * 10f64.powf(0.7)).powi(6).min(1.0);
        assert!(
            (f64::from(d) - want).abs() < 1e-4 * want.max(1e-3),
            "{d} vs {want}"
        );
        // 1.9 sideways (inside the box): amount 0.05.
        let d = r.density(c + Vec3A::new(1.9, 0.0, 0.0));
        let want = (0.05f64 * 10f64.powf(0.7)).powi(6);
        assert!((f64::from(d) - want).abs() < 1e-3 * want, "{d} vs {want}");
        // Outside the radius, and outside the box.
        assert_eq!(r.density(c + Vec3A::new(0.0, 2.1, 0.0)), 0.0);
        assert_eq!(r.density(Vec3A::new(-0.1, 0.5, 1.65)), 0.0);
    }

    /// Below the centre the base fades: amount × (1 − cos((z − c.z + f)/f · π/2)), f the fade
    /// distance d·(1 − baseflatness) = 2·0.2 = 0.4 here.
    #[test]
    fn the_base_fades_over_the_box_depth() {
        let mut p = ParamSet::default();
        p.add("turbulence", ParamValue::Float(vec![0.0]));
        p.add("sharpness", ParamValue::Float(vec![1.0]));
        let r = region(p, Vec3A::new(0.0, -1.5, 1.0), Vec3A::new(4.0, 2.5, 3.0));
        let c = Vec3A::new(2.0, 0.5, 1.65);
        let dz = -0.3f64;
        let amount = 1.0 - 0.3 / 2.0;
        let fade = 1.0 - ((dz + 0.4) / 0.4 * std::f64::consts::FRAC_PI_2).cos();
        let want = (amount * fade * 10f64.powf(0.7)).min(1.0);
        let d = r.density(c + Vec3A::new(0.0, 0.0, dz as f32));
        assert!((f64::from(d) - want).abs() < 1e-4, "{d} vs {want}");
        // Lower than 0.4 radius below the centre: nothing.
        assert_eq!(r.density(c + Vec3A::new(0.0, 0.0, -0.81)), 0.0);
    }

    #[test]
    fn bad_parameters_are_errors_at_the_statement() {
        let mut p = ParamSet::default();
        p.add("spheres", ParamValue::Integer(vec![-1]));
        let e = Entity {
            kind: "cloud".into(),
            params: p,
            ..Default::default()
        };
        let mut w = Vec::new();
        let mut s = Stmt::new("volume", &e, &mut w);
        let r = CloudRegion::build(&mut s, Affine3A::IDENTITY, Vec3A::ZERO, Vec3A::ONE);
        assert!(r.is_err());
    }
}
