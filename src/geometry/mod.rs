//! Geometry basics: rays, bounds, transforms, surface interactions and robust ray offsets.
//!
//! Rays and hit points are f32 (glam `Vec3A`); every hit point carries a conservative bound on
//! its floating-point error, and secondary rays start outside that bound (see
//! [`interaction::offset_ray_origin`]), so self-intersection avoidance does not depend on the
//! scene's scale.

pub mod distribution;
pub mod frame;
pub mod interaction;
pub mod ray;
pub mod transform;

pub use distribution::Distribution1D;
pub use glam::{Vec2, Vec3A};
pub use interaction::{Interaction, Shading, SurfaceInteraction};
pub use ray::Ray;
pub use transform::Transform;
