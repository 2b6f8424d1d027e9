//! The variance buffer a film keeps for noise-aware sampling (`"bool noiseaware"`): per
//! buffer pixel, the filter-weighted spread of the luminance (Y) of the contributions its
//! filter footprint receives. LuxRender 1.x's film adds every contribution to it with the
//! weight it gives the pixel (`Film::AddTileSamples`, `VarianceBuffer::Add`), and its
//! noise-aware map is built from each pixel's per-sample standard deviation
//! (`crate::sampler::map`); a film without a noise-aware sampler keeps none.
//!
//! LuxRender updates a running weighted mean and sum of squared deviations per pixel. Here a
//! pixel keeps the three sums Σw, Σw·Y and Σw·Y² in f64, which give the same variance
//! (Σw·Y²/Σw − (Σw·Y/Σw)²) and add exactly across tiles, farm deltas and merges, as the
//! film's own sums do.

/// Weighted luminance sums per pixel, row by row: `[Σw, Σw·Y, Σw·Y²]`.
#[derive(Clone, Debug, PartialEq)]
pub struct VarianceBuffer {
    width: u32,
    height: u32,
    sums: Vec<[f64; 3]>,
}

impl VarianceBuffer {
    /// An empty buffer (the size is checked by the film's limits before a render makes one).
    pub fn new(width: u32, height: u32) -> VarianceBuffer {
        VarianceBuffer {
            width,
            height,
            sums: vec![[0.0; 3]; width as usize * height as usize],
        }
    }

    /// A buffer from its sums, row by row (a film read back from the wire): `width × height`
    /// triples, all finite. (Filters with negative lobes, such as the default Mitchell, give
    /// negative weights, so any sign may arrive.)
    pub fn from_sums(width: u32, height: u32, sums: Vec<[f64; 3]>) -> Result<Self, String> {
        let n = width as usize * height as usize;
        if sums.len() != n {
            return Err(format!(
                "a {width}x{height} variance buffer needs {n} sums, got {}",
                sums.len()
            ));
        }
        check_finite(&sums)?;
        Ok(VarianceBuffer {
            width,
            height,
            sums,
        })
    }

    /// Overwrites every sum with `count` triples decoded by `read` (a farm delta read into a
    /// reused film: no fresh memory); refused unless `count` is the pixel count and every
    /// value finite.
    pub fn overwrite(
        &mut self,
        count: usize,
        mut read: impl FnMut(usize) -> [f64; 3],
    ) -> Result<(), String> {
        if count != self.sums.len() {
            return Err(format!(
                "a {}x{} variance buffer needs {} sums, got {count}",
                self.width,
                self.height,
                self.sums.len()
            ));
        }
        for (i, s) in self.sums.iter_mut().enumerate() {
            *s = read(i);
        }
        check_finite(&self.sums)
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    /// The sums `[Σw, Σw·Y, Σw·Y²]`, row by row.
    pub fn sums(&self) -> &[[f64; 3]] {
        &self.sums
    }

    /// Sets every sum to zero.
    pub fn clear(&mut self) {
        self.sums.fill([0.0; 3]);
    }

    /// Adds a contribution of luminance `y` with filter weight `weight` at (x, y_px); outside
    /// the buffer, a zero or non-finite weight or a non-finite luminance adds nothing.
    #[inline]
    pub fn add(&mut self, x: u32, y_px: u32, y: f32, weight: f32) {
        if x >= self.width || y_px >= self.height || weight == 0.0 {
            return;
        }
        if !(y.is_finite() && weight.is_finite()) {
            return;
        }
        let i = y_px as usize * self.width as usize + x as usize;
        if let Some(s) = self.sums.get_mut(i) {
            let (w, y) = (f64::from(weight), f64::from(y));
            s[0] += w;
            s[1] += w * y;
            s[2] += w * y * y;
        }
    }

    /// Adds another buffer placed with its top left pixel at (x0, y0); the parts outside are
    /// ignored.
    pub fn merge_at(&mut self, other: &VarianceBuffer, x0: u32, y0: u32) {
        let (sw, ow) = (self.width as usize, other.width as usize);
        for y in 0..other.height as usize {
            let ty = y0 as usize + y;
            if ty >= self.height as usize {
                break;
            }
            let cols = ow.min(sw.saturating_sub(x0 as usize));
            let (Some(dst), Some(src)) = (
                self.sums
                    .get_mut(ty * sw + x0 as usize..ty * sw + x0 as usize + cols),
                other.sums.get(y * ow..y * ow + cols),
            ) else {
                continue;
            };
            for (d, s) in dst.iter_mut().zip(src) {
                d[0] += s[0];
                d[1] += s[1];
                d[2] += s[2];
            }
        }
    }

    /// The weighted variance of the luminance of one contribution to pixel (x, y)
    /// (LuxRender's `GetVariance`), `None` for a pixel no contribution has reached yet.
    pub fn variance(&self, x: u32, y: u32) -> Option<f64> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let s = self
            .sums
            .get(y as usize * self.width as usize + x as usize)?;
        variance_of(s)
    }

    /// Per pixel, the standard deviation of one contribution's luminance, row by row; `None`
    /// when some pixel has no contribution yet.
    pub fn deviations(&self) -> Option<Vec<f32>> {
        self.sums
            .iter()
            .map(|s| variance_of(s).map(|v| v.sqrt() as f32))
            .collect()
    }
}

/// Every value finite, else why not.
fn check_finite(sums: &[[f64; 3]]) -> Result<(), String> {
    if sums.iter().flatten().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err("variance sums must be finite".into())
    }
}

/// Σw·Y²/Σw − (Σw·Y/Σw)², not below 0 (rounding); `None` without weight.
fn variance_of(s: &[f64; 3]) -> Option<f64> {
    if s[0] > 0.0 {
        let mean = s[1] / s[0];
        Some((s[2] / s[0] - mean * mean).max(0.0))
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weighted_variance_matches_the_definition_and_merges_exactly() {
        let samples = [(0.5f32, 1.0f32), (2.0, 0.25), (1.0, 0.5), (4.0, 0.125)];
        let mut whole = VarianceBuffer::new(3, 2);
        for (y, w) in samples {
            whole.add(1, 1, y, w);
        }
        let wsum: f64 = samples.iter().map(|s| f64::from(s.1)).sum();
        let mean: f64 = samples
            .iter()
            .map(|s| f64::from(s.0) * f64::from(s.1))
            .sum::<f64>()
            / wsum;
        let var: f64 = samples
            .iter()
            .map(|s| f64::from(s.1) * (f64::from(s.0) - mean).powi(2))
            .sum::<f64>()
            / wsum;
        let got = whole.variance(1, 1).unwrap();
        assert!((got - var).abs() < 1e-12, "{got} {var}");
        assert_eq!(whole.variance(0, 0), None);
        assert!(whole.deviations().is_none());
        // two halves, one placed by offset, sum to the whole
        let mut a = VarianceBuffer::new(3, 2);
        let mut b = VarianceBuffer::new(1, 1);
        for (k, (y, w)) in samples.iter().enumerate() {
            if k % 2 == 0 {
                a.add(1, 1, *y, *w);
            } else {
                b.add(0, 0, *y, *w);
            }
        }
        a.merge_at(&b, 1, 1);
        assert!((a.variance(1, 1).unwrap() - var).abs() < 1e-12);
        // a constant pixel has no spread; junk is ignored
        let mut c = VarianceBuffer::new(1, 1);
        for _ in 0..10 {
            c.add(0, 0, 12.6, 0.7);
        }
        c.add(0, 0, f32::NAN, 1.0);
        c.add(0, 0, 1.0, f32::INFINITY);
        c.add(5, 0, 1.0, 1.0);
        assert!(c.variance(0, 0).unwrap() < 1e-9);
        assert_eq!(c.deviations().unwrap().len(), 1);
    }

    #[test]
    fn sums_from_the_wire_are_checked() {
        assert!(VarianceBuffer::from_sums(2, 1, vec![[1.0, 0.5, 0.5]; 2]).is_ok());
        assert!(VarianceBuffer::from_sums(2, 1, vec![[1.0, 0.5, 0.5]; 3]).is_err());
        // negative lobes (Mitchell) give negative weights and squares: accepted
        assert!(VarianceBuffer::from_sums(1, 1, vec![[-1.0, 0.5, -0.5]]).is_ok());
        assert!(VarianceBuffer::from_sums(1, 1, vec![[1.0, f64::NAN, 0.5]]).is_err());
        assert!(VarianceBuffer::from_sums(1, 1, vec![[1.0, 0.5, f64::INFINITY]]).is_err());
        let mut v = VarianceBuffer::new(2, 1);
        assert!(v.overwrite(2, |i| [i as f64, 1.0, 2.0]).is_ok());
        assert_eq!(v.sums(), &[[0.0, 1.0, 2.0], [1.0, 1.0, 2.0]]);
        assert!(v.overwrite(3, |_| [1.0; 3]).is_err());
        assert!(v.overwrite(2, |_| [f64::NAN; 3]).is_err());
    }
}
