//! The steps LuxRender 1.x's noise-aware map takes after dividing each pixel's noise by its
//! visibility threshold (`Film::GenerateNoiseAwareMap`; [`super::map`]'s
//! `SamplingMap::from_deviation` runs them): a stretch between the 5th and 95th percentiles
//! of the pixels, then a heavy box filter.

/// Smallest share of the map every pixel keeps after the stretch (before the box filter).
pub const STRETCH_FLOOR: f32 = 0.05;

/// LuxRender's stretch of a map whose values lie in [0, 1]: with `lo` and `hi` half the
/// values at the 5th and 95th percentiles of the pixels, a value `v` becomes
/// `0.95 · max(v − hi, 0) / (hi − lo) + 0.05`: every pixel below `hi` keeps the floor and the
/// noisier ones rise linearly above it. `None` when the percentiles coincide (a flat map).
///
/// LuxRender takes the percentiles from a histogram of a million bins and counts 5 % of the
/// bins (50 000 pixels) from each end rather than 5 % of the pixels, so on a film of fewer
/// than about 100 000 pixels its stretch never finds two distinct ends and it samples
/// uniformly; luxfarm takes 5 % of the pixels, as the step is meant to (its comment says
/// "between 5th percentile value and 95th").
pub(super) fn stretch(v: &[f32]) -> Option<Vec<f32>> {
    let n = v.len();
    if n == 0 {
        return None;
    }
    let mut sorted = v.to_vec();
    sorted.sort_unstable_by(f32::total_cmp);
    let k = n / 20;
    let p5 = sorted.get(k).copied()?;
    let p95 = sorted.get(n - 1 - k).copied()?;
    if p95 <= p5 {
        return None;
    }
    let (lo, hi) = (0.5 * p5, 0.5 * p95);
    Some(
        v.iter()
            .map(|x| (1.0 - STRETCH_FLOOR) * (x - hi).max(0.0) / (hi - lo) + STRETCH_FLOOR)
            .collect(),
    )
}

/// A separable box filter of radius `r` (a (2r+1)² window), the border pixel repeated past
/// the edges, as LuxRender's `ApplyBoxFilter` does (so the mean moves where the borders
/// differ from their inside; the map is normalised afterwards).
pub(super) fn box_filter(v: &[f32], w: usize, h: usize, r: usize) -> Vec<f32> {
    let rows = box_pass(v, w, h, r, |x, y| y * w + x);
    box_pass(&rows, h, w, r, |y, x| y * w + x)
}

/// One direction of [`box_filter`]: along lines of `len` pixels, `lines` of them, pixel
/// (i, line) at `index(i, line)`.
fn box_pass(
    v: &[f32],
    len: usize,
    lines: usize,
    r: usize,
    index: impl Fn(usize, usize) -> usize,
) -> Vec<f32> {
    let mut out = vec![0.0; v.len()];
    let scale = 1.0 / (2 * r + 1) as f64;
    for line in 0..lines {
        let at = |i: isize| -> f64 {
            let i = i.clamp(0, len as isize - 1) as usize;
            f64::from(v.get(index(i, line)).copied().unwrap_or(0.0))
        };
        let mut sum: f64 = (-(r as isize)..=r as isize).map(at).sum();
        for i in 0..len {
            if let Some(o) = out.get_mut(index(i, line)) {
                *o = (sum * scale) as f32;
            }
            sum += at(i as isize + r as isize + 1) - at(i as isize - r as isize);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stretch_floors_the_quiet_pixels_and_raises_the_noisy_ones_linearly() {
        // 100 pixels: values 0.00, 0.01, ..., 0.99 -> p5 = 0.05, p95 = 0.94
        let v: Vec<f32> = (0..100).map(|i| i as f32 / 100.0).collect();
        let s = stretch(&v).unwrap();
        let (lo, hi) = (0.025f32, 0.47f32);
        for (x, y) in v.iter().zip(&s) {
            let want = 0.95 * (x - hi).max(0.0) / (hi - lo) + 0.05;
            assert!((y - want).abs() < 1e-5, "{x}: {y} against {want}");
        }
        assert_eq!(s[10], STRETCH_FLOOR);
        assert!(s[99] > 1.0);
        // a flat map cannot be stretched
        assert!(stretch(&[0.3; 50]).is_none());
        assert!(stretch(&[]).is_none());
    }

    #[test]
    fn the_box_filter_averages_its_window_with_the_border_repeated() {
        // 5 x 1, radius 1: the ends see their border value twice.
        let v = [3.0, 0.0, 0.0, 0.0, 6.0];
        let b = box_filter(&v, 5, 1, 1);
        let want = [2.0, 1.0, 0.0, 2.0, 4.0];
        for (g, w) in b.iter().zip(want) {
            assert!((g - w).abs() < 1e-6, "{b:?}");
        }
        // a lone spike spreads over the (2r+1)² window, each pixel 1/(2r+1)² of it
        let (w, h, r) = (15usize, 15usize, 6usize);
        let mut v = vec![0.0f32; w * h];
        v[7 * w + 7] = 169.0;
        let b = box_filter(&v, w, h, r);
        for y in 0..h {
            for x in 0..w {
                let inside = x.abs_diff(7) <= r && y.abs_diff(7) <= r;
                let want = if inside { 1.0 } else { 0.0 };
                assert!((b[y * w + x] - want).abs() < 1e-5, "({x}, {y})");
            }
        }
    }
}
