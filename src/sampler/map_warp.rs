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
//! A position is drawn by [`PiecewiseConstant2D`]: a row in proportion to its total weight,
//! then a pixel of that row in proportion to its weight, then a point uniformly inside the
//! pixel. Its density over the unit square is the pixel's weight over the mean weight: what
//! `density` returns, so an estimator can divide by it.

use super::map::SamplingMap;
use crate::sampling::piecewise::PiecewiseConstant2D;

/// The extent's pixel weights as a density over the unit square.
#[derive(Clone, Debug)]
pub struct MapWarp {
    dist: PiecewiseConstant2D,
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
                weight.push(map.density(nearest(offset[0] + x as i64, map.width()), by));
            }
        }
        let dist = PiecewiseConstant2D::new(&weight, w, h);
        (dist.integral() > 0.0).then_some(MapWarp { dist })
    }

    /// The film position (fractions of the extent, each in [0, 1)) of uniform numbers `u`:
    /// `u[1]` picks the row, `u[0]` the pixel within it and the point within the pixel.
    pub fn warp(&self, u: [f32; 2]) -> [f32; 2] {
        self.dist
            .sample(u[0].clamp(0.0, 1.0), u[1].clamp(0.0, 1.0))
            .0
    }

    /// The density with which [`MapWarp::warp`] draws the film position `f` (fractions of the
    /// extent): its pixel's weight over the mean (0 for a pixel of weight 0).
    pub fn density(&self, f: [f32; 2]) -> f32 {
        self.dist.pdf(f[0].clamp(0.0, 1.0), f[1].clamp(0.0, 1.0))
    }
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
