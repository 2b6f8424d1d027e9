//! `hyperboloid`: the segment `point p1` (0 0 0) – `point p2` (1 1 1) swept by `phimax` (360)
//! around z, as LuxRender's hyperboloid.cpp. A segment with p1.z == p2.z sweeps a flat
//! annulus, which is rejected (use a disk).

use super::quadric::{Quadric, Surface};
use super::{Build, BuildError};
use glam::DVec3;

pub(crate) fn build(b: &Build) -> Result<Quadric, BuildError> {
    let p = |name: &str, default: [f32; 3]| {
        let v = b.params().point(name).unwrap_or(default);
        let v = DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64);
        if v.is_finite() {
            Ok(v)
        } else {
            Err(b.err(format!("\"{name}\" is not finite")))
        }
    };
    let p1 = p("p1", [0.0, 0.0, 0.0])?;
    let p2 = p("p2", [1.0, 1.0, 1.0])?;
    if p1.z == p2.z {
        return Err(b.err("p1 and p2 have the same z: the surface is a flat annulus"));
    }
    Quadric::new(b, Surface::Hyperboloid { p1, p2 }, b.phimax()?)
}
