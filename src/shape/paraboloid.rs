//! `paraboloid`: `x² + y² = radius² z / zmax`, `float radius` (1), `zmin` (0), `zmax` (1),
//! `phimax` (360), as LuxRender's paraboloid.cpp.

use super::quadric::{z_range, Quadric, Surface};
use super::{Build, BuildError};

pub(crate) fn build(b: &Build) -> Result<Quadric, BuildError> {
    let r = b.float("radius", 1.0)?.abs();
    let (zmin, zmax) = z_range(b, 0.0, 1.0)?;
    if r == 0.0 || zmax <= 0.0 || zmin < 0.0 {
        return Err(b.err("need radius != 0 and 0 <= zmin < zmax"));
    }
    let surface = Surface::Paraboloid {
        r,
        zmin,
        zmax,
        zcap: zmax,
    };
    Quadric::new(b, surface, b.phimax()?)
}
