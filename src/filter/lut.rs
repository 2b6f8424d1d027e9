//! Precomputed splat weights, the way LuxRender's film applies a pixel filter.
//!
//! LuxRender's fleximage film does not evaluate the filter per sample. At start it builds a
//! grid of `(q + 1)²` lookup tables, one per quantised sub-pixel offset of the sample
//! (`q = 2^filterquality`, 16 by default), each holding the filter values at the pixel
//! centres around that offset, **normalised so the table sums to 1**. A sample then adds
//! `weight * table[i]` to every pixel of the table chosen by its sub-pixel offset. We
//! replicate that: same table layout, same offset quantisation, same normalisation, so a pixel's
//! weight sum and the weighted XYZ sums match LuxRender's film.

/// One table: the normalised weights of the pixels `x0 .. x0 + width` relative to the pixel
/// containing the sample, rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct FilterLut {
    pub width: usize,
    pub height: usize,
    pub weights: Vec<f32>,
}

impl FilterLut {
    /// The table for a sample at sub-pixel offset (`ox`, `oy`) in [-0.5, 0.5) relative to the
    /// centre of its pixel. `eval` takes absolute offsets; `rx`, `ry` are the filter radii.
    fn build(ox: f32, oy: f32, rx: f32, ry: f32, eval: &dyn Fn(f32, f32) -> f32) -> FilterLut {
        let (x0, x1) = ((ox - rx).ceil() as i64, (ox + rx).floor() as i64);
        let (y0, y1) = ((oy - ry).ceil() as i64, (oy + ry).floor() as i64);
        // A support narrower than the pixel spacing may contain no pixel centre: LuxRender then
        // keeps one entry evaluated at the centre offset 0 on that axis.
        let xs: Vec<f32> = if x1 >= x0 {
            (x0..=x1).map(|ix| (ix as f32 - ox).abs()).collect()
        } else {
            vec![0.0]
        };
        let ys: Vec<f32> = if y1 >= y0 {
            (y0..=y1).map(|iy| (iy as f32 - oy).abs()).collect()
        } else {
            vec![0.0]
        };
        let mut weights = Vec::with_capacity(xs.len() * ys.len());
        for &dy in &ys {
            for &dx in &xs {
                weights.push(eval(dx, dy));
            }
        }
        let total: f32 = weights.iter().sum();
        if total > 0.0 {
            for w in &mut weights {
                *w /= total;
            }
        }
        FilterLut {
            width: xs.len(),
            height: ys.len(),
            weights,
        }
    }
}

/// The grid of tables for every quantised sub-pixel offset.
#[derive(Clone, Debug, PartialEq)]
pub struct FilterLuts {
    /// Tables per axis (`q + 1`).
    size: usize,
    luts: Vec<FilterLut>,
}

impl FilterLuts {
    /// `quality`: LuxRender's Film `filterquality` (default 4): `q = 2^max(quality, 1)`,
    /// clamped to [2, 64].
    pub fn new(quality: i32, rx: f32, ry: f32, eval: &dyn Fn(f32, f32) -> f32) -> FilterLuts {
        let q = 1u32 << quality.clamp(1, 6);
        let q = q.clamp(2, 64) as usize;
        let size = q + 1;
        let step = 1.0 / q as f32;
        let mut luts = Vec::with_capacity(size * size);
        for iy in 0..size {
            for ix in 0..size {
                let ox = ix as f32 * step - 0.5 + step / 2.0;
                let oy = iy as f32 * step - 0.5 + step / 2.0;
                luts.push(FilterLut::build(ox, oy, rx, ry, eval));
            }
        }
        FilterLuts { size, luts }
    }

    /// Whether every table weight is a finite number.
    pub fn all_finite(&self) -> bool {
        self.luts
            .iter()
            .all(|l| l.weights.iter().all(|w| w.is_finite()))
    }

    /// Whether every table's weights sum to 1, i.e. no sub-pixel position loses its samples
    /// (a table whose filter values sum to 0 or less is left unnormalised, as in LuxRender).
    pub fn all_normalised(&self) -> bool {
        self.luts
            .iter()
            .all(|l| (l.weights.iter().map(|&w| f64::from(w)).sum::<f64>() - 1.0).abs() < 1e-3)
    }

    /// The table LuxRender picks for sub-pixel offsets `ox`, `oy` in [-0.5, 0.5).
    pub fn get(&self, ox: f32, oy: f32) -> &FilterLut {
        let last = self.size as i64 - 1;
        let pick = |o: f32| ((self.size as f32 * (o + 0.5)).floor() as i64).clamp(0, last) as usize;
        // `pick` is within 0..size, so the index is within the table grid.
        &self.luts[pick(ox) + pick(oy) * self.size]
    }
}
