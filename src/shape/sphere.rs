//! `sphere`: `float radius` (1), `zmin` (-radius), `zmax` (radius), `phimax` (360 degrees),
//! as LuxRender's sphere.cpp. Intersected analytically (see [`super::quadric`]).

use super::quadric::{z_range, Quadric, Surface};
use super::{Build, BuildError};

pub(crate) fn build(b: &Build) -> Result<Quadric, BuildError> {
    let r = b.float("radius", 1.0)?.abs();
    if r == 0.0 {
        return Err(b.err("radius must not be 0"));
    }
    let (z0, z1) = z_range(b, -r as f32, r as f32)?;
    let (zmin, zmax) = (z0.clamp(-r, r), z1.clamp(-r, r));
    let surface = Surface::Sphere {
        r,
        zmin,
        zmax,
        theta_zmin: (zmin / r).clamp(-1.0, 1.0).acos(),
        theta_zmax: (zmax / r).clamp(-1.0, 1.0).acos(),
    };
    Quadric::new(b, surface, b.phimax()?)
}
