//! Sampling maps of noise-aware sampling (`"bool noiseaware"`) and the user sampling map: per
//! pixel of the film buffer, a relative sample density (mean 1 over the buffer) that says how
//! many of a pass's samples each pixel gets.
//!
//! ```text
//! convergence test's per-pixel noise (visible difference / threshold, crate::halt)
//!   --from_noise: cap, 9x9 maximum, 3x3 box blur, normalise to mean 1, mix with a floor-->
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
//! deterministic. Every pixel keeps at least [`MAP_FLOOR`] of the average density, so none
//! starves; no pixel takes more than [`MAX_DENSITY`] times the average.
//!
//! Why pixel choice does not bias the image: a film pixel is the ratio of the filter-weighted
//! sum of radiance to the sum of the filter weights (per-pixel normalised buffers, as
//! LuxRender's). Within a pixel the sample position stays uniform, so each sample is an
//! unbiased draw of that pixel's filtered radiance; taking more samples in a pixel changes
//! only how fast its ratio converges — as long as the count does not depend on the pixel's
//! own values. The noise-aware map does depend on them (a user map does not), and where a
//! pixel's light comes only from rare paths (a lamp seen through glass, a caustic) that
//! matters: a pixel that has caught none of them looks converged, one that just caught one
//! looks noisy, so a map built from each pixel's own change gives the lucky pixel more
//! samples (diluting its catch) and the others fewer. Such an image reads dark: 0.82 of the
//! reference at 433 samples a pixel on a lamp seen only through glass, where uniform sampling
//! read 1.02. (LuxRender 1.x builds its map another way, which luxfarm does not follow yet:
//! each pixel's per-sample luminance deviation over the convergence test's threshold,
//! stretched between the 5th and 95th percentiles, box-filtered with radius 6 and rebuilt on
//! a doubling samples-per-pixel schedule; `Film::GenerateNoiseAwareMap`. It too depends on
//! each pixel's own samples, so the same caution applies.)
//! So a pixel is judged by its neighbourhood: its noise is the largest within
//! [`DILATE_RADIUS`] pixels, and (`crate::render::noise`) a noisy pixel's noise fades over
//! several tests rather than vanishing at the first quiet one. A catch then raises the
//! density of some 80 pixels for many passes, and its own pixel's share of that is small.
//! `tests/noiseaware_rare_light.rs` measures it: light that reaches a pixel once in 500 or
//! 2000 samples reads within noise of the truth (0.86 and 0.65 of it without the window and
//! the memory). Rarer light, caught less than once per 9 × 9 window and memory, still reads
//! somewhat dark until more samples arrive: the map is consistent, not unbiased.
//!
//! With a filter wider than a pixel, neighbours at different densities weigh the filtered
//! average by their density (LuxRender's films behave the same); the blur keeps the density
//! smooth across a filter's support, and with the box filter of radius 0.5 this effect is
//! absent.
//! Per-screen buffers (metropolis) are normalised by the total sample count, where pixel
//! choice would matter: there the map becomes a density over film positions
//! ([`super::map_warp`]) and every contribution is divided by it (`crate::render::mlt`).

use super::hash::{combine, pixel_key, unit_f32};
use super::map_filter::{blur3, dilate};

/// The least density of a pixel, as a fraction of the average.
pub const MAP_FLOOR: f32 = 0.1;
/// The greatest density of a pixel, in multiples of the average.
pub const MAX_DENSITY: f32 = 16.0;
/// Noise values above this (the convergence ratio; `inf` on the first test) count as this.
pub const NOISE_CAP: f32 = 16.0;
/// Radius of the square window whose noisiest pixel sets a pixel's noise (a 9 × 9 window):
/// a pixel is judged by its neighbourhood, not by its own few samples (see the module doc).
pub const DILATE_RADIUS: usize = 4;
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
    /// The map of a convergence test's per-pixel noise (`w` × `h`, row-major; higher is
    /// noisier; NaN and inf count as the cap): capped, raised to the largest within
    /// [`DILATE_RADIUS`], blurred, normalised to mean 1 and mixed with [`MAP_FLOOR`]. A film that shows no noise at all gives the uniform map.
    pub fn from_noise(noise: &[f32], w: u32, h: u32) -> Result<SamplingMap, MapError> {
        let n = check_size(w, h)?;
        if noise.len() as u64 != n {
            return Err(MapError::Count {
                got: noise.len(),
                want: n,
            });
        }
        let capped: Vec<f32> = noise
            .iter()
            .map(|v| {
                if v.is_nan() {
                    NOISE_CAP
                } else {
                    v.clamp(0.0, NOISE_CAP)
                }
            })
            .collect();
        let dilated = dilate(&capped, w as usize, h as usize, DILATE_RADIUS);
        let blurred = blur3(&dilated, w as usize, h as usize);
        let mean = blurred.iter().map(|v| f64::from(*v)).sum::<f64>() / n as f64;
        let density = if mean > 0.0 {
            blurred
                .iter()
                .map(|v| MAP_FLOOR + (1.0 - MAP_FLOOR) * (f64::from(*v) / mean) as f32)
                .collect()
        } else {
            vec![1.0; blurred.len()]
        };
        Ok(SamplingMap::normalised(w, h, density))
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

    #[test]
    fn noise_map_is_normalised_floored_and_follows_the_noise() {
        // Left half noisy, right half converged.
        let (w, h) = (32u32, 8u32);
        let noise: Vec<f32> = (0..w * h)
            .map(|i| if i % w < w / 2 { 4.0 } else { 0.0 })
            .collect();
        let m = SamplingMap::from_noise(&noise, w, h).unwrap();
        let mean: f32 = m.densities().iter().sum::<f32>() / (w * h) as f32;
        assert!((mean - 1.0).abs() < 1e-4, "{mean}");
        assert!(m.density(0, 0) > 1.5, "{}", m.density(0, 0));
        // the floor: a converged pixel keeps a share
        let right = m.density(w - 1, 0);
        assert!(right > 0.05 && right < 0.5, "{right}");
        // nothing noisy: uniform
        let u = SamplingMap::from_noise(&vec![0.0; 128], 16, 8).unwrap();
        assert!(u.densities().iter().all(|d| *d == 1.0));
        // first test (inf everywhere): uniform too
        let u = SamplingMap::from_noise(&vec![f32::INFINITY; 128], 16, 8).unwrap();
        assert!(u.densities().iter().all(|d| (*d - 1.0).abs() < 1e-5));
    }

    #[test]
    fn a_lone_noisy_pixel_raises_its_whole_neighbourhood() {
        // The neighbourhood of one noisy pixel is sampled alike: nothing in the window is
        // left at the floor, and the pixel itself is not singled out.
        let (w, h) = (40u32, 40u32);
        let mut noise = vec![0.0f32; (w * h) as usize];
        noise[(20 * w + 20) as usize] = 8.0;
        let m = SamplingMap::from_noise(&noise, w, h).unwrap();
        // (the blur after the maximum softens the window's outermost ring)
        let r = DILATE_RADIUS as u32 - 1;
        let centre = m.density(20, 20);
        for (x, y) in [(20 - r, 20), (20 + r, 20 + r), (20, 20 - r)] {
            assert!(
                (m.density(x, y) - centre).abs() < 1e-5 * centre,
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
        let noise: Vec<f32> = (0..40 * 30).map(|i| (i % 40) as f32 / 10.0).collect();
        let m = SamplingMap::from_noise(&noise, 40, 30).unwrap();
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
        let mut noise = vec![0.0f32; 64];
        noise[0] = 1.0;
        let m = SamplingMap::from_noise(&noise, 8, 8).unwrap();
        let most = (0..64)
            .map(|p| m.pixel_samples(4, 0, 0, key(0, 0, p)))
            .max()
            .unwrap();
        assert!(most <= max_pixel_samples(4), "{most}");
    }
}
