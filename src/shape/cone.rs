//! `cone`: `float radius` (1) at z = 0, apex at `height` (1), `phimax` (360), as LuxRender's
//! cone.cpp.

use super::quadric::{Quadric, Surface};
use super::{Build, BuildError};

pub(crate) fn build(b: &Build) -> Result<Quadric, BuildError> {
    let r = b.float("radius", 1.0)?.abs();
    let h = b.float("height", 1.0)?;
    if r == 0.0 || h <= 0.0 {
        return Err(b.err("radius must not be 0 and height must be positive"));
    }
    Quadric::new(b, Surface::Cone { r, h }, b.phimax()?)
}
