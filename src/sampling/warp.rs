//! Sampling warps: maps from uniform points of [0, 1)² to directions and points with known
//! densities (sphere, cone, cosine hemisphere, concentric disc), and the power heuristic that
//! weighs two strategies in multiple importance sampling. Used by lights, materials, cameras
//! and integrators alike.

use glam::{Vec2, Vec3A};
use std::f32::consts::PI;

#[cfg(test)]
use crate::geometry::frame::coordinate_system;

/// A uniformly distributed direction on the unit sphere.
pub fn uniform_sphere(u: Vec2) -> Vec3A {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3A::new(r * phi.cos(), r * phi.sin(), z)
}

pub const UNIFORM_SPHERE_PDF: f32 = 1.0 / (4.0 * PI);

/// A uniformly distributed direction in the cone around +z with the given cosine half-angle.
pub fn uniform_cone(u: Vec2, cos_max: f32) -> Vec3A {
    let cos_t = (1.0 - u.x) + u.x * cos_max;
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3A::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t)
}

pub fn uniform_cone_pdf(cos_max: f32) -> f32 {
    1.0 / (2.0 * PI * (1.0 - cos_max))
}

/// Shirley and Chiu's concentric mapping of [0, 1)² onto the unit disc. The wedge is chosen
/// by selects, not branches (it is a coin flip per sample).
pub fn concentric_disc(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    let wide = o.x.abs() > o.y.abs();
    let (r, other) = if wide { (o.x, o.y) } else { (o.y, o.x) };
    let q = PI / 4.0 * (other / r);
    // The angle is q (wide wedge) or π/2 - q, whose sine and cosine are q's swapped.
    let (s, c) = sin_cos_quarter(q);
    let (sin, cos) = if wide { (s, c) } else { (c, s) };
    if o == Vec2::ZERO {
        Vec2::ZERO
    } else {
        r * Vec2::new(cos, sin)
    }
}

/// Sine and cosine of `x` in [-π/4, π/4] by their Taylor polynomials to x⁹ and x¹⁰: the
/// truncation errors there are below 2e-9 and 2e-10, under f32 rounding, at a fraction of a
/// libm call (which was 1.8% of a Cornell render, nearly all from diffuse sampling). Outside
/// the range (a NaN input) the result is NaN or inaccurate, as the callers never ask.
#[inline]
fn sin_cos_quarter(x: f32) -> (f32, f32) {
    let x2 = x * x;
    let sin = x
        * (1.0
            + x2 * (-1.0 / 6.0
                + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362_880.0)))));
    let cos = 1.0
        + x2 * (-0.5
            + x2 * (1.0 / 24.0
                + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40_320.0 + x2 * (-1.0 / 3_628_800.0)))));
    (sin, cos)
}

/// Cosine-weighted direction on the +z hemisphere (the concentric disc lifted to it);
/// density cosθ/π.
pub fn cosine_hemisphere(u: Vec2) -> Vec3A {
    let d = concentric_disc(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3A::new(d.x, d.y, z)
}

/// Multiple importance sampling: the power heuristic (beta 2) for one sample of each strategy.
pub fn power_heuristic(pdf_a: f32, pdf_b: f32) -> f32 {
    let (a, b) = (pdf_a * pdf_a, pdf_b * pdf_b);
    if a.is_infinite() {
        return 1.0;
    }
    if a + b > 0.0 {
        a / (a + b)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The polynomials agree with f64 sine and cosine to f32 rounding over [-π/4, π/4].
    #[test]
    fn quarter_sine_and_cosine_are_f32_accurate() {
        let mut worst = 0.0f64;
        for i in 0..=20_000 {
            let x = -PI / 4.0 + (PI / 2.0) * i as f32 / 20_000.0;
            let (s, c) = sin_cos_quarter(x);
            let xd = f64::from(x);
            worst = worst
                .max((f64::from(s) - xd.sin()).abs())
                .max((f64::from(c) - xd.cos()).abs());
        }
        assert!(worst < 1.5e-7, "worst error {worst:e}");
        let (s, c) = sin_cos_quarter(0.0);
        assert_eq!((s, c), (0.0, 1.0));
    }

    #[test]
    fn frame_is_orthonormal() {
        for n in [Vec3A::Z, -Vec3A::Z, Vec3A::new(0.3, -0.5, 0.8).normalize()] {
            let (s, t) = coordinate_system(n);
            assert!(s.dot(t).abs() < 1e-5 && s.dot(n).abs() < 1e-5 && t.dot(n).abs() < 1e-5);
            assert!((s.length() - 1.0).abs() < 1e-5 && (t.length() - 1.0).abs() < 1e-5);
        }
    }

    #[test]
    fn cone_directions_stay_in_cone() {
        let c = 0.9;
        for i in 0..10 {
            for j in 0..10 {
                let d = uniform_cone(Vec2::new(i as f32 / 10.0, j as f32 / 10.0), c);
                assert!(d.z >= c - 1e-6 && (d.length() - 1.0).abs() < 1e-5);
            }
        }
    }
}
