//! Error metrics of an image against a reference, shared by `luxfarm compare-image` and the
//! accuracy half of `luxfarm bench cornell`: pixel pairs under a whole-row shift, RMSE,
//! relative MSE and the ratio of the means, and the linear RGB of a film to measure.
//!
//! Pixel conventions differ between renderers: LuxRender (and luxfarm) map image row `y` to
//! raster rows `[y, y + 1)`, while LuxCore's cameras use `filmHeight - filmY - 1`, so LuxCore's
//! row `y` shows what LuxRender shows in row `y - 1`. Comparing with a shift of one row puts
//! both under one convention without resampling.

use luxfarm::film::Film;
use luxfarm::spectrum::{xyz_to_rgb, Rgb};
use luxfarm::tonemap::{film_xyz, TonemapParams};

/// Index pairs (a, b) of pixels compared when A is shifted down by `rows` rows (rows without a
/// partner are left out).
pub fn row_pairs(w: usize, h: usize, rows: i64) -> Vec<(usize, usize)> {
    let mut out = Vec::with_capacity(w * h);
    for y in 0..h as i64 {
        let ya = y - rows;
        if ya < 0 || ya >= h as i64 {
            continue;
        }
        for x in 0..w {
            out.push((ya as usize * w + x, y as usize * w + x));
        }
    }
    out
}

/// Error metrics of A against the reference B.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Metrics {
    /// sqrt(mean over pixels and channels of (a − b)²).
    pub rmse: f64,
    /// mean of (a − b)² / (b² + 0.01).
    pub rel_mse: f64,
    /// mean(a) / mean(b).
    pub mean_ratio: f64,
}

/// The metrics of `a` against the reference `b`, pixel by pixel (the shorter length counts).
pub fn metrics(a: &[[f32; 3]], b: &[[f32; 3]]) -> Metrics {
    let (mut se, mut rel, mut sa, mut sb) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (pa, pb) in a.iter().zip(b) {
        for c in 0..3 {
            let (x, y) = (f64::from(pa[c]), f64::from(pb[c]));
            let d = x - y;
            se += d * d;
            rel += d * d / (y * y + 0.01);
            sa += x;
            sb += y;
        }
    }
    let n = (a.len().min(b.len()) * 3).max(1) as f64;
    Metrics {
        rmse: (se / n).sqrt(),
        rel_mse: rel / n,
        mean_ratio: if sb != 0.0 { sa / sb } else { f64::NAN },
    }
}

/// Linear RGB of a film: every light group (at scale 1) and every buffer combined as the
/// tonemapper's first step combines them (per-pixel buffers weight-normalised, per-screen
/// buffers such as light tracing's and Metropolis' scaled by pixels / samples), turned back
/// into the renderer's RGB (the inverse of `spectrum::rgb_to_xyz`), no tonemapping, row by row.
pub fn film_rgb(film: &Film) -> Vec<Rgb> {
    film_xyz(film, &TonemapParams::default())
        .xyz
        .iter()
        .map(|&p| xyz_to_rgb(p))
        .collect()
}

/// Writes a linear RGB image (rows top to bottom) as an OpenEXR file, for a look.
pub fn write_rgb_exr(
    path: &std::path::Path,
    w: u32,
    h: u32,
    rgb: &[[f32; 3]],
) -> anyhow::Result<()> {
    use luxfarm::imageio::exr::{write_exr, ExrCompression, ExrImage};
    let gray: Vec<f32> = rgb.iter().map(|p| (p[0] + p[1] + p[2]) / 3.0).collect();
    let img = ExrImage {
        width: w,
        height: h,
        rgb,
        gray: &gray,
        alpha: &[],
        z: None,
    };
    write_exr(
        path,
        &img,
        luxfarm::imageio::ChannelSet::Rgb,
        false,
        ExrCompression::Zip,
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_images_have_zero_error() {
        let a = vec![[0.5, 0.25, 1.0]; 4];
        let m = metrics(&a, &a);
        assert_eq!(m.rmse, 0.0);
        assert_eq!(m.rel_mse, 0.0);
        assert_eq!(m.mean_ratio, 1.0);
    }

    #[test]
    fn row_shift_pairs_a_row_above_with_b() {
        // 2x3 image: shifting by one row pairs A's row 0 with B's row 1, A's 1 with B's 2.
        assert_eq!(row_pairs(2, 3, 1), vec![(0, 2), (1, 3), (2, 4), (3, 5)]);
        assert_eq!(row_pairs(2, 3, -1), vec![(2, 0), (3, 1), (4, 2), (5, 3)]);
        assert_eq!(row_pairs(2, 3, 0).len(), 6);
        assert!(row_pairs(2, 3, 5).is_empty());
    }

    #[test]
    fn known_difference() {
        let a = vec![[1.0, 1.0, 1.0]; 2];
        let b = vec![[0.5, 0.5, 0.5]; 2];
        let m = metrics(&a, &b);
        assert!((m.rmse - 0.5).abs() < 1e-12);
        assert!((m.mean_ratio - 2.0).abs() < 1e-12);
    }

    #[test]
    fn film_rgb_adds_per_screen_buffers_and_every_group() {
        use luxfarm::film::BufferType;
        let mut f = Film::with_buffers(
            2,
            1,
            vec!["a".into(), "b".into()],
            vec![BufferType::PerPixel, BufferType::PerScreen],
        )
        .unwrap();
        let xyz = luxfarm::spectrum::rgb_to_xyz(Rgb::new(0.5, 0.5, 0.5));
        // Eye samples: 0.5 on pixel 1 in group 0; light splats: 0.8 summed on pixel 0 in
        // group 1's per-screen buffer over 4 samples on 2 pixels (0.8 * 2 / 4 = 0.4).
        f.add_splat(0, 1, 0, xyz, 1.0, 1.0);
        f.add_buffer_splat(1, 1, 0, 0, xyz.map(|c| c * 1.6), 1.0, 1.0);
        f.add_sample_count(4.0);
        let px = film_rgb(&f);
        for (got, want) in px[0].to_array().iter().zip([0.4; 3]) {
            assert!((got - want).abs() < 1e-4, "{got} vs {want}");
        }
        for (got, want) in px[1].to_array().iter().zip([0.5; 3]) {
            assert!((got - want).abs() < 1e-4, "{got} vs {want}");
        }
    }

    #[test]
    fn film_rgb_normalises_by_the_weight() {
        let mut f = Film::new(2, 1, vec![]);
        let xyz = luxfarm::spectrum::rgb_to_xyz(Rgb::new(0.5, 0.25, 0.125));
        f.add_splat(0, 1, 0, xyz, 1.0, 2.0);
        f.add_splat(0, 1, 0, xyz, 1.0, 2.0);
        let px = film_rgb(&f);
        assert_eq!(px.len(), 2);
        assert_eq!(px[0].to_array(), [0.0; 3]);
        for (got, want) in px[1].to_array().iter().zip([0.5, 0.25, 0.125]) {
            assert!((got - want).abs() < 1e-5, "{got} vs {want}");
        }
    }
}
