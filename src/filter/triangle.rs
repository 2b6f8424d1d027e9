//! Triangle (tent) filter, separable: `max(0, xwidth - |dx|) * max(0, ywidth - |dy|)`.
//!
//! As in LuxRender the value is not scaled to 1 at the centre (it is `xwidth * ywidth`
//! there); the film normalises the splat weights per sample, so only the shape matters.
//! LuxRender defaults: `xwidth` = `ywidth` = 2.

use super::{widths, FilterKind};
use crate::plugin::{BuildError, Stmt};
use glam::Vec2;

pub(super) fn eval(dx: f32, dy: f32, xw: f32, yw: f32) -> f32 {
    (xw - dx.abs()).max(0.0) * (yw - dy.abs()).max(0.0)
}

pub(super) const DEFAULT_WIDTH: f32 = 2.0;

/// Reads a `triangle` statement.
pub(super) fn build(s: &Stmt) -> Result<(FilterKind, Vec2), BuildError> {
    Ok((FilterKind::Triangle, widths(s, DEFAULT_WIDTH)?))
}
