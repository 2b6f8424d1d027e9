//! Each pixel's samples taken so far under a sampling map, so that a pixel's samples are
//! always the next indices of its own sample sequence.
//!
//! Without a map every pixel takes `pixelsamples` a pass, and pass `p`'s samples are the
//! indices `p × pixelsamples ..` of the pixel's sequence: every pixel's samples are a prefix
//! of its sequence, which is what keeps lowdiscrepancy and sobol stratified. Under a map the
//! counts differ from pixel to pixel and pass to pass, so the session keeps, per raster
//! pixel of the sample extent, the index its next sample takes: a pixel given 3 samples in
//! one pass and 1 in the next takes indices n, n+1, n+2 and then n+3. The counts start, when
//! the first map arrives, at the samples the uniform passes gave (`pass × pixelsamples`),
//! and every complete pass adds the map's count of each pixel (the same deterministic count
//! the tiles drew, `super::tile`). An earlier scheme gave each pass a fixed block of
//! indices, so a pixel's samples were a strided subset of its sequence and lost the
//! sampler's stratification (noise-aware sobol rendered with random's error per sample).

use super::extent::SampleExtent;

/// Per raster pixel of the sample extent, the index of its next sample.
#[derive(Clone, Debug)]
pub struct SampleCounts {
    x0: i32,
    y0: i32,
    w: usize,
    h: usize,
    next: Vec<u64>,
}

impl SampleCounts {
    /// Every pixel of `extent` with `start` samples taken.
    pub fn new(extent: SampleExtent, start: u64) -> SampleCounts {
        let w = usize::try_from(i64::from(extent.x1) - i64::from(extent.x0)).unwrap_or(0);
        let h = usize::try_from(i64::from(extent.y1) - i64::from(extent.y0)).unwrap_or(0);
        SampleCounts {
            x0: extent.x0,
            y0: extent.y0,
            w,
            h,
            next: vec![start; w * h],
        }
    }

    fn slot(&self, px: i32, py: i32) -> Option<usize> {
        let x = usize::try_from(i64::from(px) - i64::from(self.x0)).ok()?;
        let y = usize::try_from(i64::from(py) - i64::from(self.y0)).ok()?;
        (x < self.w && y < self.h).then_some(y * self.w + x)
    }

    /// The index of raster pixel (`px`, `py`)'s next sample (`None` outside the extent).
    pub fn next(&self, px: i32, py: i32) -> Option<u64> {
        self.slot(px, py).and_then(|i| self.next.get(i).copied())
    }

    /// Counts a complete pass: every pixel took `plan(px, py)` samples.
    pub fn advance(&mut self, plan: impl Fn(i32, i32) -> u32) {
        for y in 0..self.h {
            for x in 0..self.w {
                let (px, py) = (self.x0 + x as i32, self.y0 + y as i32);
                if let Some(n) = self.next.get_mut(y * self.w + x) {
                    *n += u64::from(plan(px, py));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn extent() -> SampleExtent {
        SampleExtent {
            x0: -2,
            x1: 5,
            y0: -1,
            y1: 3,
            image_pixels: 12,
        }
    }

    #[test]
    fn a_pixels_samples_are_consecutive_indices_across_passes() {
        let mut c = SampleCounts::new(extent(), 8);
        assert_eq!(c.next(-2, -1), Some(8));
        assert_eq!(c.next(4, 2), Some(8));
        assert_eq!(c.next(5, 0), None);
        assert_eq!(c.next(0, -2), None);
        // Pass 1: pixel (x, y) takes x + 3 samples; pass 2: 1 each.
        let plan1 = |px: i32, _py: i32| (px + 3) as u32;
        let mut taken: Vec<u64> = Vec::new();
        for k in 0..plan1(1, 1) {
            taken.push(c.next(1, 1).unwrap() + u64::from(k));
        }
        c.advance(plan1);
        taken.push(c.next(1, 1).unwrap());
        c.advance(|_, _| 1);
        assert_eq!(taken, vec![8, 9, 10, 11, 12]);
        assert_eq!(c.next(1, 1), Some(13));
        assert_eq!(c.next(-2, -1), Some(8 + 1 + 1));
    }
}
