//! Scattering functions in the local shading frame (z = shading normal). Each works on local
//! directions `wo` (towards the viewer) and `wi` (towards the light), returns `f` without the
//! cosine factor, and samples with a pdf consistent with `f` (solid-angle measure; for
//! specular lobes the pdf is the discrete probability of the lobe and `f` carries 1/|cos|).

pub mod asperity;
pub mod carpaint;
pub mod diffuse;
pub mod fresnel;
pub mod fresnel_blend;
pub mod glossy_translucent;
pub mod irawan;
pub mod microfacet;
pub mod perlin;
pub mod rough_dielectric;
pub mod scatter;
pub mod schlick;
pub mod specular;
pub mod thin_film;
pub mod translucent;

use crate::spectrum::Rgb;
use glam::Vec3A;

/// A sampled direction in the local frame.
#[derive(Clone, Copy, Debug)]
pub struct LocalSample {
    pub wi: Vec3A,
    pub f: Rgb,
    pub pdf: f32,
    pub specular: bool,
}

pub fn same_hemisphere(a: Vec3A, b: Vec3A) -> bool {
    a.z * b.z > 0.0
}

/// Mirror direction of `wo` about `n` (both pointing away from the surface).
pub fn reflect(wo: Vec3A, n: Vec3A) -> Vec3A {
    2.0 * wo.dot(n) * n - wo
}

/// Refraction of `wo` through a surface with normal `n` (on the side of `wo`) and relative
/// index `eta = eta_i / eta_t` (incident over transmitted). `None` on total internal reflection.
pub fn refract(wo: Vec3A, n: Vec3A, eta: f32) -> Option<Vec3A> {
    let cos_i = wo.dot(n);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(-wo * eta + n * (eta * cos_i - cos_t))
}

pub use crate::sampling::cosine_hemisphere;

/// Average of the three channels (lobe selection weights).
pub fn avg(c: Rgb) -> f32 {
    (c.r + c.g + c.b) / 3.0
}
