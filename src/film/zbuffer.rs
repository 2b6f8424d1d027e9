//! The depth (Z) buffer a Film keeps when one of its outputs asks for a Z channel
//! (`write_exr_ZBuf`, ...): per buffer pixel, the filter-weighted mean of the samples' depths
//! (the distance from the camera to the first surface hit), as LuxRender's fleximage adds each
//! sample's depth with its filter weight. Samples that hit nothing add no depth.
//!
//! Renders add depths tile by tile ([`ZBuffer::add`], [`ZBuffer::merge_at`]); outputs take
//! [`ZBuffer::depths`] normalised as `write_*_zbuf_normalizationtype` asks. Sums are f64.

use super::image_output::ZBufNorm;

/// Depth sums and weights per pixel, row by row.
#[derive(Clone, Debug, PartialEq)]
pub struct ZBuffer {
    width: u32,
    height: u32,
    sum: Vec<f64>,
    weight: Vec<f64>,
}

impl ZBuffer {
    /// An empty buffer (the size is checked by the film's limits before a render makes one).
    pub fn new(width: u32, height: u32) -> ZBuffer {
        let n = width as usize * height as usize;
        ZBuffer {
            width,
            height,
            sum: vec![0.0; n],
            weight: vec![0.0; n],
        }
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    /// Adds a depth with a filter weight at (x, y); outside the buffer, non-finite or
    /// non-positive values are ignored.
    pub fn add(&mut self, x: u32, y: u32, depth: f32, weight: f32) {
        if x >= self.width || y >= self.height {
            return;
        }
        if !(depth.is_finite() && depth > 0.0 && weight.is_finite() && weight != 0.0) {
            return;
        }
        let i = y as usize * self.width as usize + x as usize;
        self.sum[i] += f64::from(depth) * f64::from(weight);
        self.weight[i] += f64::from(weight);
    }

    /// Adds another buffer placed with its top left pixel at (x0, y0); the parts outside are
    /// ignored.
    pub fn merge_at(&mut self, other: &ZBuffer, x0: u32, y0: u32) {
        for y in 0..other.height {
            let ty = y0 as usize + y as usize;
            if ty >= self.height as usize {
                break;
            }
            for x in 0..other.width {
                let tx = x0 as usize + x as usize;
                if tx >= self.width as usize {
                    break;
                }
                let (i, j) = (
                    ty * self.width as usize + tx,
                    (y * other.width + x) as usize,
                );
                self.sum[i] += other.sum[j];
                self.weight[i] += other.weight[j];
            }
        }
    }

    /// The mean depth per pixel (0 where no sample hit a surface).
    pub fn raw(&self) -> Vec<f32> {
        self.sum
            .iter()
            .zip(&self.weight)
            .map(|(&s, &w)| {
                let d = if w > 0.0 { s / w } else { 0.0 };
                if d.is_finite() && d > 0.0 {
                    d as f32
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// The depths as an output writes them: raw, mapped from [hither, yon] to [0, 1]
    /// ("Camera Start/End clip"), or from the smallest to the largest depth present
    /// ("Min/Max"). Pixels without depth stay 0.
    pub fn depths(&self, norm: ZBufNorm, hither: f32, yon: f32) -> Vec<f32> {
        let raw = self.raw();
        let (lo, hi) = match norm {
            ZBufNorm::None => return raw,
            ZBufNorm::CameraStartEnd => (hither, yon),
            ZBufNorm::MinMax => raw
                .iter()
                .filter(|&&d| d > 0.0)
                .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &d| {
                    (a.min(d), b.max(d))
                }),
        };
        let span = hi - lo;
        raw.into_iter()
            .map(|d| {
                if d > 0.0 && span > 0.0 && span.is_finite() {
                    ((d - lo) / span).clamp(0.0, 1.0)
                } else {
                    0.0
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weighted_mean_and_normalisations() {
        let mut z = ZBuffer::new(2, 1);
        z.add(0, 0, 2.0, 1.0);
        z.add(0, 0, 5.0, 0.5); // mean (2 + 2.5) / 1.5 = 3
        z.add(1, 0, 7.0, 1.0);
        z.add(5, 0, 1.0, 1.0); // outside
        z.add(1, 0, f32::NAN, 1.0);
        assert_eq!(z.raw(), vec![3.0, 7.0]);
        assert_eq!(z.depths(ZBufNorm::MinMax, 0.0, 0.0), vec![0.0, 1.0]);
        let c = z.depths(ZBufNorm::CameraStartEnd, 1.0, 11.0);
        assert!((c[0] - 0.2).abs() < 1e-6 && (c[1] - 0.6).abs() < 1e-6);
        let mut big = ZBuffer::new(3, 2);
        big.merge_at(&z, 1, 1);
        assert_eq!(big.raw(), vec![0.0, 0.0, 0.0, 0.0, 3.0, 7.0]);
    }
}
