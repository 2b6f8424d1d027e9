//! Film comparison as LuxRender's regression tool (`luxcomp`): per buffer of the first light
//! group, MSE and RMS over the normalised X, Y, Z of every pixel, and the shares of small
//! (<= 10%), medium (<= 50%) and big relative differences. The result is the largest value
//! over the buffers.
//!
//! [`block_bias`] looks past per-pixel noise: it compares the luminance means of square pixel
//! blocks, and reports the overall scale of the test against the reference separately from
//! the block-to-block error that remains once that scale is removed. A reference made by
//! another renderer (or an older LuxRender, with spectral noise) can then be judged on bias
//! rather than on its own noise.

use super::{BufferType, Film, FilmError, PIXEL_VALUES};

/// The statistics of one comparison.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Comparison {
    pub mse: f64,
    pub rms: f64,
    /// Components (3 per pixel) with relative difference <= 0.1, <= 0.5, > 0.5.
    pub small: u64,
    pub medium: u64,
    pub big: u64,
    pub components: u64,
    pub min_diff: f64,
    pub max_diff: f64,
    pub avg_reference: f64,
    pub avg_test: f64,
}

impl Comparison {
    pub fn share(&self, n: u64) -> f64 {
        if self.components == 0 {
            0.0
        } else {
            n as f64 / self.components as f64
        }
    }
}

/// The normalised XYZ of a pixel as the buffer type defines it.
fn normalised(p: &[f64], ty: BufferType, screen: f64) -> [f64; 3] {
    let w = p[4];
    let s = match ty {
        BufferType::PerPixel if w != 0.0 => 1.0 / w,
        BufferType::PerPixel => 0.0,
        BufferType::PerScreen if w > 0.0 => screen,
        BufferType::PerScreenScaled if w > 0.0 => 1.0,
        BufferType::PerScreen | BufferType::PerScreenScaled => 0.0,
        BufferType::Raw => 1.0,
    };
    [p[0] * s, p[1] * s, p[2] * s]
}

/// Compares buffer `b` of group 0 of two films of the same resolution.
pub fn compare_buffer(reference: &Film, test: &Film, b: usize) -> Result<Comparison, FilmError> {
    if reference.width() != test.width() || reference.height() != test.height() {
        return Err(FilmError::Mismatch(format!(
            "reference is {}x{}, test is {}x{}",
            reference.width(),
            reference.height(),
            test.width(),
            test.height()
        )));
    }
    let (Some(rb), Some(tb)) = (reference.buffer(0, b), test.buffer(0, b)) else {
        return Err(FilmError::Mismatch(format!("buffer {b} missing")));
    };
    let ty_r = reference.buffer_types()[b];
    let ty_t = test.buffer_types().get(b).copied().unwrap_or(ty_r);
    let n = reference.pixel_count() as f64;
    let screen = |f: &Film| n / f.sample_count(0).max(f64::MIN_POSITIVE);
    let (sr, st) = (screen(reference), screen(test));
    let mut c = Comparison {
        min_diff: f64::MAX,
        max_diff: f64::MIN,
        ..Comparison::default()
    };
    let (mut sum_r, mut sum_t, mut se) = (0.0, 0.0, 0.0);
    for (pr, pt) in rb
        .chunks_exact(PIXEL_VALUES)
        .zip(tb.chunks_exact(PIXEL_VALUES))
    {
        let (r, t) = (normalised(pr, ty_r, sr), normalised(pt, ty_t, st));
        for i in 0..3 {
            sum_r += r[i];
            sum_t += t[i];
            se += (r[i] - t[i]) * (r[i] - t[i]);
            let d = if r[i] == 0.0 {
                (r[i] - t[i]).abs()
            } else {
                ((r[i] - t[i]) / r[i]).abs()
            };
            c.min_diff = c.min_diff.min(d);
            c.max_diff = c.max_diff.max(d);
            match d {
                d if d <= 0.1 => c.small += 1,
                d if d <= 0.5 => c.medium += 1,
                _ => c.big += 1,
            }
        }
    }
    c.components = 3 * reference.pixel_count() as u64;
    c.mse = se / c.components as f64;
    c.rms = c.mse.sqrt();
    c.avg_reference = sum_r / n;
    c.avg_test = sum_t / n;
    Ok(c)
}

/// Compares every buffer and returns the comparison with the largest RMS.
pub fn compare(reference: &Film, test: &Film) -> Result<Comparison, FilmError> {
    let mut worst: Option<Comparison> = None;
    for b in 0..reference.buffer_types().len() {
        let c = compare_buffer(reference, test, b)?;
        if worst.as_ref().is_none_or(|w| c.rms > w.rms) {
            worst = Some(c);
        }
    }
    worst.ok_or_else(|| FilmError::Mismatch("no buffers".into()))
}

/// Block-level agreement of two films ([`block_bias`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BlockBias {
    /// Block edge in pixels.
    pub block: u32,
    /// Blocks compared (blocks whose reference mean is zero are left out).
    pub blocks: usize,
    /// Total luminance of the test over that of the reference.
    pub scale: f64,
    /// RMS over blocks of `test / reference - 1`.
    pub rms_rel: f64,
    /// RMS over blocks of `test / (scale * reference) - 1`: the error the global scale
    /// does not explain.
    pub rms_rel_unscaled: f64,
    /// Largest `|test / reference - 1|` of a block.
    pub max_rel: f64,
}

/// Luminance (normalised Y summed over the buffers of group 0) of every pixel.
fn luminance(f: &Film) -> Vec<f64> {
    let n = f.pixel_count();
    let screen = n as f64 / f.sample_count(0).max(f64::MIN_POSITIVE);
    let mut y = vec![0.0; n];
    for (b, &ty) in f.buffer_types().iter().enumerate() {
        let Some(buf) = f.buffer(0, b) else { continue };
        for (out, p) in y.iter_mut().zip(buf.chunks_exact(PIXEL_VALUES)) {
            *out += normalised(p, ty, screen)[1];
        }
    }
    y
}

/// Luminance means of `block`×`block` blocks (partial blocks at the right and bottom edges
/// are left out).
fn block_means(f: &Film, block: u32) -> Vec<f64> {
    let y = luminance(f);
    let (w, block) = (f.width(), block.max(1));
    let (bw, bh) = (w / block, f.height() / block);
    let mut out = vec![0.0; bw as usize * bh as usize];
    let area = f64::from(block) * f64::from(block);
    for py in 0..bh * block {
        for px in 0..bw * block {
            let i = ((py / block) * bw + px / block) as usize;
            out[i] += y[(py * w + px) as usize] / area;
        }
    }
    out
}

/// Compares `block`×`block` luminance block means of two films of the same resolution.
pub fn block_bias(reference: &Film, test: &Film, block: u32) -> Result<BlockBias, FilmError> {
    if reference.width() != test.width() || reference.height() != test.height() {
        return Err(FilmError::Mismatch(format!(
            "reference is {}x{}, test is {}x{}",
            reference.width(),
            reference.height(),
            test.width(),
            test.height()
        )));
    }
    let (r, t) = (block_means(reference, block), block_means(test, block));
    let pairs: Vec<(f64, f64)> = r.into_iter().zip(t).filter(|(r, _)| *r > 0.0).collect();
    let (sr, st) = pairs
        .iter()
        .fold((0.0, 0.0), |(a, b), (r, t)| (a + r, b + t));
    let scale = if sr > 0.0 { st / sr } else { 0.0 };
    let rms = |s: f64| {
        let se: f64 = pairs.iter().map(|(r, t)| (t / (s * r) - 1.0).powi(2)).sum();
        (se / pairs.len().max(1) as f64).sqrt()
    };
    Ok(BlockBias {
        block,
        blocks: pairs.len(),
        scale,
        rms_rel: rms(1.0),
        rms_rel_unscaled: if scale > 0.0 { rms(scale) } else { f64::NAN },
        max_rel: pairs
            .iter()
            .map(|(r, t)| (t / r - 1.0).abs())
            .fold(0.0, f64::max),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_films_compare_to_zero() {
        let mut a = Film::new(4, 4, vec![]);
        a.add_splat(0, 1, 1, [1.0, 2.0, 3.0], 1.0, 0.5);
        let c = compare(&a, &a).unwrap();
        assert_eq!(c.mse, 0.0);
        assert_eq!(c.rms, 0.0);
        assert_eq!(c.small, 48);
    }

    #[test]
    fn differences_are_measured() {
        let mut a = Film::new(1, 1, vec![]);
        let mut b = Film::new(1, 1, vec![]);
        a.add_splat(0, 0, 0, [1.0, 1.0, 1.0], 1.0, 1.0);
        b.add_splat(0, 0, 0, [1.0, 1.05, 2.0], 1.0, 2.0);
        let c = compare(&a, &b).unwrap();
        assert!((c.mse - (0.0025 + 1.0) / 3.0).abs() < 1e-6);
        assert_eq!((c.small, c.medium, c.big), (2, 0, 1));
        assert!(compare(&a, &Film::new(2, 1, vec![])).is_err());
    }

    #[test]
    fn block_bias_separates_scale_from_structure() {
        let mut a = Film::new(4, 4, vec![]);
        let mut b = Film::new(4, 4, vec![]);
        for y in 0..4 {
            for x in 0..4 {
                a.add_splat(0, x, y, [1.0, 1.0, 1.0], 1.0, 1.0);
                // Twice as bright everywhere, and the top-left 2x2 block 3x instead of 2x.
                let k = if x < 2 && y < 2 { 3.0 } else { 2.0 };
                b.add_splat(0, x, y, [k, k, k], 1.0, 1.0);
            }
        }
        let c = block_bias(&a, &b, 2).unwrap();
        assert_eq!(c.blocks, 4);
        // Block ratios 3, 2, 2, 2: scale 9/4.
        assert!((c.scale - 2.25).abs() < 1e-12);
        let want = ((4.0 + 3.0) / 4.0f64).sqrt();
        assert!((c.rms_rel - want).abs() < 1e-12, "{}", c.rms_rel);
        let u = [3.0 / 2.25 - 1.0, 2.0 / 2.25 - 1.0];
        let want_u = ((u[0] * u[0] + 3.0 * u[1] * u[1]) / 4.0f64).sqrt();
        assert!((c.rms_rel_unscaled - want_u).abs() < 1e-12);
        assert!((c.max_rel - 2.0).abs() < 1e-12);
        assert!(block_bias(&a, &Film::new(2, 2, vec![]), 2).is_err());
    }
}
