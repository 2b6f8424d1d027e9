//! A sampling map as a probability density over the sample extent, for samplers that draw
//! film positions continuously rather than pixel by pixel (metropolis' large steps and
//! start-up samples, `crate::render::mlt`).
//!
//! ```text
//! SamplingMap (film buffer pixels, mean 1) --MapWarp::new(extent size, buffer offset)-->
//!   extent pixel densities (margin pixels take the nearest buffer pixel's), mean 1
//!   --warp(u ∈ [0,1)²)--> film position as fractions of the extent, drawn with density q
//!   --density(position)--> q (1 everywhere for the uniform map)
//! ```
//!
//! A position is drawn by choosing a row in proportion to its total weight, then a pixel of
//! that row in proportion to its weight, then a point uniformly inside the pixel. Its density
//! over the unit square is the pixel's weight over the mean weight: what `density` returns,
//! so an estimator can divide by it.

use super::map::SamplingMap;

/// The densities of the extent's pixels with their cumulative sums.
#[derive(Clone, Debug, PartialEq)]
pub struct MapWarp {
    width: usize,
    height: usize,
    /// Per extent pixel, row-major: its weight over the mean weight.
    density: Vec<f32>,
    /// Cumulative row totals (length height + 1, from 0 to 1).
    rows: Vec<f64>,
    /// Per row, cumulative pixel weights within the row (width + 1 each, from 0 to 1; a row
    /// of zero weight is never chosen).
    cols: Vec<f32>,
}

impl MapWarp {
    /// `map` (the film buffer's) over an extent of `width` × `height` pixels whose pixel
    /// (0, 0) is buffer pixel `offset` (negative: left of or above the buffer). `None` when
    /// the extent is empty or every weight is zero.
    pub fn new(map: &SamplingMap, width: u32, height: u32, offset: [i64; 2]) -> Option<MapWarp> {
        let (w, h) = (width as usize, height as usize);
        if w == 0 || h == 0 {
            return None;
        }
        let nearest = |v: i64, n: u32| v.clamp(0, i64::from(n.max(1)) - 1) as u32;
        let mut weight = Vec::with_capacity(w * h);
        for y in 0..h {
            let by = nearest(offset[1] + y as i64, map.height());
            for x in 0..w {
                let bx = nearest(offset[0] + x as i64, map.width());
                let d = map.density(bx, by);
                weight.push(if d.is_finite() && d > 0.0 { d } else { 0.0 });
            }
        }
        let total: f64 = weight.iter().map(|&d| f64::from(d)).sum();
        if total <= 0.0 || !total.is_finite() {
            return None;
        }
        let mean = total / (w * h) as f64;
        let mut rows = Vec::with_capacity(h + 1);
        let mut cols = Vec::with_capacity(h * (w + 1));
        let mut acc = 0.0f64;
        rows.push(0.0);
        for row in weight.chunks(w) {
            let row_total: f64 = row.iter().map(|&d| f64::from(d)).sum();
            let mut c = 0.0f64;
            cols.push(0.0);
            for &d in row {
                c += f64::from(d);
                cols.push(if row_total > 0.0 {
                    (c / row_total) as f32
                } else {
                    0.0
                });
            }
            acc += row_total;
            rows.push(acc / total);
        }
        let density = weight
            .iter()
            .map(|&d| (f64::from(d) / mean) as f32)
            .collect();
        Some(MapWarp {
            width: w,
            height: h,
            density,
            rows,
            cols,
        })
    }

    /// The film position (fractions of the extent, each in [0, 1)) of uniform numbers `u`:
    /// `u[1]` picks the row, `u[0]` the pixel within it and the point within the pixel.
    pub fn warp(&self, u: [f32; 2]) -> [f32; 2] {
        let (j, fy) = pick(&self.rows, f64::from(u[1].clamp(0.0, 1.0)));
        let row = &self.cols[j * (self.width + 1)..(j + 1) * (self.width + 1)];
        let (i, fx) = pick(row, f64::from(u[0].clamp(0.0, 1.0)));
        let x = ((i as f64 + fx) / self.width as f64) as f32;
        let y = ((j as f64 + fy) / self.height as f64) as f32;
        [below_one(x), below_one(y)]
    }

    /// The density with which [`MapWarp::warp`] draws the film position `f` (fractions of the
    /// extent): its pixel's weight over the mean (0 for a pixel of weight 0).
    pub fn density(&self, f: [f32; 2]) -> f32 {
        let cell = |v: f32, n: usize| ((v.clamp(0.0, 1.0) * n as f32) as usize).min(n - 1);
        let (i, j) = (cell(f[0], self.width), cell(f[1], self.height));
        self.density.get(j * self.width + i).copied().unwrap_or(0.0)
    }
}

/// The largest f32 below 1 for values that rounded up to 1.
fn below_one(v: f32) -> f32 {
    if v < 1.0 {
        v.max(0.0)
    } else {
        1.0 - f32::EPSILON / 2.0
    }
}

/// The interval `i` of cumulative sums `cdf` (non-decreasing, 0 … 1) holding `u`, and where
/// in it `u` lies (0 … 1). Only `u` at or beyond the last sum can land on an empty
/// interval; it then moves back to the last non-empty one.
fn pick<T: Copy + Into<f64>>(cdf: &[T], u: f64) -> (usize, f64) {
    let at = |i: usize| -> f64 { cdf[i].into() };
    let n = cdf.len() - 1;
    let mut i = cdf.partition_point(|&c| c.into() <= u).clamp(1, n) - 1;
    while i > 0 && at(i + 1) <= at(i) {
        i -= 1;
    }
    let width = at(i + 1) - at(i);
    let f = if width > 0.0 {
        (u - at(i)) / width
    } else {
        0.5
    };
    (i, f.clamp(0.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map(w: u32, h: u32, weights: &[f32]) -> SamplingMap {
        SamplingMap::from_weights(weights, w, h).unwrap()
    }

    #[test]
    fn uniform_map_is_the_identity_with_density_one() {
        let m = SamplingMap::uniform(4, 3).unwrap();
        let w = MapWarp::new(&m, 4, 3, [0, 0]).unwrap();
        for &u in &[[0.1f32, 0.2f32], [0.5, 0.5], [0.93, 0.07]] {
            let p = w.warp(u);
            assert!(
                (p[0] - u[0]).abs() < 1e-5 && (p[1] - u[1]).abs() < 1e-5,
                "{u:?} -> {p:?}"
            );
            assert!((w.density(p) - 1.0).abs() < 1e-6);
        }
    }

    #[test]
    fn positions_follow_the_weights_and_density_is_their_pdf() {
        // 2 x 1 map, weights 3 : 1: three quarters of the positions land in the left half,
        // where the density is 1.5 (and 0.5 on the right).
        let w = MapWarp::new(&map(2, 1, &[3.0, 1.0]), 2, 1, [0, 0]).unwrap();
        let n = 4000;
        let left = (0..n)
            .filter(|k| w.warp([(*k as f32 + 0.5) / n as f32, 0.3])[0] < 0.5)
            .count();
        assert_eq!(left, 3000);
        assert!((w.density([0.2, 0.5]) - 1.5).abs() < 1e-6);
        assert!((w.density([0.7, 0.5]) - 0.5).abs() < 1e-6);
        // Within a pixel the point is uniform: the left pixel's positions cover [0, 0.5).
        let xs: Vec<f32> = (0..300)
            .map(|k| w.warp([(k as f32 + 0.5) / 400.0, 0.5])[0])
            .collect();
        assert!(xs.iter().all(|&x| (0.0..0.5).contains(&x)));
        assert!(xs.windows(2).all(|p| p[0] < p[1]));
    }

    #[test]
    fn zero_weight_pixels_are_never_drawn() {
        // 3 x 2; the middle column and the whole bottom row are zero.
        let m = map(3, 2, &[1.0, 0.0, 2.0, 0.0, 0.0, 0.0]);
        let w = MapWarp::new(&m, 3, 2, [0, 0]).unwrap();
        for a in 0..50 {
            for b in 0..50 {
                let p = w.warp([a as f32 / 50.0, b as f32 / 50.0]);
                assert!(p[1] < 0.5, "bottom row drawn: {p:?}");
                assert!(
                    !(1.0 / 3.0..2.0 / 3.0).contains(&p[0]),
                    "middle drawn: {p:?}"
                );
                assert!(w.density(p) > 0.0);
            }
        }
        assert_eq!(w.density([0.5, 0.25]), 0.0);
    }

    #[test]
    fn margins_take_the_nearest_buffer_pixel() {
        // A 2 x 1 buffer (weights 1 : 3) inside a 4 x 1 extent starting one pixel left of it:
        // extent weights 1, 1, 3, 3, mean 2.
        let w = MapWarp::new(&map(2, 1, &[1.0, 3.0]), 4, 1, [-1, 0]).unwrap();
        let d: Vec<f32> = (0..4)
            .map(|i| w.density([(i as f32 + 0.5) / 4.0, 0.5]))
            .collect();
        assert_eq!(d, vec![0.5, 0.5, 1.5, 1.5]);
    }

    #[test]
    fn warped_integrals_over_density_are_unbiased() {
        // E_q[f / q] = ∫ f for f(x, y) = x² + y on a skewed map.
        let m = map(3, 2, &[0.2, 1.0, 4.0, 2.0, 0.5, 1.0]);
        let w = MapWarp::new(&m, 3, 2, [0, 0]).unwrap();
        let n = 400;
        let mut s = 0.0f64;
        for a in 0..n {
            for b in 0..n {
                let p = w.warp([(a as f32 + 0.5) / n as f32, (b as f32 + 0.5) / n as f32]);
                let f = f64::from(p[0] * p[0] + p[1]);
                s += f / f64::from(w.density(p));
            }
        }
        let est = s / (n * n) as f64;
        assert!((est - (1.0 / 3.0 + 0.5)).abs() < 2e-3, "{est}");
    }
}
