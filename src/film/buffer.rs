//! `Film`: the sample buffers of LuxRender's fleximage film, kept in f64.
//!
//! Per light group ("buffer group") and per buffer configuration, every pixel holds the weighted
//! sums of X, Y, Z and alpha and the sum of the weights; every group holds its sample count.
//! LuxRender keeps these in f32; here they are f64 so that merging thousands of network deltas
//! loses nothing. The FLM format stores f32 and a double sample count (see `flm`).

use super::{FilmError, VarianceBuffer, ZBuffer};
use rayon::prelude::*;

/// Number of f64 values per pixel: X, Y, Z, alpha, weight sum.
pub const PIXEL_VALUES: usize = 5;
/// Largest accepted film side (pixels), as for FLM files.
pub const MAX_AXIS: u32 = 65_536;
/// Largest accepted pixel count of a film.
pub const MAX_PIXELS: u64 = 1 << 28;

/// How a buffer is normalised when the image is built (LuxRender's `BufferType`, FLM ids).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BufferType {
    /// Divided by the pixel's weight sum (the ordinary fleximage buffer).
    PerPixel = 0,
    /// Scaled by pixel count / group sample count (light-tracing integrators).
    PerScreen = 1,
    /// Per screen with a renderer-specific scale (SPPM); the scale is taken as 1.
    PerScreenScaled = 2,
    /// Used as is.
    Raw = 3,
}

impl BufferType {
    pub fn from_id(id: i32) -> Option<BufferType> {
        Some(match id {
            0 => BufferType::PerPixel,
            1 => BufferType::PerScreen,
            2 => BufferType::PerScreenScaled,
            3 => BufferType::Raw,
            _ => return None,
        })
    }

    pub fn id(self) -> i32 {
        self as i32
    }

    pub fn name(self) -> &'static str {
        match self {
            BufferType::PerPixel => "per-pixel normalized",
            BufferType::PerScreen => "per-screen normalized",
            BufferType::PerScreenScaled => "per-screen scaled",
            BufferType::Raw => "raw",
        }
    }
}

/// Checks a film size against the limits (before anything is allocated).
pub fn check_size(width: u32, height: u32) -> Result<(), FilmError> {
    if width == 0 || height == 0 {
        return Err(FilmError::BadHeader(format!(
            "resolution {width}x{height} is empty"
        )));
    }
    if width > MAX_AXIS || height > MAX_AXIS || u64::from(width) * u64::from(height) > MAX_PIXELS {
        return Err(FilmError::TooLarge { width, height });
    }
    Ok(())
}

/// The film buffers: f64 sums per light group, buffer and pixel, and f64 sample counts; and
/// the depth sums when the film carries a Z buffer (a farm delta of a Film that writes Z), and
/// the luminance spread sums of a noise-aware render ([`VarianceBuffer`]).
#[derive(Debug, PartialEq)]
pub struct Film {
    width: u32,
    height: u32,
    groups: Vec<String>,
    buffer_types: Vec<BufferType>,
    /// One vector per (group, buffer), index `group * buffers + buffer`; 5 values per pixel.
    data: Vec<Vec<f64>>,
    samples: Vec<f64>,
    rejected: u64,
    /// Depth sums and weights (`write_exr_ZBuf`), merged with the film; `None` without Z.
    depth: Option<ZBuffer>,
    /// Luminance spread sums of a noise-aware render, merged with the film; `None` otherwise.
    variance: Option<VarianceBuffer>,
}

impl Clone for Film {
    fn clone(&self) -> Film {
        Film {
            width: self.width,
            height: self.height,
            groups: self.groups.clone(),
            buffer_types: self.buffer_types.clone(),
            data: self.data.clone(),
            samples: self.samples.clone(),
            rejected: self.rejected,
            depth: self.depth.clone(),
            variance: self.variance.clone(),
        }
    }

    /// Copies `source` into the buffers this film already holds (no fresh pages when the
    /// layouts match: a snapshot taken again and again of a large film).
    fn clone_from(&mut self, source: &Film) {
        self.width = source.width;
        self.height = source.height;
        self.groups.clone_from(&source.groups);
        self.buffer_types.clone_from(&source.buffer_types);
        self.data.clone_from(&source.data);
        self.samples.clone_from(&source.samples);
        self.rejected = source.rejected;
        self.depth.clone_from(&source.depth);
        self.variance.clone_from(&source.variance);
    }
}

impl Film {
    /// A cleared film of `width` x `height` buffer pixels (the crop window's size) with one
    /// per-pixel normalised buffer per light group. No group names: one group, "default".
    /// Sizes are clamped to at least 1 pixel; callers validate limits with [`check_size`].
    pub fn new(width: u32, height: u32, groups: Vec<String>) -> Film {
        Film::build(
            width.max(1),
            height.max(1),
            groups,
            vec![BufferType::PerPixel],
        )
    }

    /// A cleared film with explicit buffer configurations, refusing absurd sizes.
    pub fn with_buffers(
        width: u32,
        height: u32,
        groups: Vec<String>,
        buffer_types: Vec<BufferType>,
    ) -> Result<Film, FilmError> {
        check_size(width, height)?;
        if buffer_types.is_empty() {
            return Err(FilmError::BadHeader("no buffer configuration".into()));
        }
        Ok(Film::build(width, height, groups, buffer_types))
    }

    fn build(width: u32, height: u32, groups: Vec<String>, buffer_types: Vec<BufferType>) -> Film {
        let groups = if groups.is_empty() {
            vec!["default".to_string()]
        } else {
            groups
        };
        let n = width as usize * height as usize * PIXEL_VALUES;
        let count = groups.len() * buffer_types.len();
        Film {
            width,
            height,
            data: (0..count).map(|_| vec![0.0; n]).collect(),
            samples: vec![0.0; groups.len()],
            groups,
            buffer_types,
            rejected: 0,
            depth: None,
            variance: None,
        }
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    pub fn pixel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// Light group names, in buffer group order.
    pub fn groups(&self) -> &[String] {
        &self.groups
    }

    pub fn buffer_types(&self) -> &[BufferType] {
        &self.buffer_types
    }

    /// Samples rejected so far (non-finite or negative values, outliers).
    pub fn rejected(&self) -> u64 {
        self.rejected
    }

    /// Sets the rejection count (a delta decoded into a reused film).
    pub fn set_rejected(&mut self, n: u64) {
        self.rejected = n;
    }

    /// Counts samples rejected outside the film (e.g. by outlier rejection).
    pub fn add_rejected(&mut self, n: u64) {
        self.rejected += n;
    }

    /// The sample count of a light group (0 for an unknown group).
    pub fn sample_count(&self, group: usize) -> f64 {
        self.samples.get(group).copied().unwrap_or(0.0)
    }

    /// Sets the sample count of a group (FLM reading).
    pub fn set_sample_count(&mut self, group: usize, n: f64) {
        if let Some(s) = self.samples.get_mut(group) {
            *s = n;
        }
    }

    /// The largest group sample count (LuxRender keeps them equal).
    pub fn total_samples(&self) -> f64 {
        self.samples.iter().copied().fold(0.0, f64::max)
    }

    /// Samples per pixel: samples / buffer pixels, as LuxRender reports it. The count holds
    /// the samples of the sample extent's margin too, so this reads slightly above the
    /// `pixelsamples` per pass that haltspp counts (`crate::render::extent`).
    pub fn spp(&self) -> f64 {
        self.total_samples() / self.pixel_count() as f64
    }

    /// Adds `weight * xyz`, `weight * alpha` and `weight` to a buffer pixel of buffer 0 of a
    /// group. Out-of-range pixels or groups are ignored; a non-finite value, a negative Y or
    /// alpha, or a non-finite weight is rejected and counted, as LuxRender's film does.
    /// Negative weights are kept: Mitchell, Catmull-Rom and sinc filters have negative lobes.
    pub fn add_splat(
        &mut self,
        group: usize,
        x: u32,
        y: u32,
        xyz: [f32; 3],
        alpha: f32,
        weight: f32,
    ) {
        self.add_buffer_splat(group, 0, x, y, xyz, alpha, weight);
    }

    /// As [`Film::add_splat`] for any buffer configuration.
    #[allow(clippy::too_many_arguments)]
    pub fn add_buffer_splat(
        &mut self,
        group: usize,
        buffer: usize,
        x: u32,
        y: u32,
        xyz: [f32; 3],
        alpha: f32,
        weight: f32,
    ) {
        if x >= self.width || y >= self.height || buffer >= self.buffer_types.len() {
            return;
        }
        let valid = xyz.iter().all(|v| v.is_finite())
            && xyz[1] >= 0.0
            && alpha.is_finite()
            && alpha >= 0.0
            && weight.is_finite();
        if !valid {
            self.rejected += 1;
            return;
        }
        let nbuf = self.buffer_types.len();
        let offset = (y as usize * self.width as usize + x as usize) * PIXEL_VALUES;
        let Some(buf) = self.data.get_mut(group * nbuf + buffer) else {
            return;
        };
        let w = f64::from(weight);
        let p = &mut buf[offset..offset + PIXEL_VALUES];
        p[0] += w * f64::from(xyz[0]);
        p[1] += w * f64::from(xyz[1]);
        p[2] += w * f64::from(xyz[2]);
        p[3] += w * f64::from(alpha);
        p[4] += w;
    }

    /// Adds `n` samples to every group's count.
    pub fn add_sample_count(&mut self, n: f64) {
        for s in &mut self.samples {
            *s += n;
        }
    }

    /// Whether another film has the same resolution, group count and buffer layout.
    pub fn check_layout(&self, other: &Film) -> Result<(), FilmError> {
        if self.width != other.width || self.height != other.height {
            return Err(FilmError::Mismatch(format!(
                "resolution {}x{} against {}x{}",
                self.width, self.height, other.width, other.height
            )));
        }
        if self.groups.len() != other.groups.len() {
            return Err(FilmError::Mismatch(format!(
                "{} light groups against {}",
                self.groups.len(),
                other.groups.len()
            )));
        }
        if self.buffer_types != other.buffer_types {
            return Err(FilmError::Mismatch(format!(
                "buffers {:?} against {:?}",
                self.buffer_types, other.buffer_types
            )));
        }
        Ok(())
    }

    /// Adds another film of the same layout: every sum and every sample count.
    pub fn merge(&mut self, other: &Film) -> Result<(), FilmError> {
        self.check_layout(other)?;
        for (dst, src) in self.data.iter_mut().zip(&other.data) {
            add_slices(dst, src);
        }
        for (d, s) in self.samples.iter_mut().zip(&other.samples) {
            *d += s;
        }
        self.rejected += other.rejected;
        match (&mut self.depth, &other.depth) {
            (Some(d), Some(o)) => d.merge_at(o, 0, 0),
            (None, Some(o)) => self.depth = Some(o.clone()),
            _ => {}
        }
        match (&mut self.variance, &other.variance) {
            (Some(v), Some(o)) => v.merge_at(o, 0, 0),
            (None, Some(o)) => self.variance = Some(o.clone()),
            _ => {}
        }
        Ok(())
    }

    /// Adds a smaller film's pixel sums at offset (x0, y0); sample counts are not added (tile
    /// rendering adds the count once for the whole pass). The tile must fit inside the film
    /// and have the same groups and buffers.
    pub fn merge_at(&mut self, tile: &Film, x0: u32, y0: u32) -> Result<(), FilmError> {
        let fits = u64::from(x0) + u64::from(tile.width) <= u64::from(self.width)
            && u64::from(y0) + u64::from(tile.height) <= u64::from(self.height);
        if !fits {
            return Err(FilmError::Mismatch(format!(
                "tile {}x{} at ({x0}, {y0}) exceeds film {}x{}",
                tile.width, tile.height, self.width, self.height
            )));
        }
        if tile.groups.len() != self.groups.len() || tile.buffer_types != self.buffer_types {
            return Err(FilmError::Mismatch("tile groups or buffers differ".into()));
        }
        let row = tile.width as usize * PIXEL_VALUES;
        for (dst, src) in self.data.iter_mut().zip(&tile.data) {
            for ty in 0..tile.height as usize {
                let start = ((y0 as usize + ty) * self.width as usize + x0 as usize) * PIXEL_VALUES;
                add_slices(&mut dst[start..start + row], &src[ty * row..(ty + 1) * row]);
            }
        }
        self.rejected += tile.rejected;
        if let (Some(v), Some(tv)) = (&mut self.variance, &tile.variance) {
            v.merge_at(tv, x0, y0);
        }
        Ok(())
    }

    /// Clears all sums, sample counts and the rejection count (after sending a delta).
    pub fn clear(&mut self) {
        for buf in &mut self.data {
            buf.fill(0.0);
        }
        self.samples.fill(0.0);
        self.rejected = 0;
        if let Some(z) = &mut self.depth {
            z.clear();
        }
        if let Some(v) = &mut self.variance {
            v.clear();
        }
    }

    /// A `what` buffer of `w` × `h` kept beside the sums must have the film's size.
    fn check_side_buffer(&self, what: &str, w: u32, h: u32) -> Result<(), FilmError> {
        if (w, h) == (self.width, self.height) {
            return Ok(());
        }
        Err(FilmError::Mismatch(format!(
            "a {w}x{h} {what} buffer for a {}x{} film",
            self.width, self.height
        )))
    }

    /// The depth sums the film carries (a farm delta or job film of a Film writing Z).
    pub fn depth(&self) -> Option<&ZBuffer> {
        self.depth.as_ref()
    }

    /// Gives the film depth sums of its size (replacing any), or takes them away; a buffer
    /// of another size is refused.
    pub fn set_depth(&mut self, depth: Option<ZBuffer>) -> Result<(), FilmError> {
        if let Some(z) = &depth {
            self.check_side_buffer("depth", z.width(), z.height())?;
        }
        self.depth = depth;
        Ok(())
    }

    /// Adds a contribution's luminance `lum` with filter weight `weight` at pixel (x, y) to
    /// the variance sums, when the film keeps them (a noise-aware render).
    #[inline]
    pub fn add_variance(&mut self, x: u32, y: u32, lum: f32, weight: f32) {
        if let Some(v) = &mut self.variance {
            v.add(x, y, lum, weight);
        }
    }

    /// The luminance spread sums the film carries (a noise-aware render's film or delta).
    pub fn variance(&self) -> Option<&VarianceBuffer> {
        self.variance.as_ref()
    }

    /// The luminance spread sums, to write (a farm delta decoded into a reused film).
    pub fn variance_mut(&mut self) -> Option<&mut VarianceBuffer> {
        self.variance.as_mut()
    }

    /// Gives the film variance sums of its size (replacing any), or takes them away; a
    /// buffer of another size is refused.
    pub fn set_variance(&mut self, variance: Option<VarianceBuffer>) -> Result<(), FilmError> {
        if let Some(v) = &variance {
            self.check_side_buffer("variance", v.width(), v.height())?;
        }
        self.variance = variance;
        Ok(())
    }

    /// The five sums (X, Y, Z, alpha, weight) of a pixel; `None` out of range.
    pub fn pixel(&self, group: usize, buffer: usize, x: u32, y: u32) -> Option<[f64; 5]> {
        if x >= self.width || y >= self.height || buffer >= self.buffer_types.len() {
            return None;
        }
        let buf = self.data.get(group * self.buffer_types.len() + buffer)?;
        let o = (y as usize * self.width as usize + x as usize) * PIXEL_VALUES;
        let p = buf.get(o..o + PIXEL_VALUES)?;
        Some([p[0], p[1], p[2], p[3], p[4]])
    }

    /// The raw sums of one (group, buffer): 5 values per pixel, row by row.
    pub fn buffer(&self, group: usize, buffer: usize) -> Option<&[f64]> {
        if buffer >= self.buffer_types.len() {
            return None;
        }
        self.data
            .get(group * self.buffer_types.len() + buffer)
            .map(Vec::as_slice)
    }

    /// Mutable sums of one (group, buffer) (FLM decoding adds into these).
    pub fn buffer_mut(&mut self, group: usize, buffer: usize) -> Option<&mut [f64]> {
        if buffer >= self.buffer_types.len() {
            return None;
        }
        let n = self.buffer_types.len();
        self.data.get_mut(group * n + buffer).map(Vec::as_mut_slice)
    }

    /// Renames the light groups (FLM headers carry the names as parameters).
    pub fn set_group_name(&mut self, group: usize, name: &str) {
        if let Some(g) = self.groups.get_mut(group) {
            *g = name.to_string();
        }
    }
}

/// `dst += src`, element-wise, in parallel for large buffers.
fn add_slices(dst: &mut [f64], src: &[f64]) {
    const CHUNK: usize = 1 << 16;
    if dst.len() > 4 * CHUNK {
        dst.par_chunks_mut(CHUNK)
            .zip(src.par_chunks(CHUNK))
            .for_each(|(d, s)| d.iter_mut().zip(s).for_each(|(a, b)| *a += b));
    } else {
        dst.iter_mut().zip(src).for_each(|(a, b)| *a += b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splat_accumulates_weighted_sums() {
        let mut f = Film::new(4, 3, vec![]);
        f.add_splat(0, 1, 2, [1.0, 2.0, 3.0], 1.0, 0.5);
        f.add_splat(0, 1, 2, [1.0, 2.0, 3.0], 0.0, 0.5);
        assert_eq!(f.pixel(0, 0, 1, 2), Some([1.0, 2.0, 3.0, 0.5, 1.0]));
        assert_eq!(f.groups(), ["default"]);
    }

    #[test]
    fn invalid_splats_are_rejected_and_out_of_range_ignored() {
        let mut f = Film::new(2, 2, vec!["a".into()]);
        f.add_splat(0, 0, 0, [f32::NAN, 0.0, 0.0], 1.0, 1.0);
        f.add_splat(0, 0, 0, [0.0, -1.0, 0.0], 1.0, 1.0);
        f.add_splat(0, 0, 0, [0.0, 1.0, 0.0], 1.0, f32::INFINITY);
        f.add_splat(0, 5, 0, [0.0, 1.0, 0.0], 1.0, 1.0);
        f.add_splat(3, 0, 0, [0.0, 1.0, 0.0], 1.0, 1.0);
        assert_eq!(f.rejected(), 3);
        assert_eq!(f.pixel(0, 0, 0, 0), Some([0.0; 5]));
    }

    #[test]
    fn merge_adds_and_refuses_other_layouts() {
        let mut a = Film::new(2, 2, vec![]);
        let mut b = Film::new(2, 2, vec![]);
        a.add_splat(0, 0, 0, [1.0, 1.0, 1.0], 1.0, 1.0);
        b.add_splat(0, 0, 0, [2.0, 2.0, 2.0], 1.0, 1.0);
        a.add_sample_count(4.0);
        b.add_sample_count(4.0);
        a.merge(&b).unwrap();
        assert_eq!(a.pixel(0, 0, 0, 0), Some([3.0, 3.0, 3.0, 2.0, 2.0]));
        assert_eq!(a.sample_count(0), 8.0);
        assert_eq!(a.spp(), 2.0);
        assert!(a.merge(&Film::new(3, 2, vec![])).is_err());
        assert!(a
            .merge(&Film::new(2, 2, vec!["x".into(), "y".into()]))
            .is_err());
    }

    #[test]
    fn merge_at_places_tile_without_counts() {
        let mut f = Film::new(4, 4, vec![]);
        let mut t = Film::new(2, 2, vec![]);
        t.add_splat(0, 1, 1, [1.0, 1.0, 1.0], 1.0, 1.0);
        t.add_sample_count(4.0);
        f.merge_at(&t, 2, 1).unwrap();
        assert_eq!(f.pixel(0, 0, 3, 2), Some([1.0, 1.0, 1.0, 1.0, 1.0]));
        assert_eq!(f.sample_count(0), 0.0);
        assert!(f.merge_at(&t, 3, 3).is_err());
        f.clear();
        assert_eq!(f.pixel(0, 0, 3, 2), Some([0.0; 5]));
    }

    #[test]
    fn clone_from_reuses_the_buffers_and_copies_everything() {
        let mut a = Film::new(3, 2, vec!["a".into(), "b".into()]);
        a.add_splat(1, 2, 1, [1.0, 2.0, 3.0], 1.0, 0.5);
        a.add_sample_count(6.0);
        a.add_rejected(2);
        let mut b = Film::new(3, 2, vec!["x".into(), "y".into()]);
        b.add_splat(0, 0, 0, [5.0, 5.0, 5.0], 1.0, 1.0);
        let before = b.buffer(0, 0).map(<[f64]>::as_ptr);
        b.clone_from(&a);
        assert_eq!(b, a);
        assert_eq!(b.buffer(0, 0).map(<[f64]>::as_ptr), before);
        let mut c = Film::new(1, 1, vec![]);
        c.clone_from(&a);
        assert_eq!(c, a);
        c.set_rejected(0);
        assert_eq!(c.rejected(), 0);
    }

    #[test]
    fn size_limits() {
        assert!(check_size(65_536, 4096).is_ok());
        assert!(check_size(65_537, 1).is_err());
        assert!(check_size(65_536, 65_536).is_err());
        assert!(check_size(0, 5).is_err());
    }
}
