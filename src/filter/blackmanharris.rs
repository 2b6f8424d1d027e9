//! Blackman-Harris filter, separable, as LuxRender defines it: per axis with
//! `t = d * 2 / width` the 4-term Blackman-Harris window over `t` in [-1, 1], i.e. the kernel
//! spans *half* the filter width (LuxRender's quirk), 0 beyond.
//!
//! LuxRender defaults: `xwidth` = `ywidth` = 4.

use super::{widths, FilterKind};
use crate::plugin::{BuildError, Stmt};
use glam::Vec2;

fn axis(t: f32) -> f32 {
    if !(-1.0..=1.0).contains(&t) {
        return 0.0;
    }
    let x = (t + 1.0) * 0.5 * std::f32::consts::PI;
    const A0: f32 = 0.35875;
    const A1: f32 = -0.48829;
    const A2: f32 = 0.14128;
    const A3: f32 = -0.01168;
    A0 + A1 * (2.0 * x).cos() + A2 * (4.0 * x).cos() + A3 * (6.0 * x).cos()
}

pub(super) fn eval(dx: f32, dy: f32, xw: f32, yw: f32) -> f32 {
    axis(dx * 2.0 / xw) * axis(dy * 2.0 / yw)
}

pub(super) const DEFAULT_WIDTH: f32 = 4.0;

/// Reads a `blackmanharris` statement.
pub(super) fn build(s: &Stmt) -> Result<(FilterKind, Vec2), BuildError> {
    Ok((FilterKind::BlackmanHarris, widths(s, DEFAULT_WIDTH)?))
}
