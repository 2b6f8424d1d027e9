//! Geometry basics: rays, bounds, transforms, surface interactions and robust ray offsets.
//!
//! Rays and hit points are f32 (glam `Vec3A`); every hit point carries a conservative bound on
//! its floating-point error, and secondary rays start outside that bound (see
//! [`interaction::offset_ray_origin`]), so self-intersection avoidance does not depend on the
//! scene's scale.

pub mod frame;
pub mod interaction;
pub mod motion;
pub mod ray;
pub mod transform;

pub use glam::{Vec2, Vec3A};
pub use interaction::{HitData, Interaction, Shading, SurfaceInteraction};
pub use ray::Ray;
pub use transform::Transform;

/// Whether `v` has unit length to within a few roundings (then normalising it again would
/// only spend a square root and a division on the renderer's hot path).
#[inline(always)]
pub fn is_unit(v: Vec3A) -> bool {
    (v.length_squared() - 1.0).abs() <= 4.0 * f32::EPSILON
}

/// `v` normalised, or `fallback` when `v` has no direction; unit vectors come back as they are.
#[inline(always)]
pub fn unit_or(v: Vec3A, fallback: Vec3A) -> Vec3A {
    if is_unit(v) {
        v
    } else {
        v.normalize_or(fallback)
    }
}
