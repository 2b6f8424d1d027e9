//! Sampling maps of noise-aware sampling (`"bool noiseaware"`) and the user sampling map: per
//! pixel of the film buffer, a relative sample density (mean 1 over the buffer) that says how
//! many of a pass's samples each pixel gets.
//!
//! ```text
//! film's per-pixel spread of single contributions (crate::film::variance) and the display
//!   image's visibility threshold (crate::render::noise)
//!   --from_deviation: sigma/TVI, normalised, 5-95 % stretch, 13x13 box filter, mean 1-->
//!   SamplingMap
//! user's weights (an image's luminance, crate::render::usermap)
//!   --from_weights: finite, >= 0, not all zero, normalise to mean 1-->  SamplingMap
//! noise-aware map x user map --product (pixel by pixel, renormalised)-->  SamplingMap
//!   --(farm) to_cells: downsampled cells, f32--> wire --from_cells: validate, expand-->
//!   SamplingMap --pixel_samples(spp, pixel, pass)--> samples of that pixel in that pass
//! ```
//!
//! LuxRender 1.x keeps the user's map beside its noise-aware one and samples by their pixel
//! by pixel product when it has both (`Film::UpdateSamplingMap`), by the one it has otherwise.
//! A user map may give pixels weight 0: they take no samples of their own (a filter wider than
//! a pixel still brings them their neighbours' samples), as in LuxRender.
//!
//! A pixel's expected samples in a pass are `spp × density`; the count is that number rounded
//! up or down at random (a hash of seed, stream, pixel and pass), so it is unbiased and
//! deterministic. No pixel takes more than [`MAX_DENSITY`] times the average; before the box
//! filter, the stretch gives every pixel at least LuxRender's floor of 0.05.
//!
//! Why pixel choice does not bias the image: a film pixel is the ratio of the filter-weighted
//! sum of radiance to the sum of the filter weights (per-pixel normalised buffers, as
//! LuxRender's). Within a pixel the sample position stays uniform, so each sample is an
//! unbiased draw of that pixel's filtered radiance; taking more samples in a pixel changes
//! only how fast its ratio converges — as long as the count does not depend on the pixel's
//! own values. The noise-aware map does depend on them (a user map does not), and where a
//! pixel's light comes only from rare paths (a caustic, the edge of a small bright lamp) that
//! matters: a pixel whose first samples caught a rare bright path shows a large spread and
//! draws more samples, which dilute its catch, while one that caught none draws fewer. The
//! image reads slightly dark until the samples outnumber the map's: LuxRender's map is
//! consistent, not unbiased, and so is luxfarm's. Two things keep the effect small: the map
//! is built from the spread of single contributions, which a pixel's own catch moves only
//! within its 13 × 13 box window, and maps are rebuilt on a doubling schedule, so most
//! samples are taken under a map built from far fewer. Measured on the Cornell benchmark
//! (`luxfarm bench cornell`, sobol, 6 seeds): 0.9994 ± 0.0002 of the reference outside the
//! lamp at 64 spp against 1.0005 ± 0.0003 uniform, and within 0.05 % at equal time (about 150
//! spp); `tests/noiseaware_rare_light.rs` checks light caught once in 500 and 2000 samples.
//!
//! With a filter wider than a pixel, neighbours at different densities weigh the filtered
//! average by their density (LuxRender's films behave the same); the box filter keeps the density
//! smooth across a filter's support, and with the box filter of radius 0.5 this effect is
//! absent.
//! Per-screen buffers (metropolis) are normalised by the total sample count, where pixel
//! choice would matter: there the map becomes a density over film positions
//! ([`super::map_warp`]) and every contribution is divided by it (`crate::render::mlt`).

use super::hash::{combine, pixel_key, unit_f32};
use super::map_filter::{box_filter, stretch};

/// The greatest density of a pixel, in multiples of the average.
pub const MAX_DENSITY: f32 = 16.0;
/// Radius of the box filter that smooths a noise-aware map (a 13 × 13 window, LuxRender's).
pub const BOX_RADIUS: usize = 6;
/// Most pixels a map may have (a 16384 × 16384 buffer).
pub const MAX_MAP_PIXELS: u64 = 1 << 28;

/// Why a map cannot be used.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MapError {
    #[error("sampling map size {0}x{1} is empty or too large")]
    Size(u32, u32),
    #[error("sampling map has {got} values, {want} expected")]
    Count { got: usize, want: u64 },
    #[error("sampling map value {index} is {value} (must be finite and not negative)")]
    Value { index: usize, value: f32 },
    #[error("sampling map cell size {0} does not tile a {1}x{2} film")]
    Cells(u32, u32, u32),
    #[error("sampling map pixel ({x}, {y}) is {value} (must be finite and not negative)")]
    Pixel { x: u32, y: u32, value: f32 },
    #[error("sampling map is zero everywhere (at least one pixel must have a weight above 0)")]
    AllZero,
    #[error("sampling map is {got_w}x{got_h}, the film is {want_w}x{want_h}")]
    Mismatch {
        got_w: u32,
        got_h: u32,
        want_w: u32,
        want_h: u32,
    },
}

/// Relative sample densities of the pixels of a film buffer (mean 1).
#[derive(Clone, Debug, PartialEq)]
pub struct SamplingMap {
    width: u32,
    height: u32,
    density: Vec<f32>,
}

fn check_size(w: u32, h: u32) -> Result<u64, MapError> {
    let n = u64::from(w) * u64::from(h);
    if n == 0 || n > MAX_MAP_PIXELS {
        return Err(MapError::Size(w, h));
    }
    Ok(n)
}

/// Finite and not negative, else the first offending value.
fn check_values(v: &[f32]) -> Result<(), MapError> {
    match v.iter().position(|x| !x.is_finite() || *x < 0.0) {
        Some(index) => Err(MapError::Value {
            index,
            value: v.get(index).copied().unwrap_or(f32::NAN),
        }),
        None => Ok(()),
    }
}

impl SamplingMap {
    /// LuxRender 1.x's noise-aware map (`Film::GenerateNoiseAwareMap`) from each pixel's
    /// standard deviation of one contribution's luminance (`sigma`) and the threshold versus
    /// intensity of its adaptation luminance (`tvi`, `crate::halt::convergence::tvi_map`),
    /// both `w` × `h`, row-major: the deviation over the threshold, each normalised by its
    /// maximum, normalised again by the largest ratio, stretched between its 5th and 95th
    /// percentiles ([`super::map_filter::stretch`]), box-filtered with radius
    /// [`BOX_RADIUS`], then normalised to mean 1. As in LuxRender: a film without noise or
    /// without a threshold gives no map (`None`: LuxRender leaves its map version as it is,
    /// so samplers keep the map they have), and one whose stretch finds no spread gives the
    /// uniform map (a new version).
    pub fn from_deviation(
        sigma: &[f32],
        tvi: &[f32],
        w: u32,
        h: u32,
    ) -> Result<Option<SamplingMap>, MapError> {
        let n = check_size(w, h)?;
        for v in [sigma, tvi] {
            if v.len() as u64 != n {
                return Err(MapError::Count {
                    got: v.len(),
                    want: n,
                });
            }
        }
        let finite_max = |v: &[f32]| {
            v.iter()
                .filter(|x| x.is_finite())
                .fold(0.0f32, |a, b| a.max(*b))
        };
        let (max_sigma, max_tvi) = (finite_max(sigma), finite_max(tvi));
        if max_sigma <= 0.0 || max_tvi <= 0.0 {
            return Ok(None);
        }
        let ratio: Vec<f32> = sigma
            .iter()
            .zip(tvi)
            .map(|(s, t)| {
                let (s, t) = (s / max_sigma, t / max_tvi);
                if t > 0.0 && s.is_finite() && t.is_finite() {
                    s.max(0.0) / t
                } else {
                    0.0
                }
            })
            .collect();
        let max_ratio = finite_max(&ratio);
        if max_ratio <= 0.0 {
            return SamplingMap::uniform(w, h).map(Some);
        }
        let ratio: Vec<f32> = ratio.iter().map(|r| (r / max_ratio).min(1.0)).collect();
        let Some(stretched) = stretch(&ratio) else {
            return SamplingMap::uniform(w, h).map(Some);
        };
        let filtered = box_filter(&stretched, w as usize, h as usize, BOX_RADIUS);
        Ok(Some(SamplingMap::normalised(w, h, filtered)))
    }

    /// A user sampling map from per-pixel weights (`w` × `h`, row-major, row 0 at the top):
    /// each finite and not negative, not all zero; normalised to mean 1 (capped at
    /// [`MAX_DENSITY`]).
    pub fn from_weights(weights: &[f32], w: u32, h: u32) -> Result<SamplingMap, MapError> {
        let n = check_size(w, h)?;
        if weights.len() as u64 != n {
            return Err(MapError::Count {
                got: weights.len(),
                want: n,
            });
        }
        if let Err(MapError::Value { index, value }) = check_values(weights) {
            let (x, y) = (
                (index as u64 % u64::from(w)) as u32,
                (index as u64 / u64::from(w)) as u32,
            );
            return Err(MapError::Pixel { x, y, value });
        }
        if weights.iter().all(|v| *v == 0.0) {
            return Err(MapError::AllZero);
        }
        Ok(SamplingMap::normalised(w, h, weights.to_vec()))
    }

    /// The pixel by pixel product of two maps of the same size (LuxRender's noise-aware map
    /// times its user map), normalised to mean 1; a product that is zero everywhere gives the
    /// uniform map.
    pub fn product(&self, other: &SamplingMap) -> Result<SamplingMap, MapError> {
        other.check_film(self.width, self.height)?;
        let density = self
            .density
            .iter()
            .zip(&other.density)
            .map(|(a, b)| a * b)
            .collect();
        Ok(SamplingMap::normalised(self.width, self.height, density))
    }

    /// The uniform map (every pixel at density 1).
    pub fn uniform(w: u32, h: u32) -> Result<SamplingMap, MapError> {
        let n = check_size(w, h)?;
        Ok(SamplingMap {
            width: w,
            height: h,
            density: vec![1.0; n as usize],
        })
    }

    /// Scales the densities to mean 1 and caps them at [`MAX_DENSITY`] (all zero: uniform).
    fn normalised(width: u32, height: u32, mut density: Vec<f32>) -> SamplingMap {
        let sum: f64 = density.iter().map(|v| f64::from(*v)).sum();
        if sum > 0.0 && sum.is_finite() {
            let scale = density.len() as f64 / sum;
            for d in &mut density {
                *d = ((f64::from(*d) * scale) as f32).min(MAX_DENSITY);
            }
        } else {
            density.iter_mut().for_each(|d| *d = 1.0);
        }
        SamplingMap {
            width,
            height,
            density,
        }
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    /// The relative density of buffer pixel (`x`, `y`) (1 outside the map).
    pub fn density(&self, x: u32, y: u32) -> f32 {
        if x >= self.width || y >= self.height {
            return 1.0;
        }
        let i = y as usize * self.width as usize + x as usize;
        self.density.get(i).copied().unwrap_or(1.0)
    }

    /// The densities, row-major.
    pub fn densities(&self) -> &[f32] {
        &self.density
    }

    /// The samples buffer pixel (`x`, `y`) (image pixel `px`, `py`) takes in pass `pass` of
    /// `spp` samples per pixel: `spp × density` rounded up with probability its fraction.
    pub fn pixel_samples(&self, spp: u32, x: u32, y: u32, key: PassKey) -> u32 {
        let expected = f64::from(spp) * f64::from(self.density(x, y));
        let whole = expected.floor();
        let u = unit_f32(combine(
            pixel_key(key.seed, key.stream, key.px, key.py),
            key.pass ^ 0x6d61_7073_616d_706c,
        ));
        let n = whole
            + if f64::from(u) < expected - whole {
                1.0
            } else {
                0.0
            };
        n.clamp(0.0, f64::from(max_pixel_samples(spp))) as u32
    }

    /// The map over cells of `cell` × `cell` pixels (each cell's mean density): what travels
    /// to the workers. Returns (cells across, cells down, values).
    pub fn to_cells(&self, cell: u32) -> (u32, u32, Vec<f32>) {
        let cell = cell.max(1);
        let (cw, ch) = (self.width.div_ceil(cell), self.height.div_ceil(cell));
        let mut sum = vec![0.0f64; cw as usize * ch as usize];
        let mut count = vec![0u32; sum.len()];
        for y in 0..self.height {
            for x in 0..self.width {
                let c = (y / cell) as usize * cw as usize + (x / cell) as usize;
                if let (Some(s), Some(n)) = (sum.get_mut(c), count.get_mut(c)) {
                    *s += f64::from(self.density(x, y));
                    *n += 1;
                }
            }
        }
        let v = sum
            .iter()
            .zip(&count)
            .map(|(s, n)| (s / f64::from((*n).max(1))) as f32)
            .collect();
        (cw, ch, v)
    }

    /// The smallest cell size whose map has at most `max_cells` values.
    pub fn cell_size_for(&self, max_cells: u64) -> u32 {
        let mut cell = 1u32;
        while u64::from(self.width.div_ceil(cell)) * u64::from(self.height.div_ceil(cell))
            > max_cells.max(1)
            && cell < self.width.max(self.height)
        {
            cell *= 2;
        }
        cell
    }

    /// A map for a `w` × `h` film from values over `cell` × `cell` cells (from the network or
    /// a file): checked (cell count, finite, not negative), each pixel taking its cell's
    /// value, normalised to mean 1.
    pub fn from_cells(
        w: u32,
        h: u32,
        cell: u32,
        cells_w: u32,
        cells_h: u32,
        values: &[f32],
    ) -> Result<SamplingMap, MapError> {
        let n = check_size(w, h)?;
        if cell == 0 || w.div_ceil(cell) != cells_w || h.div_ceil(cell) != cells_h {
            return Err(MapError::Cells(cell, w, h));
        }
        let want = u64::from(cells_w) * u64::from(cells_h);
        if values.len() as u64 != want {
            return Err(MapError::Count {
                got: values.len(),
                want,
            });
        }
        check_values(values)?;
        let mut density = Vec::with_capacity(n as usize);
        for y in 0..h {
            for x in 0..w {
                let c = (y / cell) as usize * cells_w as usize + (x / cell) as usize;
                density.push(values.get(c).copied().unwrap_or(0.0));
            }
        }
        Ok(SamplingMap::normalised(w, h, density))
    }

    /// Checks that the map covers a `w` × `h` buffer.
    pub fn check_film(&self, w: u32, h: u32) -> Result<(), MapError> {
        if (self.width, self.height) != (w, h) {
            return Err(MapError::Mismatch {
                got_w: self.width,
                got_h: self.height,
                want_w: w,
                want_h: h,
            });
        }
        Ok(())
    }
}

/// What a pixel's count in a pass is keyed by.
#[derive(Clone, Copy, Debug)]
pub struct PassKey {
    pub seed: u64,
    pub stream: u64,
    /// Image pixel.
    pub px: u32,
    pub py: u32,
    pub pass: u64,
}

/// Most samples a pixel takes in one pass of `spp` samples per pixel.
pub fn max_pixel_samples(spp: u32) -> u32 {
    spp.saturating_mul(MAX_DENSITY as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(px: u32, py: u32, pass: u64) -> PassKey {
        PassKey {
            seed: 3,
            stream: 1,
            px,
            py,
            pass,
        }
    }

    /// The deviation map of `sigma` over `tvi`, which must give one.
    fn map(sigma: &[f32], tvi: &[f32], w: u32, h: u32) -> SamplingMap {
        SamplingMap::from_deviation(sigma, tvi, w, h)
            .unwrap()
            .expect("a map")
    }

    /// A threshold of 1 everywhere: the map follows the deviations alone.
    fn flat(n: usize) -> Vec<f32> {
        vec![1.0; n]
    }

    #[test]
    fn the_deviation_map_is_normalised_and_follows_the_noise() {
        // Left half noisy, right half quiet: after the stretch the right half sits at the
        // floor and the left well above it; the 13 x 13 box blends the two near the edge.
        let (w, h) = (64u32, 16u32);
        let n = (w * h) as usize;
        let sigma: Vec<f32> = (0..w * h)
            .map(|i| if i % w < w / 2 { 0.4 } else { 0.01 })
            .collect();
        let m = map(&sigma, &flat(n), w, h);
        let mean: f32 = m.densities().iter().sum::<f32>() / n as f32;
        assert!((mean - 1.0).abs() < 1e-4, "{mean}");
        let (left, right) = (m.density(0, 0), m.density(w - 1, 0));
        assert!(left > 1.5 && right > 0.0 && right < 0.1, "{left} {right}");
        // the threshold divides: noise 40 times the other half's over a threshold 40 times
        // as high is as visible, and the map is uniform
        let tvi: Vec<f32> = (0..w * h)
            .map(|i| if i % w < w / 2 { 40.0 } else { 1.0 })
            .collect();
        let m = map(&sigma, &tvi, w, h);
        assert!(m.densities().iter().all(|d| (*d - 1.0).abs() < 1e-4));
        // no noise or no threshold: no map (the samplers keep theirs)
        for (s, t) in [(vec![0.0; n], flat(n)), (sigma.clone(), vec![0.0; n])] {
            assert!(SamplingMap::from_deviation(&s, &t, w, h).unwrap().is_none());
        }
        // noise everywhere alike, nothing to stretch: a uniform map
        let u = map(&vec![0.2; n], &flat(n), w, h);
        assert!(u.densities().iter().all(|d| (*d - 1.0).abs() < 1e-5));
        assert!(SamplingMap::from_deviation(&sigma, &flat(n - 1), w, h).is_err());
    }

    #[test]
    fn a_lone_noisy_pixel_raises_its_whole_box_window() {
        // The box window of one noisy pixel is sampled alike, the pixel not singled out.
        let (w, h) = (40u32, 40u32);
        let mut sigma = vec![0.01f32; (w * h) as usize];
        for (i, s) in sigma.iter_mut().enumerate() {
            *s += (i % 7) as f32 * 0.001;
        }
        sigma[(20 * w + 20) as usize] = 8.0;
        let m = map(&sigma, &flat((w * h) as usize), w, h);
        let r = BOX_RADIUS as u32;
        let centre = m.density(20, 20);
        for (x, y) in [(20 - r, 20), (20 + r, 20 + r), (20, 20 - r)] {
            assert!(
                (m.density(x, y) - centre).abs() < 0.05 * centre,
                "({x}, {y})"
            );
        }
        assert!(m.density(0, 0) < 0.2 * centre);
    }

    #[test]
    fn pixel_counts_follow_the_density_on_average() {
        let m = SamplingMap::from_cells(2, 1, 1, 2, 1, &[3.0, 1.0]).unwrap();
        assert_eq!(m.densities(), &[1.5, 0.5]);
        let total = |x: u32| -> u64 {
            (0..4000)
                .map(|p| u64::from(m.pixel_samples(4, x, 0, key(x, 0, p))))
                .sum()
        };
        let (a, b) = (total(0), total(1));
        // expected 6 and 2 per pass
        assert!((a as f64 / 4000.0 - 6.0).abs() < 0.01, "{a}");
        assert!((b as f64 / 4000.0 - 2.0).abs() < 0.01, "{b}");
        // deterministic
        assert_eq!(
            m.pixel_samples(3, 0, 0, key(0, 0, 9)),
            m.pixel_samples(3, 0, 0, key(0, 0, 9))
        );
        // fractional densities round both ways
        let m = SamplingMap::from_cells(2, 1, 1, 2, 1, &[1.25, 0.75]).unwrap();
        let counts: Vec<u32> = (0..200)
            .map(|p| m.pixel_samples(1, 0, 0, key(0, 0, p)))
            .collect();
        assert!(counts.contains(&1) && counts.contains(&2));
    }

    #[test]
    fn cells_round_trip_and_hostile_values_are_refused() {
        let weights: Vec<f32> = (0..40 * 30).map(|i| (i % 40) as f32 / 10.0).collect();
        let m = SamplingMap::from_weights(&weights, 40, 30).unwrap();
        let cell = m.cell_size_for(100);
        let (cw, ch, v) = m.to_cells(cell);
        assert!(u64::from(cw * ch) <= 100);
        assert_eq!((cw, ch), (40u32.div_ceil(cell), 30u32.div_ceil(cell)));
        let back = SamplingMap::from_cells(40, 30, cell, cw, ch, &v).unwrap();
        assert!(back.density(39, 0) > back.density(0, 0));
        let (cw, ch, v) = m.to_cells(1);
        let same = SamplingMap::from_cells(40, 30, 1, cw, ch, &v).unwrap();
        for (a, b) in same.densities().iter().zip(m.densities()) {
            assert!((a - b).abs() < 1e-4);
        }
        assert!(matches!(
            SamplingMap::from_cells(2, 1, 1, 2, 1, &[f32::NAN, 1.0]),
            Err(MapError::Value { index: 0, .. })
        ));
        assert!(matches!(
            SamplingMap::from_cells(2, 1, 1, 2, 1, &[1.0, -1.0]),
            Err(MapError::Value { index: 1, .. })
        ));
        assert!(matches!(
            SamplingMap::from_cells(2, 1, 1, 2, 1, &[1.0]),
            Err(MapError::Count { .. })
        ));
        assert!(SamplingMap::from_cells(4, 4, 2, 3, 2, &[1.0; 6]).is_err());
        assert!(SamplingMap::from_cells(4, 4, 0, 0, 0, &[]).is_err());
        assert!(SamplingMap::from_cells(0, 4, 1, 0, 4, &[]).is_err());
        // all zero: uniform
        let z = SamplingMap::from_cells(2, 1, 1, 2, 1, &[0.0, 0.0]).unwrap();
        assert_eq!(z.densities(), &[1.0, 1.0]);
    }

    #[test]
    fn user_weights_are_checked_normalised_and_multiply_with_a_noise_map() {
        // 9:1 left to right
        let w: Vec<f32> = (0..8).map(|i| if i % 4 < 2 { 9.0 } else { 1.0 }).collect();
        let m = SamplingMap::from_weights(&w, 4, 2).unwrap();
        assert!((m.density(0, 0) - 1.8).abs() < 1e-6 && (m.density(3, 1) - 0.2).abs() < 1e-6);
        // zeros are kept (those pixels take no samples), all zero is refused
        let z = SamplingMap::from_weights(&[0.0, 1.0], 2, 1).unwrap();
        assert_eq!(z.densities(), &[0.0, 2.0]);
        assert_eq!(z.pixel_samples(4, 0, 0, key(0, 0, 1)), 0);
        assert_eq!(
            SamplingMap::from_weights(&[0.0, 0.0], 2, 1),
            Err(MapError::AllZero)
        );
        assert_eq!(
            SamplingMap::from_weights(&[1.0, 1.0, -2.0, 1.0], 2, 2),
            Err(MapError::Pixel {
                x: 0,
                y: 1,
                value: -2.0
            })
        );
        assert!(matches!(
            SamplingMap::from_weights(&[1.0, f32::NAN], 2, 1),
            Err(MapError::Pixel { x: 1, y: 0, .. })
        ));
        assert!(matches!(
            SamplingMap::from_weights(&[1.0, f32::INFINITY], 2, 1),
            Err(MapError::Pixel { x: 1, y: 0, .. })
        ));
        assert!(matches!(
            SamplingMap::from_weights(&[1.0; 3], 2, 1),
            Err(MapError::Count { got: 3, want: 2 })
        ));
        // the product, pixel by pixel, renormalised
        let noise =
            SamplingMap::from_cells(4, 2, 1, 4, 2, &[1.0, 3.0, 1.0, 3.0, 1.0, 3.0, 1.0, 3.0])
                .unwrap();
        let p = noise.product(&m).unwrap();
        let raw = [9.0f32, 27.0, 1.0, 3.0];
        let mean = raw.iter().sum::<f32>() / 4.0;
        for x in 0..4u32 {
            let want = raw[x as usize] / mean;
            assert!(
                (p.density(x, 0) - want).abs() < 1e-5,
                "{x}: {}",
                p.density(x, 0)
            );
            assert_eq!(p.density(x, 0), p.density(x, 1));
        }
        assert!(noise.product(&SamplingMap::uniform(2, 2).unwrap()).is_err());
    }

    #[test]
    fn a_pass_gives_a_pixel_at_most_max_density_times_spp() {
        assert_eq!(max_pixel_samples(4), 64);
        let mut weights = vec![0.0f32; 64];
        weights[0] = 1.0;
        let m = SamplingMap::from_weights(&weights, 8, 8).unwrap();
        let most = (0..64)
            .map(|p| m.pixel_samples(4, 0, 0, key(0, 0, p)))
            .max()
            .unwrap();
        assert!(most <= max_pixel_samples(4), "{most}");
    }
}
