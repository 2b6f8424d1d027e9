//! Box filter: every pixel within `xwidth`/`ywidth` of the sample gets the same weight.
//!
//! LuxRender defaults: `xwidth` = `ywidth` = 0.5 (only the pixel containing the sample).

use super::{widths, FilterKind};
use crate::plugin::{BuildError, Stmt};
use glam::Vec2;

/// Weight at offset (`dx`, `dy`) from the sample, 0 outside the support.
pub(super) fn eval(dx: f32, dy: f32, xw: f32, yw: f32) -> f32 {
    if dx.abs() <= xw && dy.abs() <= yw {
        1.0
    } else {
        0.0
    }
}

pub(super) const DEFAULT_WIDTH: f32 = 0.5;

/// Reads a `box` statement.
pub(super) fn build(s: &Stmt) -> Result<(FilterKind, Vec2), BuildError> {
    Ok((FilterKind::Box, widths(s, DEFAULT_WIDTH)?))
}
