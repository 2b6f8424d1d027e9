//! The efficiency benchmark's reference: two independent halves, rendered by LuxCore's
//! BIDIRCPU once and kept on disk. Their mean is the reference; (A − B)² / 4 estimates the
//! mean's own variance per value, so a contestant's error is measured without the reference's
//! noise: E[(X − R)²] = MSE(X) + Var(R) for independent X and R.

use super::luxcore::LuxCore;
use super::{Contestant, Renderer, Variant};
use crate::image_metrics::row_pairs;
use anyhow::bail;
use luxfarm::texture::image_io::load_rgb as load_image;
use std::path::Path;

pub struct Reference {
    w: usize,
    h: usize,
    mean: Vec<[f64; 3]>,
    /// Estimated variance of `mean`, per pixel and channel.
    var: Vec<[f64; 3]>,
    /// The halves' file names.
    files: String,
}

/// A contestant's error.
pub struct Measure {
    /// RMSE with the reference's own noise taken out.
    pub rmse: f64,
    /// RMSE against the reference as it is.
    pub raw_rmse: f64,
    /// Mean of the image over the reference's mean, over the pixels measured.
    pub mean_ratio: f64,
}

fn luminance(c: [f64; 3]) -> f64 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

impl Reference {
    /// Loads the two halves of `variant`'s reference from `dir`, rendering the missing ones
    /// with LuxCore's BIDIRCPU for `seconds` each.
    pub fn load_or_render(
        lc: &LuxCore,
        variant: Variant,
        dir: &Path,
        seconds: f64,
    ) -> anyhow::Result<Reference> {
        let bidir = Contestant {
            renderer: Renderer::LuxCore,
            integrator: "BIDIRCPU".into(),
            sampler: "RANDOM".into(),
            adaptive: false,
        };
        let mut halves = Vec::new();
        for (half, seed) in [("a", 11), ("b", 12)] {
            let path = dir.join(format!(
                "{}-{}-d{}-{half}.exr",
                variant.name(),
                lc.res,
                lc.depth
            ));
            if !path.exists() {
                if !lc.available() {
                    bail!(
                        "{} is missing and pyluxcore is not installed to render it",
                        path.display()
                    );
                }
                println!(
                    "rendering {} with LuxCore BIDIRCPU for {seconds} s",
                    path.display()
                );
                let r = lc.render(variant, &bidir, seconds, seed, &path)?;
                println!("  {} spp", r.spp);
            }
            let (w, h, px) = load_image(&path).map_err(anyhow::Error::msg)?;
            halves.push((w, h, px));
        }
        let (a, b) = (&halves[0], &halves[1]);
        if (a.0, a.1) != (b.0, b.1) || a.0 != lc.res as usize {
            bail!("the reference halves in {} differ in size", dir.display());
        }
        let mut mean = Vec::with_capacity(a.2.len());
        let mut var = Vec::with_capacity(a.2.len());
        for (p, q) in a.2.iter().zip(&b.2) {
            let (p, q) = (p.to_array(), q.to_array());
            mean.push([0, 1, 2].map(|c| 0.5 * (f64::from(p[c]) + f64::from(q[c]))));
            var.push([0, 1, 2].map(|c| {
                let d = f64::from(p[c]) - f64::from(q[c]);
                d * d / 4.0
            }));
        }
        Ok(Reference {
            w: a.0,
            h: a.1,
            mean,
            var,
            files: format!("{}-{}-d{}-{{a,b}}.exr", variant.name(), lc.res, lc.depth),
        })
    }

    pub fn describe(&self) -> &str {
        &self.files
    }

    /// Which reference pixels are measured: those at or below `max_luminance`.
    pub fn mask(&self, max_luminance: f64) -> Vec<bool> {
        self.mean
            .iter()
            .map(|&c| luminance(c) <= max_luminance)
            .collect()
    }

    /// The reference's own estimated RMSE over the measured pixels.
    pub fn own_rmse(&self, mask: &[bool]) -> f64 {
        let (mut s, mut n) = (0.0, 0usize);
        for (v, _) in self.var.iter().zip(mask).filter(|(_, m)| **m) {
            s += v.iter().sum::<f64>();
            n += 3;
        }
        (s / n.max(1) as f64).sqrt()
    }

    /// The error of `img` (shifted down by `shift` rows) over the measured pixels.
    pub fn measure(&self, img: &[[f32; 3]], shift: i64, mask: &[bool]) -> Measure {
        let (mut se, mut var, mut sa, mut sb, mut n) = (0.0, 0.0, 0.0, 0.0, 0usize);
        for (i, j) in row_pairs(self.w, self.h, shift) {
            let (Some(p), Some(q), Some(v), Some(true)) =
                (img.get(i), self.mean.get(j), self.var.get(j), mask.get(j))
            else {
                continue;
            };
            for c in 0..3 {
                let d = f64::from(p[c]) - q[c];
                se += d * d;
                var += v[c];
            }
            sa += luminance(p.map(f64::from));
            sb += luminance(*q);
            n += 3;
        }
        let n = n.max(1) as f64;
        Measure {
            rmse: ((se - var).max(0.0) / n).sqrt(),
            raw_rmse: (se / n).sqrt(),
            mean_ratio: sa / sb,
        }
    }
}
