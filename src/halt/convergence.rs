//! Convergence test for `haltthreshold` (and noise-aware sampling): Yee's perceptual image
//! difference ("A perceptual metric for production testing", 2004), the model LuxRender runs
//! every `convergencestep` spp between the current display image (tonemapped, clamped, gamma
//! applied: `crate::tonemap::tonemap_display`) and the previous one. [`super`] decides when.
//!
//! Per pixel, luminance differences are tested against the threshold-versus-intensity of
//! the local adaptation luminance, raised by spatial frequency sensitivity (Barten's CSF) and
//! visual masking (Daly) measured on Laplacian pyramids; then a CIE L*a*b* colour test runs
//! in photopic regions. A pixel failing either test has not converged.

use crate::tonemap::RgbImage;
use rayon::prelude::*;

const LEVELS: usize = 8;

/// Viewing conditions of the test (LuxRender's values by default).
#[derive(Clone, Debug, PartialEq)]
pub struct YeeParams {
    pub luminance_only: bool,
    /// Horizontal field of view of the observer, degrees.
    pub field_of_view: f32,
    /// Gamma of the display-encoded input.
    pub gamma: f32,
    /// White luminance of the display, cd/m^2.
    pub luminance: f32,
    pub color_factor: f32,
}

impl Default for YeeParams {
    fn default() -> Self {
        YeeParams {
            luminance_only: false,
            field_of_view: 45.0,
            gamma: 2.2,
            luminance: 100.0,
            color_factor: 1.0,
        }
    }
}

/// Threshold versus intensity (Ward Larson 1997), cd/m^2.
pub fn tvi(adaptation: f32) -> f32 {
    let l = adaptation.log10();
    let r = if l < -3.94 {
        -2.86
    } else if l < -1.44 {
        (0.405 * l + 1.6).powf(2.18) - 2.86
    } else if l < -0.0184 {
        l - 0.395
    } else if l < 1.9 {
        (0.249 * l + 0.65).powf(2.7) - 0.72
    } else {
        l - 1.255
    };
    10f32.powf(r)
}

/// Contrast sensitivity (Barten 1989) at `cpd` cycles per degree and luminance `lum`.
pub fn csf(cpd: f32, lum: f32) -> f32 {
    Csf::at(lum).of(cpd)
}

/// Barten's contrast sensitivity at one luminance: its two luminance terms, computed once for
/// the levels of a pixel (the same values [`csf`] gives).
struct Csf {
    a: f32,
    b: f32,
}

impl Csf {
    fn at(lum: f32) -> Csf {
        Csf {
            a: 440.0 * (1.0 + 0.7 / lum).powf(-0.2),
            b: 0.3 * (1.0 + 100.0 / lum).powf(0.15),
        }
    }

    fn of(&self, cpd: f32) -> f32 {
        let (a, b) = (self.a, self.b);
        a * cpd * (-b * cpd).exp() * (1.0 + 0.06 * (b * cpd).exp()).sqrt()
    }
}

/// Visual masking (Daly 1993).
pub fn mask(contrast: f32) -> f32 {
    let a = (392.498 * contrast).powf(0.7);
    let b = (0.0153 * a).powf(4.0);
    (1.0 + b).powf(0.25)
}

fn adobe_to_xyz(c: [f32; 3]) -> [f32; 3] {
    [
        c[0] * 0.576700 + c[1] * 0.185556 + c[2] * 0.188212,
        c[0] * 0.297361 + c[1] * 0.627355 + c[2] * 0.0752847,
        c[0] * 0.0270328 + c[1] * 0.0706879 + c[2] * 0.991248,
    ]
}

/// a* and b* of CIE L*a*b* (white: Adobe RGB white).
fn lab_ab(xyz: [f32; 3]) -> [f32; 2] {
    const EPS: f32 = 216.0 / 24389.0;
    const KAPPA: f32 = 24389.0 / 27.0;
    let w = adobe_to_xyz([1.0; 3]);
    let f = [0, 1, 2].map(|i| {
        let r = xyz[i] / w[i];
        if r > EPS {
            r.cbrt()
        } else {
            (KAPPA * r + 16.0) / 116.0
        }
    });
    [500.0 * (f[0] - f[1]), 200.0 * (f[1] - f[2])]
}

/// Laplacian-style pyramid as in Yee's implementation: every level at full resolution,
/// each the previous one blurred by the 5-tap kernel (mirrored borders).
struct Pyramid {
    levels: Vec<Vec<f32>>,
    width: usize,
}

impl Pyramid {
    fn new(lum: Vec<f32>, width: usize, height: usize) -> Pyramid {
        let mut levels = vec![lum];
        for _ in 1..LEVELS {
            let prev = levels.last().map(Vec::as_slice).unwrap_or(&[]);
            let next = blur(prev, width, height);
            levels.push(next);
        }
        Pyramid { levels, width }
    }

    fn get(&self, x: usize, y: usize, level: usize) -> f32 {
        self.levels[level][y * self.width + x]
    }
}

fn mirror(i: isize, n: usize) -> usize {
    let n = n as isize;
    let i = if i < 0 { -i } else { i };
    let i = if i >= n { 2 * n - i - 1 } else { i };
    i.clamp(0, n - 1) as usize
}

fn blur(src: &[f32], w: usize, h: usize) -> Vec<f32> {
    const K: [f32; 5] = [0.05, 0.25, 0.4, 0.25, 0.05];
    let mut tmp = vec![0.0; src.len()];
    tmp.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        for (x, v) in row.iter_mut().enumerate() {
            *v = (0..5)
                .map(|k| K[k] * src[y * w + mirror(x as isize + k as isize - 2, w)])
                .sum();
        }
    });
    let mut out = vec![0.0; src.len()];
    out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        for (x, v) in row.iter_mut().enumerate() {
            *v = (0..5)
                .map(|k| K[k] * tmp[mirror(y as isize + k as isize - 2, h) * w + x])
                .sum();
        }
    });
    out
}

struct Prepared {
    pyramid: Pyramid,
    ab: Vec<[f32; 2]>,
}

fn prepare(img: &RgbImage, p: &YeeParams) -> Prepared {
    let (xyz, ab): (Vec<[f32; 3]>, Vec<[f32; 2]>) = img
        .rgb
        .par_iter()
        .map(|c| {
            let xyz = adobe_to_xyz(c.map(|v| v.max(0.0).powf(p.gamma)));
            (xyz, lab_ab(xyz))
        })
        .unzip();
    let lum = xyz.iter().map(|c| c[1] * p.luminance).collect();
    Prepared {
        pyramid: Pyramid::new(lum, img.width as usize, img.height as usize),
        ab,
    }
}

/// Yee's "pixels in one degree" of the observer's field of view.
fn one_degree_pixels(p: &YeeParams) -> f32 {
    2.0 * (p.field_of_view * 0.5).to_radians().tan() * 180.0 / std::f32::consts::PI
}

/// The pyramid level whose blur spans about one degree: the adaptation luminance's.
fn adaptation_level(one_degree: f32) -> usize {
    let mut level = 0;
    let mut n = 1.0;
    for i in 0..LEVELS {
        level = i;
        if n > one_degree {
            break;
        }
        n *= 2.0;
    }
    level
}

/// Per pixel of a display image, the threshold versus intensity of its adaptation luminance
/// (cd/m^2): the smallest luminance change visible there, as the test measures it. The
/// noise-aware map divides each pixel's noise by it (`crate::sampler::map`).
pub fn tvi_map(img: &RgbImage, p: &YeeParams) -> Vec<f32> {
    let level = adaptation_level(one_degree_pixels(p));
    let pyramid = prepare(img, p).pyramid;
    let (w, h) = (img.width as usize, img.height as usize);
    (0..w * h)
        .map(|i| tvi(pyramid.get(i % w, i / w, level).max(1e-5)))
        .collect()
}

/// Yee's comparison of two display images of the same size: per pixel, the ratio of the
/// visible-difference measure to its threshold (> 1 fails) and whether it failed.
pub fn yee_compare(a: &RgbImage, b: &RgbImage, p: &YeeParams) -> Vec<(f32, bool)> {
    let (w, h) = (a.width as usize, a.height as usize);
    let (pa, pb) = (prepare(a, p), prepare(b, p));
    let one_degree = one_degree_pixels(p);
    let pixels_per_degree = w as f32 / one_degree;
    let adaptation_level = adaptation_level(one_degree);
    let mut cpd = [0.0f32; LEVELS];
    cpd[0] = 0.5 * pixels_per_degree;
    for i in 1..LEVELS {
        cpd[i] = 0.5 * cpd[i - 1];
    }
    let csf_max = csf(3.248, 100.0);
    let freq: Vec<f32> = (0..LEVELS - 2)
        .map(|i| csf_max / csf(cpd[i], 100.0))
        .collect();
    (0..w * h)
        .into_par_iter()
        .map(|idx| {
            let (x, y) = (idx % w, idx / w);
            let (la, lb) = (&pa.pyramid, &pb.pyramid);
            let mut contrast = [0.0f32; LEVELS - 2];
            let mut sum = 0.0;
            for (i, c) in contrast.iter_mut().enumerate() {
                let n1 = (la.get(x, y, i) - la.get(x, y, i + 1)).abs();
                let n2 = (lb.get(x, y, i) - lb.get(x, y, i + 1)).abs();
                let d = la
                    .get(x, y, i + 2)
                    .abs()
                    .max(lb.get(x, y, i + 2).abs())
                    .max(1e-5);
                *c = n1.max(n2) / d;
                sum += *c;
            }
            let sum = sum.max(1e-5);
            let adapt =
                (0.5 * (la.get(x, y, adaptation_level) + lb.get(x, y, adaptation_level))).max(1e-5);
            let sensitivity = Csf::at(adapt);
            let factor = (0..LEVELS - 2)
                .map(|i| contrast[i] * freq[i] * mask(contrast[i] * sensitivity.of(cpd[i])) / sum)
                .sum::<f32>()
                .clamp(1.0, 10.0);
            let delta = (la.get(x, y, 0) - lb.get(x, y, 0)).abs();
            let threshold = factor * tvi(adapt);
            let ratio = delta / threshold;
            if ratio > 1.0 {
                return (ratio, false);
            }
            if p.luminance_only || adapt < 10.0 {
                return (ratio, true);
            }
            let da = pa.ab[idx][0] - pb.ab[idx][0];
            let db = pa.ab[idx][1] - pb.ab[idx][1];
            let delta_e = (da * da + db * db) * p.color_factor;
            (ratio.max(delta_e / factor), delta_e <= factor)
        })
        .collect()
}

/// The running convergence test: compares each new snapshot with the previous one.
#[derive(Clone, Debug, Default)]
pub struct ConvergenceTest {
    params: YeeParams,
    previous: Option<RgbImage>,
    noise: Vec<f32>,
    failing: Vec<bool>,
}

impl ConvergenceTest {
    pub fn new(params: YeeParams) -> ConvergenceTest {
        ConvergenceTest {
            params,
            ..ConvergenceTest::default()
        }
    }

    /// Takes a new display image (tonemapped, clamped, gamma applied) and returns the
    /// fraction of pixels failing the test against the previous snapshot: 1 for the first
    /// snapshot or after a size change, 0 for an identical image.
    pub fn update(&mut self, img: &RgbImage) -> f64 {
        let n = img.rgb.len();
        let result = match &self.previous {
            Some(prev) if prev.width == img.width && prev.height == img.height && n > 0 => {
                if prev.rgb == img.rgb {
                    vec![(0.0, true); n]
                } else {
                    yee_compare(prev, img, &self.params)
                }
            }
            _ => vec![(f32::INFINITY, false); n],
        };
        self.noise = result.iter().map(|r| r.0).collect();
        self.failing = result.iter().map(|r| !r.1).collect();
        self.previous = Some(img.clone());
        if n == 0 {
            return 1.0;
        }
        self.failing.iter().filter(|&&f| f).count() as f64 / n as f64
    }

    /// Per pixel, the visible difference relative to its threshold in the last update
    /// (above 1: the pixel is still changing visibly); higher means noisier.
    pub fn noise_map(&self) -> &[f32] {
        &self.noise
    }

    /// Per pixel, whether it failed the last test.
    pub fn failing(&self) -> &[bool] {
        &self.failing
    }

    /// Forgets the previous snapshot (after a tonemapping change).
    pub fn reset(&mut self) {
        self.previous = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn img(w: u32, h: u32, f: impl Fn(usize) -> [f32; 3]) -> RgbImage {
        let n = (w * h) as usize;
        RgbImage {
            width: w,
            height: h,
            rgb: (0..n).map(f).collect(),
            alpha: vec![1.0; n],
        }
    }

    #[test]
    fn identical_converges_and_noise_fails() {
        let mut t = ConvergenceTest::new(YeeParams::default());
        let a = img(64, 48, |i| {
            [0.5, 0.4, 0.3].map(|c| c + (i % 7) as f32 * 0.01)
        });
        assert_eq!(t.update(&a), 1.0);
        assert_eq!(t.update(&a), 0.0);
        let noisy = img(64, 48, |i| {
            let v = if (i * 7919) % 3 == 0 { 0.9 } else { 0.1 };
            [v, v, v]
        });
        let f = t.update(&noisy);
        assert!(f > 0.3, "{f}");
        assert_eq!(t.noise_map().len(), 64 * 48);
        // A barely different image passes almost everywhere.
        let mut t = ConvergenceTest::new(YeeParams::default());
        t.update(&a);
        let b = img(64, 48, |i| {
            [0.5, 0.4, 0.3].map(|c| c + (i % 7) as f32 * 0.01 + 0.0005)
        });
        assert!(t.update(&b) < 0.05);
    }

    #[test]
    fn threshold_functions() {
        assert!((tvi(100.0) - 10f32.powf(2.0 - 1.255)).abs() < 1e-3);
        assert!(csf(3.248, 100.0) > csf(30.0, 100.0));
        assert!(mask(0.0) == 1.0);
    }
}
