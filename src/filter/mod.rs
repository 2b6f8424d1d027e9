//! Pixel filters: box, gaussian, mitchell, triangle, sinc, catmullrom, blackmanharris.
//!
//! [`Filter::build`] dispatches a `PixelFilter` statement to the filter's file, which reads its
//! parameters with LuxRender's names and defaults (mitchell when the scene has none, as
//! LuxRender). [`Filter::eval`] is the filter
//! function itself; [`Filter::splat`] gives the pixels a sample contributes to and their
//! weights exactly as LuxRender's fleximage film computes them: from precomputed tables per
//! quantised sub-pixel offset, normalised so one sample's weights sum to 1 (see [`lut`]).
//!
//! Conventions: raster coordinates over the full image, pixel `(x, y)` covers
//! `[x, x+1) x [y, y+1)` and has its centre at `(x + 0.5, y + 0.5)`.

mod blackmanharris;
mod box_filter;
mod catmullrom;
mod gaussian;
pub mod lut;
mod mitchell;
mod sinc;
mod triangle;

pub use gaussian::Gaussian;
pub use lut::{FilterLut, FilterLuts};
pub use mitchell::Mitchell;

use crate::lxs::{Diagnostic, Entity};
use crate::plugin::{BuildError, Stmt};
use glam::Vec2;

/// LuxRender's Film `filterquality` default (tables per axis: 2^4 + 1).
pub const DEFAULT_FILTER_QUALITY: i32 = 4;

/// The filter function and its parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FilterKind {
    Box,
    Gaussian(Gaussian),
    Mitchell(Mitchell),
    Triangle,
    /// Lanczos-windowed sinc with its `tau`.
    Sinc {
        tau: f32,
    },
    CatmullRom,
    BlackmanHarris,
}

/// A pixel filter with its splat tables.
#[derive(Clone, Debug, PartialEq)]
pub struct Filter {
    kind: FilterKind,
    /// The `xwidth`/`ywidth` parameters as given.
    width: Vec2,
    /// Half-extent of the pixels a sample reaches (LuxRender's filter xWidth/yWidth: the
    /// parameters, except mitchell with supersample: 5/3 of them).
    radius: Vec2,
    luts: FilterLuts,
}

impl Filter {
    /// Builds the filter of a `PixelFilter` statement (`None`: LuxRender's default, mitchell).
    /// Each filter file reads its own parameters; this only dispatches on the name.
    pub fn build(e: Option<&Entity>, warnings: &mut Vec<Diagnostic>) -> Result<Filter, BuildError> {
        let Some(e) = e else {
            return Ok(Filter::new(
                FilterKind::Mitchell(Mitchell::new(
                    mitchell::DEFAULT_B,
                    mitchell::DEFAULT_C,
                    false,
                )),
                Vec2::splat(mitchell::DEFAULT_WIDTH),
            ));
        };
        let mut s = Stmt::new("pixel filter", e, warnings);
        let (kind, width) = match e.kind.as_str() {
            "box" => box_filter::build(&s)?,
            "gaussian" => gaussian::build(&s)?,
            "mitchell" => mitchell::build(&s)?,
            "triangle" => triangle::build(&s)?,
            "sinc" => sinc::build(&s)?,
            "catmullrom" => catmullrom::build(&s)?,
            "blackmanharris" => blackmanharris::build(&s)?,
            other => {
                return Err(s.err(format!(
                    "unknown pixel filter \"{other}\" (known: box, gaussian, mitchell, triangle, sinc, catmullrom, blackmanharris)"
                )))
            }
        };
        let f = Filter::new(kind, width);
        if !f.luts.all_finite() || !f.eval(0.0, 0.0).is_finite() {
            return Err(s.err(format!(
                "pixel filter \"{}\": its parameters give non-finite filter values",
                e.kind
            )));
        }
        if !f.luts.all_normalised() {
            s.warn(format!(
                "pixel filter \"{}\" gives no weight to any pixel centre for some sample \
                 positions; samples there are lost (as in LuxRender)",
                e.kind
            ));
        }
        Ok(f)
    }

    /// A filter from its function and `xwidth`/`ywidth`, with the default table quality.
    pub fn new(kind: FilterKind, width: Vec2) -> Filter {
        let radius = match kind {
            FilterKind::Mitchell(m) => {
                let (sx, sy) = m.support(width.x, width.y);
                Vec2::new(sx, sy)
            }
            _ => width,
        };
        let mut f = Filter {
            kind,
            width,
            radius,
            luts: FilterLuts::new(1, 0.5, 0.5, &|_, _| 1.0),
        };
        f.luts = f.build_luts(DEFAULT_FILTER_QUALITY);
        f
    }

    /// Rebuilds the splat tables for the Film's `filterquality` (LuxRender default 4).
    pub fn with_filter_quality(mut self, quality: i32) -> Filter {
        self.luts = self.build_luts(quality);
        self
    }

    fn build_luts(&self, quality: i32) -> FilterLuts {
        FilterLuts::new(quality, self.radius.x, self.radius.y, &|dx, dy| {
            self.eval(dx, dy)
        })
    }

    pub fn kind(&self) -> &FilterKind {
        &self.kind
    }

    /// Half-extent (pixels) of the region a sample contributes to.
    pub fn radius(&self) -> Vec2 {
        self.radius
    }

    /// The filter function at offset (`dx`, `dy`) pixels from the sample, as LuxRender
    /// defines it (not normalised); 0 beyond [`Filter::radius`].
    pub fn eval(&self, dx: f32, dy: f32) -> f32 {
        let (dx, dy) = (dx.abs(), dy.abs());
        if dx > self.radius.x || dy > self.radius.y {
            return 0.0;
        }
        let (w, r) = (self.width, self.radius);
        match &self.kind {
            FilterKind::Box => box_filter::eval(dx, dy, w.x, w.y),
            FilterKind::Gaussian(g) => g.eval(dx, dy),
            FilterKind::Mitchell(m) => m.eval(dx, dy, r.x, r.y),
            FilterKind::Triangle => triangle::eval(dx, dy, w.x, w.y),
            FilterKind::Sinc { tau } => sinc::eval(dx, dy, w.x, w.y, *tau),
            FilterKind::CatmullRom => catmullrom::eval(dx, dy, w.x, w.y),
            FilterKind::BlackmanHarris => blackmanharris::eval(dx, dy, w.x, w.y),
        }
    }

    /// Calls `f(x, y, weight)` for every pixel (full-image raster indices, not clipped to the
    /// image or crop window: the caller drops what lies outside its buffer) that a sample at
    /// raster position `p_film` contributes to, with LuxRender's normalised table weight.
    /// Pixels whose weight is exactly 0 are skipped (they add nothing). Weights may be negative
    /// (mitchell, catmullrom, sinc lobes). A non-finite `p_film` visits nothing.
    pub fn splat(&self, p_film: Vec2, mut f: impl FnMut(i32, i32, f32)) {
        self.each_cell(p_film, |x, y, w| {
            if w != 0.0 {
                f(x, y, w);
            }
        });
    }

    /// Calls `f(x, y)` for every pixel of the filter's footprint around `p_film`, whatever
    /// its weight (LuxRender adds a sample's depth with weight 1 to each of them).
    pub fn footprint(&self, p_film: Vec2, mut f: impl FnMut(i32, i32)) {
        self.each_cell(p_film, |x, y, _| f(x, y));
    }

    /// Every cell of the weight table placed at `p_film`, zero weights included.
    fn each_cell(&self, p_film: Vec2, mut f: impl FnMut(i32, i32, f32)) {
        if !p_film.is_finite() {
            return;
        }
        let d = p_film - Vec2::splat(0.5);
        let lut = self
            .luts
            .get(d.x - p_film.x.floor(), d.y - p_film.y.floor());
        let x0 = (d.x - self.radius.x).ceil() as i32;
        let y0 = (d.y - self.radius.y).ceil() as i32;
        for (row, ws) in lut.weights.chunks_exact(lut.width.max(1)).enumerate() {
            for (col, &w) in ws.iter().enumerate() {
                f(x0 + col as i32, y0 + row as i32, w);
            }
        }
    }

    /// The pixel range LuxRender samples so that the crop window's border pixels get full
    /// filter coverage (`Film::GetSampleExtent`): for pixels `start .. start + count` on each
    /// axis, returns `[x0, x1, y0, y1]` (half-open), possibly beyond the image.
    pub fn sample_extent(
        &self,
        x_start: u32,
        x_count: u32,
        y_start: u32,
        y_count: u32,
    ) -> [i32; 4] {
        let lo = |s: u32, r: f32| (s as f32 + 0.5 - r).floor() as i32;
        let hi = |s: u32, c: u32, r: f32| (s as f32 + 0.5 + c as f32 + r).floor() as i32;
        [
            lo(x_start, self.radius.x),
            hi(x_start, x_count, self.radius.x),
            lo(y_start, self.radius.y),
            hi(y_start, y_count, self.radius.y),
        ]
    }
}

/// `xwidth`/`ywidth` of a filter statement: positive and finite.
fn widths(s: &Stmt, default: f32) -> Result<Vec2, BuildError> {
    let p = s.params();
    let w = Vec2::new(p.float_or("xwidth", default), p.float_or("ywidth", default));
    if !(w.x > 0.0 && w.y > 0.0 && w.is_finite()) {
        return Err(s.err(format!(
            "pixel filter \"{}\": xwidth/ywidth must be positive, got {} {}",
            s.kind(),
            w.x,
            w.y
        )));
    }
    Ok(w)
}

#[cfg(test)]
mod tests;
