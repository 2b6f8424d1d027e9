//! Gaussian filter, separable, shifted so that it reaches 0 at the filter width:
//! `max(0, exp(-alpha d²) - exp(-alpha w²))` per axis.
//!
//! LuxRender defaults: `xwidth` = `ywidth` = 2, `alpha` = 2.

use super::{widths, FilterKind};
use crate::plugin::{BuildError, Stmt};
use glam::Vec2;

/// Precomputed per-axis offsets `exp(-alpha w²)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gaussian {
    pub alpha: f32,
    exp_x: f32,
    exp_y: f32,
}

impl Gaussian {
    pub fn new(alpha: f32, xw: f32, yw: f32) -> Gaussian {
        Gaussian {
            alpha,
            exp_x: (-alpha * xw * xw).exp(),
            exp_y: (-alpha * yw * yw).exp(),
        }
    }

    fn axis(&self, d: f32, expv: f32) -> f32 {
        ((-self.alpha * d * d).exp() - expv).max(0.0)
    }

    pub(super) fn eval(&self, dx: f32, dy: f32) -> f32 {
        self.axis(dx, self.exp_x) * self.axis(dy, self.exp_y)
    }
}

pub(super) const DEFAULT_WIDTH: f32 = 2.0;
pub(super) const DEFAULT_ALPHA: f32 = 2.0;

/// Reads a `gaussian` statement (`alpha`).
pub(super) fn build(s: &Stmt) -> Result<(FilterKind, Vec2), BuildError> {
    let w = widths(s, DEFAULT_WIDTH)?;
    let alpha = s.finite("alpha", DEFAULT_ALPHA)?;
    Ok((FilterKind::Gaussian(Gaussian::new(alpha, w.x, w.y)), w))
}
