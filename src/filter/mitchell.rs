//! Mitchell-Netravali filter as LuxRender 1.x evaluates it: *radially*, on the normalised
//! distance `r = sqrt((dx/xw)² + (dy/yw)²)`, the cubic with parameters `B`, `C` over `2r` in
//! [0, 2), 0 for `r >= 1`.
//!
//! With `supersample` the support grows to 5/3 of the width and the value is a three-tap blend
//! `a1 M(s - 2/3) + a0 M(s) + a1 M(s + 2/3)` with `s = r / 0.6`, `a0 = (76 - 16B + 8C) / 81`,
//! `a1 = (1 - a0) / 2` (LuxRender's "mitchell_ss").
//!
//! LuxRender defaults: `xwidth` = `ywidth` = 2, `B` = `C` = 1/3, `supersample` false.

use super::{widths, FilterKind};
use crate::plugin::{BuildError, Stmt};
use glam::Vec2;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mitchell {
    pub b: f32,
    pub c: f32,
    pub supersample: bool,
    a0: f32,
    a1: f32,
}

impl Mitchell {
    pub fn new(b: f32, c: f32, supersample: bool) -> Mitchell {
        let a0 = (76.0 - 16.0 * b + 8.0 * c) / 81.0;
        Mitchell {
            b,
            c,
            supersample,
            a0,
            a1: (1.0 - a0) / 2.0,
        }
    }

    /// Support half-widths for the requested widths (5/3 larger with supersampling).
    pub fn support(&self, xw: f32, yw: f32) -> (f32, f32) {
        if self.supersample {
            (xw * 5.0 / 3.0, yw * 5.0 / 3.0)
        } else {
            (xw, yw)
        }
    }

    /// The 1D cubic on `x` in units of the support (0 at `x >= 1`).
    fn cubic(&self, x: f32) -> f32 {
        if x >= 1.0 {
            return 0.0;
        }
        let (b, c) = (self.b, self.c);
        let x = (2.0 * x).abs();
        if x > 1.0 {
            (((-b / 6.0 - c) * x + (b + 5.0 * c)) * x + (-2.0 * b - 8.0 * c)) * x
                + (4.0 / 3.0 * b + 4.0 * c)
        } else {
            ((2.0 - 1.5 * b - c) * x + (-3.0 + 2.0 * b + c)) * x * x + (1.0 - b / 3.0)
        }
    }

    /// `sx`, `sy`: the support half-widths (see [`Mitchell::support`]).
    pub(super) fn eval(&self, dx: f32, dy: f32, sx: f32, sy: f32) -> f32 {
        let (nx, ny) = (dx / sx, dy / sy);
        let r = (nx * nx + ny * ny).sqrt();
        if !self.supersample {
            return self.cubic(r);
        }
        let s = r / 0.6;
        self.a1 * self.cubic(s - 2.0 / 3.0)
            + self.a0 * self.cubic(s)
            + self.a1 * self.cubic(s + 2.0 / 3.0)
    }
}

pub(super) const DEFAULT_WIDTH: f32 = 2.0;
pub(super) const DEFAULT_B: f32 = 1.0 / 3.0;
pub(super) const DEFAULT_C: f32 = 1.0 / 3.0;

/// Reads a `mitchell` statement (`B`, `C`, `supersample`).
pub(super) fn build(s: &Stmt) -> Result<(FilterKind, Vec2), BuildError> {
    let w = widths(s, DEFAULT_WIDTH)?;
    let b = s.finite("B", DEFAULT_B)?;
    let c = s.finite("C", DEFAULT_C)?;
    let ss = s.params().bool_or("supersample", false);
    Ok((FilterKind::Mitchell(Mitchell::new(b, c, ss)), w))
}
