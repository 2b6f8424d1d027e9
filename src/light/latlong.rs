//! The lat-long (equirectangular) parameterisation shared by the environment lights (infinite
//! with a map, sky): light-space direction ↔ (s, t) ∈ [0, 1) × [0, 1] with φ = 2π s around +z and
//! θ = π t from +z, and directions sampled from a piecewise-constant [`PiecewiseConstant2D`] over
//! (s, t), whose solid-angle pdf is `pdf(s, t) / (2π² sin θ)`; and the light sample and power
//! of a sky sampled that way (`sky`, `sky2`), which differ only in their radiance.

use super::LightSample;
use crate::geometry::Interaction;
use crate::sampling::PiecewiseConstant2D;
use crate::spectrum::Rgb;
use glam::{Mat4, Vec2, Vec3A};
use std::f32::consts::PI;

/// Light-space direction to lat-long coordinates (s, t), and sin θ.
pub fn dir_to_st(d: Vec3A) -> (f32, f32, f32) {
    let theta = d.z.clamp(-1.0, 1.0).acos();
    let mut phi = d.y.atan2(d.x);
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    (phi / (2.0 * PI), theta / PI, theta.sin())
}

/// Lat-long coordinates to the light-space direction, and sin θ.
pub fn st_to_dir(s: f32, t: f32) -> (Vec3A, f32) {
    let (phi, theta) = (s * 2.0 * PI, t * PI);
    let sin_t = theta.sin();
    (
        Vec3A::new(sin_t * phi.cos(), sin_t * phi.sin(), theta.cos()),
        sin_t,
    )
}

/// Samples a world direction from `dist`: (direction, [s, t], solid-angle pdf), or None at a
/// pole or a zero-probability cell.
pub fn sample(dist: &PiecewiseConstant2D, l2w: &Mat4, u: Vec2) -> Option<(Vec3A, [f32; 2], f32)> {
    let ([s, t], pdf_st) = dist.sample(u.x, u.y);
    let (d, sin_t) = st_to_dir(s, t);
    if sin_t <= 0.0 || pdf_st <= 0.0 {
        return None;
    }
    let wi = l2w.transform_vector3a(d).normalize_or_zero();
    Some((wi, [s, t], pdf_st / (2.0 * PI * PI * sin_t)))
}

/// Solid-angle pdf of [`sample`] returning the world direction `wi`.
pub fn pdf(dist: &PiecewiseConstant2D, w2l: &Mat4, wi: Vec3A) -> f32 {
    let d = w2l.transform_vector3a(wi).normalize_or_zero();
    let (s, t, sin_t) = dir_to_st(d);
    if sin_t <= 0.0 {
        return 0.0;
    }
    dist.pdf(s, t) / (2.0 * PI * PI * sin_t)
}

/// A light sample of a sky sampled by [`sample`]: `radiance(s, t)` at the lat-long coordinates
/// drawn, arriving at `r` from the sphere of radius `world_radius` around the scene.
pub fn sample_li(
    dist: &PiecewiseConstant2D,
    l2w: &Mat4,
    r: &Interaction,
    u: Vec2,
    world_radius: f32,
    radiance: impl FnOnce(f32, f32) -> Rgb,
) -> Option<LightSample> {
    let (wi, [s, t], pdf) = sample(dist, l2w, u)?;
    Some(LightSample::from_infinity(
        r,
        wi,
        radiance(s, t),
        pdf,
        false,
        world_radius,
    ))
}

/// Luminous power of a sky of mean luminance `mean_y` through a disc of the scene's radius
/// (as the infinite light's).
pub fn sky_power(mean_y: f32, world_radius: f32) -> f32 {
    mean_y * 4.0 * PI * PI * world_radius * world_radius
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn st_round_trip() {
        for (s, t) in [(0.1, 0.2), (0.5, 0.5), (0.9, 0.75)] {
            let (d, _) = st_to_dir(s, t);
            let (s2, t2, _) = dir_to_st(d);
            assert!((s - s2).abs() < 1e-5 && (t - t2).abs() < 1e-5);
        }
    }
}
