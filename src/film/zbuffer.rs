//! The depth (Z) buffer a Film keeps when its EXR output asks for a Z channel
//! (`write_exr_ZBuf`): per buffer pixel, the mean of the depths (the distance from the camera
//! to the first surface hit) of the samples whose filter footprint covers the pixel. LuxRender
//! 1.x's film adds each sample's depth with weight 1 to every pixel of the footprint, whatever
//! the filter's weight there (`Film::AddTileSamples`); so does luxfarm. Samples that hit
//! nothing add no depth.
//!
//! Renders add depths tile by tile ([`ZBuffer::add`], [`ZBuffer::merge_at`]); outputs take
//! [`ZBuffer::depths`] normalised as `write_exr_zbuf_normalizationtype` asks. Sums are f64.
//! Only the EXR output carries a Z channel: LuxRender 1.x's PNG and TGA writers take the
//! `write_png_ZBuf`/`write_tga_ZBuf` flags and write no depth, so a Film asking for those
//! alone renders no depth buffer (see `FilmParams::wants_zbuf`).

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

    /// A buffer from its sums and weights, row by row (a film read back from the wire):
    /// both of `width × height` values, finite, the weights not negative.
    pub fn from_sums(
        width: u32,
        height: u32,
        sum: Vec<f64>,
        weight: Vec<f64>,
    ) -> Result<ZBuffer, String> {
        let n = width as usize * height as usize;
        if sum.len() != n || weight.len() != n {
            return Err(format!(
                "a {width}x{height} depth buffer needs {n} sums and weights, got {} and {}",
                sum.len(),
                weight.len()
            ));
        }
        if !sum.iter().all(|v| v.is_finite()) || !weight.iter().all(|w| w.is_finite() && *w >= 0.0)
        {
            return Err("depth sums must be finite and their weights not negative".into());
        }
        Ok(ZBuffer {
            width,
            height,
            sum,
            weight,
        })
    }

    /// The depth sums, row by row.
    pub fn sums(&self) -> &[f64] {
        &self.sum
    }

    /// The weight sums (samples added), row by row.
    pub fn weights(&self) -> &[f64] {
        &self.weight
    }

    /// Sets every sum and weight to zero.
    pub fn clear(&mut self) {
        self.sum.fill(0.0);
        self.weight.fill(0.0);
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

    /// The depths the EXR output writes, as LuxRender 1.x's fleximage writes them for each
    /// `write_exr_zbuf_normalizationtype`:
    /// - "None": the mean depths, 0 where nothing was hit;
    /// - "Camera Start/End clip": the same (LuxRender names this option and leaves the depths
    ///   as they are);
    /// - "Min/Max": (z_max − z) / (z_max − z_min) over the depths present, so the nearest
    ///   surface is 1 and the farthest 0; a pixel without depth (z = 0) comes out at
    ///   z_max / (z_max − z_min), above 1, as LuxRender writes it. Without any depth
    ///   every pixel is 0 (as in LuxRender); with a single depth value, where LuxRender
    ///   divides by zero (NaN and infinities), every pixel is 0 here.
    pub fn depths(&self, norm: ZBufNorm) -> Vec<f32> {
        let raw = self.raw();
        if norm != ZBufNorm::MinMax {
            return raw;
        }
        let (near, far) = raw
            .iter()
            .filter(|&&d| d > 0.0)
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &d| {
                (a.min(d), b.max(d))
            });
        let span = far - near;
        if !(span > 0.0 && span.is_finite()) {
            return vec![0.0; raw.len()];
        }
        raw.into_iter().map(|d| (far - d) / span).collect()
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
        assert_eq!(z.depths(ZBufNorm::None), vec![3.0, 7.0]);
        assert_eq!(z.depths(ZBufNorm::CameraStartEnd), vec![3.0, 7.0]);
        assert_eq!(z.depths(ZBufNorm::MinMax), vec![1.0, 0.0]);
        let mut gap = ZBuffer::new(3, 1);
        gap.add(0, 0, 2.0, 1.0);
        gap.add(2, 0, 6.0, 1.0);
        // The empty pixel as LuxRender writes it: z_max / (z_max - z_min).
        assert_eq!(gap.depths(ZBufNorm::MinMax), vec![1.0, 1.5, 0.0]);
        let mut one = ZBuffer::new(2, 1);
        one.add(0, 0, 4.0, 1.0);
        assert_eq!(one.depths(ZBufNorm::MinMax), vec![0.0, 0.0]);
        let mut big = ZBuffer::new(3, 2);
        big.merge_at(&z, 1, 1);
        assert_eq!(big.raw(), vec![0.0, 0.0, 0.0, 0.0, 3.0, 7.0]);
    }
}
