//! `disk`: at z = `height` (0), `float radius` (1), `innerradius` (0), `phimax` (360), as
//! LuxRender's disk.cpp; its normal is +z (before ReverseOrientation).

use super::quadric::{Quadric, Surface};
use super::{Build, BuildError};

pub(crate) fn build(b: &Build) -> Result<Quadric, BuildError> {
    let h = b.float("height", 0.0)?;
    let r = b.float("radius", 1.0)?.abs();
    let ri = b.float("innerradius", 0.0)?.abs();
    if r <= ri {
        return Err(b.err(format!("radius {r} must exceed innerradius {ri}")));
    }
    Quadric::new(b, Surface::Disk { h, r, ri }, b.phimax()?)
}
