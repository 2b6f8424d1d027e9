//! The image filters a noise-aware sampling map is built with ([`super::map`]'s
//! `SamplingMap::from_noise`): a square-window maximum that lets a pixel's neighbourhood
//! speak for it, and the 3x3 box blur that smooths the densities across a filter's support.

/// Each pixel raised to the largest value within `r` pixels of it (a square window; a
/// separable maximum, rows then columns).
pub(super) fn dilate(v: &[f32], w: usize, h: usize, r: usize) -> Vec<f32> {
    let window_max = |get: &dyn Fn(usize) -> f32, i: usize, n: usize| -> f32 {
        (i.saturating_sub(r)..(i + r + 1).min(n))
            .map(get)
            .fold(0.0, f32::max)
    };
    let mut rows = vec![0.0; v.len()];
    for y in 0..h {
        for x in 0..w {
            let get = |xx: usize| v.get(y * w + xx).copied().unwrap_or(0.0);
            if let Some(o) = rows.get_mut(y * w + x) {
                *o = window_max(&get, x, w);
            }
        }
    }
    let mut out = vec![0.0; v.len()];
    for y in 0..h {
        for x in 0..w {
            let get = |yy: usize| rows.get(yy * w + x).copied().unwrap_or(0.0);
            if let Some(o) = out.get_mut(y * w + x) {
                *o = window_max(&get, y, h);
            }
        }
    }
    out
}

/// A 3x3 box blur (borders average the pixels inside).
pub(super) fn blur3(v: &[f32], w: usize, h: usize) -> Vec<f32> {
    let mut out = vec![0.0; v.len()];
    for y in 0..h {
        for x in 0..w {
            let (mut s, mut n) = (0.0f64, 0u32);
            for yy in y.saturating_sub(1)..(y + 2).min(h) {
                for xx in x.saturating_sub(1)..(x + 2).min(w) {
                    s += f64::from(v.get(yy * w + xx).copied().unwrap_or(0.0));
                    n += 1;
                }
            }
            if let Some(o) = out.get_mut(y * w + x) {
                *o = (s / f64::from(n.max(1))) as f32;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dilation_raises_each_pixel_to_its_windows_maximum() {
        // One noisy pixel at (5, 3) on a 12 x 7 map; radius 2 spreads it to a 5 x 5 square,
        // clipped at the border.
        let (w, h) = (12usize, 7usize);
        let mut v = vec![0.0f32; w * h];
        v[3 * w + 5] = 3.0;
        v[0] = 1.0;
        let d = dilate(&v, w, h, 2);
        for y in 0..h {
            for x in 0..w {
                let want = if x.abs_diff(5) <= 2 && y.abs_diff(3) <= 2 {
                    3.0
                } else if x <= 2 && y <= 2 {
                    1.0
                } else {
                    0.0
                };
                assert_eq!(d[y * w + x], want, "({x}, {y})");
            }
        }
        assert_eq!(dilate(&v, w, h, 0), v);
    }

    #[test]
    fn the_blur_averages_the_pixels_inside_the_border() {
        let v = [0.0, 9.0, 0.0, 0.0];
        // 2 x 2: every pixel's window holds all four.
        assert_eq!(blur3(&v, 2, 2), vec![2.25; 4]);
        // 4 x 1: the ends average two pixels, the middle three.
        assert_eq!(blur3(&v, 4, 1), vec![4.5, 3.0, 3.0, 0.0]);
    }
}
