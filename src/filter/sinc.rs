//! Lanczos-windowed sinc filter, separable: per axis, with `x = |d| / width`,
//! `sinc(pi x tau) * sinc(pi x)` for `x <= 1`, 0 beyond, 1 at the centre.
//!
//! LuxRender defaults: `xwidth` = `ywidth` = 4, `tau` = 3.

use super::{widths, FilterKind};
use crate::plugin::{BuildError, Stmt};
use glam::Vec2;

fn axis(x: f32, tau: f32) -> f32 {
    let x = x.abs();
    if x < 1e-5 {
        return 1.0;
    }
    if x > 1.0 {
        return 0.0;
    }
    let px = x * std::f32::consts::PI;
    let sinc = (px * tau).sin() / (px * tau);
    let lanczos = px.sin() / px;
    sinc * lanczos
}

pub(super) fn eval(dx: f32, dy: f32, xw: f32, yw: f32, tau: f32) -> f32 {
    axis(dx / xw, tau) * axis(dy / yw, tau)
}

pub(super) const DEFAULT_WIDTH: f32 = 4.0;
pub(super) const DEFAULT_TAU: f32 = 3.0;

/// Reads a `sinc` statement (`tau`).
pub(super) fn build(s: &Stmt) -> Result<(FilterKind, Vec2), BuildError> {
    let w = widths(s, DEFAULT_WIDTH)?;
    let tau = s.finite("tau", DEFAULT_TAU)?;
    Ok((FilterKind::Sinc { tau }, w))
}
