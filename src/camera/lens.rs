//! Lens and shutter sampling shared by the projective cameras.
//!
//! The lens point follows LuxRender: Shirley-Chiu concentric mapping of the unit square onto
//! the unit disc, or, with `blades` >= 3, LuxRender's polygonal aperture mapping, whose radial
//! sample may follow a lens `distribution` ([`LensDistribution`]).
//! Shutter time: uniform between `shutteropen` and `shutterclose`, or LuxRender's "gaussian"
//! distribution (a normal of 2 standard deviations over the shutter interval).

pub use super::lens_distribution::LensDistribution;
use crate::plugin::{BuildError, Stmt};
use crate::sampling::concentric_disc;
use glam::Vec2;
use std::f32::consts::PI;

/// The aperture shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Aperture {
    Disc,
    /// Regular polygon with this many blades (>= 3).
    Polygon(u32),
    /// Regular polygon whose radial sample follows a non-uniform `distribution`.
    PolygonDistributed(u32, LensDistribution),
}

impl Aperture {
    /// A point on the unit aperture (radius 1) for `u` in [0, 1)².
    pub fn sample(&self, u: Vec2) -> Vec2 {
        match *self {
            Aperture::Disc => concentric_disc(u),
            Aperture::Polygon(blades) => polygon(u, blades),
            Aperture::PolygonDistributed(blades, d) => {
                polygon(Vec2::new(d.remap(u.x), u.y), blades)
            }
        }
    }
}

/// LuxRender's polygonal aperture: angle from `u.y`, radius `sqrt(u.x)` scaled to the polygon
/// edge in that direction (inscribed in the unit circle).
fn polygon(u: Vec2, blades: u32) -> Vec2 {
    let half = PI / blades as f32;
    let honey = half.cos();
    let theta = 2.0 * PI * u.y;
    let sector = (theta / half).floor();
    let rho = if (sector as u32).is_multiple_of(2) {
        theta - sector * half
    } else {
        (sector + 1.0) * half - theta
    };
    let r = honey / rho.cos() * u.x.sqrt();
    Vec2::new(r * theta.cos(), r * theta.sin())
}

/// How a shutter sample maps to a time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ShutterDistribution {
    Uniform,
    Gaussian,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shutter {
    pub open: f32,
    pub close: f32,
    pub distribution: ShutterDistribution,
}

impl Shutter {
    /// Reads `shutteropen` (0), `shutterclose` (1) and `shutterdistribution` (uniform).
    pub(super) fn build(s: &mut Stmt) -> Result<Shutter, BuildError> {
        let p = s.params();
        let open = p.float_or("shutteropen", 0.0);
        let close = p.float_or("shutterclose", 1.0);
        if !(open.is_finite() && close.is_finite()) {
            return Err(s.err("shutteropen/shutterclose must be finite"));
        }
        let distribution = match p.string_or("shutterdistribution", "uniform") {
            "uniform" => ShutterDistribution::Uniform,
            "gaussian" => ShutterDistribution::Gaussian,
            other => {
                s.warn(format!(
                    "shutter distribution \"{other}\" unknown, using \"uniform\""
                ));
                ShutterDistribution::Uniform
            }
        };
        Ok(Shutter {
            open,
            close,
            distribution,
        })
    }

    /// The time of a shutter sample `u` in [0, 1).
    pub fn time(&self, u: f32) -> f32 {
        let x = match self.distribution {
            ShutterDistribution::Uniform => u,
            ShutterDistribution::Gaussian => {
                const SIGMA: f32 = 2.0;
                let mut x = normal_quantile(u);
                if x.abs() > SIGMA {
                    // Redistribute the tails around the mean rather than clamping them.
                    x = normal_quantile(0.5 + u - u.round());
                }
                (x / (2.0 * SIGMA) + 0.5).clamp(0.0, 1.0)
            }
        };
        self.open + (self.close - self.open) * x
    }
}

/// The standard normal quantile, via an inverse error function approximation (Giles 2010,
/// single precision).
fn normal_quantile(p: f32) -> f32 {
    let x = (2.0 * p - 1.0).clamp(-0.999_999, 0.999_999);
    std::f32::consts::SQRT_2 * erfinv(x)
}

fn erfinv(x: f32) -> f32 {
    let mut w = -((1.0 - x) * (1.0 + x)).ln();
    let p = if w < 5.0 {
        w -= 2.5;
        let mut p = 2.810_226_4e-8;
        for c in [
            3.432_739_4e-7,
            -3.523_387_7e-6,
            -4.391_506_5e-6,
            0.000_218_580_87,
            -0.001_253_725,
            -0.004_177_681_6,
            0.246_640_72,
            1.501_409_4,
        ] {
            p = c + p * w;
        }
        p
    } else {
        w = w.sqrt() - 3.0;
        let mut p = -0.000_200_214_26;
        for c in [
            0.000_100_950_56,
            0.001_349_343_2,
            -0.003_673_428_4,
            0.005_739_507_7,
            -0.007_622_461,
            0.009_438_870_5,
            1.001_674,
            2.832_976_7,
        ] {
            p = c + p * w;
        }
        p
    };
    p * x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn disc_samples_stay_in_the_unit_disc_and_cover_it() {
        let mut quadrants = [0u32; 4];
        for i in 0..32 {
            for j in 0..32 {
                let u = Vec2::new((i as f32 + 0.5) / 32.0, (j as f32 + 0.5) / 32.0);
                let p = concentric_disc(u);
                assert!(p.length() <= 1.0 + 1e-6);
                quadrants[(p.x > 0.0) as usize * 2 + (p.y > 0.0) as usize] += 1;
                let q = Aperture::Polygon(6).sample(u);
                assert!(q.length() <= 1.0 + 1e-5);
            }
        }
        assert_eq!(quadrants, [256; 4]);
    }

    #[test]
    fn shutter_times() {
        let s = Shutter {
            open: 0.25,
            close: 0.75,
            distribution: ShutterDistribution::Uniform,
        };
        assert_eq!(s.time(0.5), 0.5);
        let g = Shutter {
            distribution: ShutterDistribution::Gaussian,
            ..s
        };
        assert!((g.time(0.5) - 0.5).abs() < 1e-4);
        assert!((normal_quantile(0.975) - 1.959_964).abs() < 1e-3);
        for i in 0..100 {
            let t = g.time(i as f32 / 100.0);
            assert!((0.25..=0.75).contains(&t));
        }
    }
}
