//! The sample extent, and what "samples per pixel" means with it: LuxRender's convention,
//! stated here once for every sampler, integrator and halt rule.
//!
//! LuxRender draws camera samples over the Film's *sample extent* (`Film::GetSampleExtent`):
//! the crop window's pixels widened by the pixel filter's width on each side
//! ([`crate::filter::Filter::sample_extent`]), so that a border pixel's filter footprint is
//! covered as an interior pixel's is. Here, as there:
//!
//! - every sampler draws its eye samples over the extent: the pixel samplers (random,
//!   lowdiscrepancy, sobol) give each pixel of the extent `pixelsamples` samples a pass
//!   (`super::tile`; a margin pixel outside the buffer takes the sampling map's count of the
//!   nearest buffer pixel), metropolis and erpt draw film positions over its area
//!   (`super::mlt`, `super::erpt`);
//! - light paths reach the camera anywhere on the extent, the camera's importance being
//!   normalised over its area (`crate::camera::Camera::connect`);
//! - the film's sample count counts every sample drawn, the margin's included: LuxRender's
//!   `numberOfSamples`, so an FLM's count means the same in both programs. A pass adds
//!   [`SampleExtent::pass_samples`] (extent pixels × `pixelsamples`), and a metropolis or
//!   erpt pass takes as many traces;
//! - `haltspp` N halts when the count reaches N × extent pixels (LuxRender's
//!   `samplePerPass`): N samples per pixel of the extent, as `pixelsamples` counts them.
//!   [`crate::film::Film::spp`] (count / image pixels) reads slightly above that;
//! - a per-pixel buffer needs nothing more (its pixels are weighted means); a per-screen
//!   buffer reads sum × image pixels / count (LuxRender's normalisation), so a sample drawn
//!   uniformly over the extent adds its per-screen contributions scaled by extent pixels /
//!   image pixels ([`SampleExtent::per_screen_scale`]), the light paths' splats included.

use crate::film::FilmParams;
use crate::filter::Filter;
use crate::lxs::{Diagnostic, SceneDescription};

/// Raster pixels `[x0, x1) × [y0, y1)` over the full image (possibly beyond it), and the
/// number of image (crop window) pixels the film holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SampleExtent {
    pub x0: i32,
    pub x1: i32,
    pub y0: i32,
    pub y1: i32,
    /// Pixels of the film buffer (the crop window).
    pub image_pixels: u64,
}

impl SampleExtent {
    /// The extent of a film of these parameters under this filter.
    pub fn new(fp: &FilmParams, filter: &Filter) -> SampleExtent {
        let [x0, x1, y0, y1] = filter.sample_extent(
            fp.x_pixel_start,
            fp.x_pixel_count,
            fp.y_pixel_start,
            fp.y_pixel_count,
        );
        SampleExtent {
            x0,
            x1: x1.max(x0),
            y0,
            y1: y1.max(y0),
            image_pixels: fp.pixel_count(),
        }
    }

    /// The extent of a scene from its Film and PixelFilter statements alone (what the master
    /// needs for `haltspp`); `None` when either does not build (the workers refuse the scene
    /// then anyway).
    pub fn of_scene(desc: &SceneDescription) -> Option<SampleExtent> {
        let fp = FilmParams::from_entity(desc.film.as_ref()).ok()?;
        let mut warnings: Vec<Diagnostic> = Vec::new();
        let filter = Filter::build(desc.pixel_filter.as_ref(), &mut warnings).ok()?;
        Some(SampleExtent::new(&fp, &filter))
    }

    /// `[x0, x1, y0, y1]`.
    pub fn bounds(&self) -> [i32; 4] {
        [self.x0, self.x1, self.y0, self.y1]
    }

    /// Pixels of the extent: the samples one pass of one sample per pixel draws.
    pub fn pixels(&self) -> u64 {
        let w = (i64::from(self.x1) - i64::from(self.x0)).max(0) as u64;
        let h = (i64::from(self.y1) - i64::from(self.y0)).max(0) as u64;
        w.saturating_mul(h)
    }

    /// Samples a pass of `spp` samples per pixel draws (and the film counts).
    pub fn pass_samples(&self, spp: u32) -> u64 {
        self.pixels().saturating_mul(u64::from(spp))
    }

    /// The factor on per-screen contributions of samples drawn uniformly over the extent:
    /// extent pixels / image pixels.
    pub fn per_screen_scale(&self) -> f32 {
        (self.pixels() as f64 / self.image_pixels.max(1) as f64) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lxs::{parse_str, ParseOptions};

    fn extent(head: &str) -> SampleExtent {
        let text = format!("{head}\nWorldBegin\nWorldEnd\n");
        let desc = parse_str(&text, "t.lxs", &ParseOptions::default()).unwrap();
        SampleExtent::of_scene(&desc).unwrap()
    }

    #[test]
    fn the_extent_widens_the_crop_window_by_the_filter() {
        // Mitchell's default width 2: two pixels each side, as LuxRender's 516² for 512².
        let e = extent(
            "Film \"fleximage\" \"integer xresolution\" [512] \"integer yresolution\" [512]",
        );
        assert_eq!(e.bounds(), [-2, 514, -2, 514]);
        assert_eq!(e.pixels(), 516 * 516);
        assert_eq!(e.pass_samples(4), 4 * 516 * 516);
        assert!((f64::from(e.per_screen_scale()) - 516.0 * 516.0 / (512.0 * 512.0)).abs() < 1e-6);
        // A crop window: the extent reaches into the image beyond it.
        let e = extent(
            "Film \"fleximage\" \"integer xresolution\" [100] \"integer yresolution\" [40] \
             \"float cropwindow\" [0.25 0.5 0.25 0.5]\nPixelFilter \"box\"",
        );
        assert_eq!(e.image_pixels, 25 * 10);
        // LuxRender's extent for the 0.5-wide box reaches one pixel past the crop.
        assert_eq!(e.bounds(), [25, 51, 10, 21]);
    }
}
