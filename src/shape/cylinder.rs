//! `cylinder`: `float radius` (1), `zmin` (-1), `zmax` (1), `phimax` (360), as LuxRender's
//! cylinder.cpp; open at both ends.

use super::quadric::{z_range, Quadric, Surface};
use super::{Build, BuildError};

pub(crate) fn build(b: &Build) -> Result<Quadric, BuildError> {
    let r = b.float("radius", 1.0)?.abs();
    let (zmin, zmax) = z_range(b, -1.0, 1.0)?;
    if r == 0.0 || zmin == zmax {
        return Err(b.err("zero radius or height"));
    }
    Quadric::new(b, Surface::Cylinder { r, zmin, zmax }, b.phimax()?)
}
