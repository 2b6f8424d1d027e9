//! Catmull-Rom filter, separable, as LuxRender defines it: per axis on the *unscaled* offset
//! `x = |d|` (pixels), `3x³ - 5x² + 2` for `x < 1`, `-x³ + 5x² - 8x + 4` for `1 <= x < 2`,
//! 0 beyond 2 whatever the width (twice the textbook kernel; the film normalises weights).
//!
//! LuxRender defaults: `xwidth` = `ywidth` = 4 (the pixels the film visits; the kernel itself
//! ends at 2 pixels).

use super::{widths, FilterKind};
use crate::plugin::{BuildError, Stmt};
use glam::Vec2;

fn axis(x: f32) -> f32 {
    let x = x.abs();
    let x2 = x * x;
    if x >= 2.0 {
        0.0
    } else if x < 1.0 {
        3.0 * x * x2 - 5.0 * x2 + 2.0
    } else {
        -(x * x2) + 5.0 * x2 - 8.0 * x + 4.0
    }
}

pub(super) fn eval(dx: f32, dy: f32, xw: f32, yw: f32) -> f32 {
    if dx.abs() > xw || dy.abs() > yw {
        return 0.0;
    }
    axis(dx) * axis(dy)
}

pub(super) const DEFAULT_WIDTH: f32 = 4.0;

/// Reads a `catmullrom` statement.
pub(super) fn build(s: &Stmt) -> Result<(FilterKind, Vec2), BuildError> {
    Ok((FilterKind::CatmullRom, widths(s, DEFAULT_WIDTH)?))
}
