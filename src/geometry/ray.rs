//! Rays: origin, direction, parametric extent and time.

use glam::Vec3A;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub o: Vec3A,
    /// Direction; not necessarily normalized.
    pub d: Vec3A,
    /// Points `o + t d` with `0 < t < t_max` are on the ray.
    pub t_max: f32,
    /// Shutter time in [0, 1], for motion blur.
    pub time: f32,
}

impl Ray {
    pub fn new(o: Vec3A, d: Vec3A) -> Ray {
        Ray {
            o,
            d,
            t_max: f32::INFINITY,
            time: 0.0,
        }
    }

    pub fn at(&self, t: f32) -> Vec3A {
        self.o + self.d * t
    }
}
