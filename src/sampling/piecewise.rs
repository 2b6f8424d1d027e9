//! Piecewise-constant 1D and 2D densities on [0, 1) and [0, 1)² for importance sampling
//! (f32): the light-selection distribution (power strategy) and the environment and sky maps
//! (lat-long texels weighted by luminance and sin(theta)).

/// A piecewise-constant density on [0, 1) with `func.len()` equal buckets.
#[derive(Clone, Debug)]
pub struct PiecewiseConstant1D {
    func: Vec<f32>,
    /// Cumulative distribution, `func.len() + 1` entries from 0 to 1.
    cdf: Vec<f32>,
    integral: f32,
}

impl PiecewiseConstant1D {
    /// Builds from non-negative weights (negative or non-finite entries count as 0). When every
    /// weight is zero the distribution is uniform, and `integral()` is 0.
    pub fn new(weights: &[f32]) -> PiecewiseConstant1D {
        let n = weights.len().max(1);
        let func: Vec<f32> = (0..n)
            .map(|i| {
                weights
                    .get(i)
                    .copied()
                    .filter(|w| w.is_finite() && *w > 0.0)
                    .unwrap_or(0.0)
            })
            .collect();
        let mut cdf = Vec::with_capacity(n + 1);
        cdf.push(0.0f32);
        let mut acc = 0.0f64;
        for f in &func {
            acc += f64::from(*f) / n as f64;
            cdf.push(acc as f32);
        }
        let integral = acc as f32;
        if integral > 0.0 {
            for c in cdf.iter_mut() {
                *c /= integral;
            }
        } else {
            for (i, c) in cdf.iter_mut().enumerate() {
                *c = i as f32 / n as f32;
            }
        }
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        PiecewiseConstant1D {
            func,
            cdf,
            integral,
        }
    }

    pub fn count(&self) -> usize {
        self.func.len()
    }

    pub fn integral(&self) -> f32 {
        self.integral
    }

    /// Probability of picking bucket `i` with [`Self::sample_discrete`].
    pub fn discrete_pdf(&self, i: usize) -> f32 {
        match (self.cdf.get(i), self.cdf.get(i + 1)) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        }
    }

    /// The bucket whose cdf interval holds `u`, and the remapped `u` within it.
    fn find(&self, u: f32) -> (usize, f32) {
        let n = self.func.len();
        // Largest i with cdf[i] <= u, among buckets of non-zero width.
        let i = self
            .cdf
            .partition_point(|&c| c <= u)
            .saturating_sub(1)
            .min(n - 1);
        let (a, b) = (self.cdf[i], self.cdf[i + 1]);
        let du = if b > a {
            ((u - a) / (b - a)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (i, du)
    }

    /// Picks a bucket: (index, probability, `u` remapped to [0,1) inside the bucket).
    pub fn sample_discrete(&self, u: f32) -> (usize, f32, f32) {
        let (i, du) = self.find(u);
        (i, self.discrete_pdf(i), du)
    }

    /// Samples a continuous value in [0,1): (x, density at x, bucket).
    pub fn sample_continuous(&self, u: f32) -> (f32, f32, usize) {
        let (i, du) = self.find(u);
        let n = self.func.len() as f32;
        let x = ((i as f32 + du) / n).min(1.0 - f32::EPSILON);
        (x, self.pdf_bucket(i), i)
    }

    /// Density (with respect to [0,1)) of bucket `i`.
    pub fn pdf_bucket(&self, i: usize) -> f32 {
        if self.integral > 0.0 {
            self.func.get(i).copied().unwrap_or(0.0) / self.integral
        } else {
            1.0
        }
    }

    /// Density at `x` in [0,1).
    pub fn pdf(&self, x: f32) -> f32 {
        let n = self.func.len();
        let i = ((x * n as f32) as usize).min(n - 1);
        self.pdf_bucket(i)
    }
}

/// A piecewise-constant density on [0,1)² given row by row (`nv` rows of `nu` values):
/// a marginal over rows and a conditional per row.
#[derive(Clone, Debug)]
pub struct PiecewiseConstant2D {
    rows: Vec<PiecewiseConstant1D>,
    marginal: PiecewiseConstant1D,
}

impl PiecewiseConstant2D {
    pub fn new(values: &[f32], nu: usize, nv: usize) -> PiecewiseConstant2D {
        let nu = nu.max(1);
        let rows: Vec<PiecewiseConstant1D> = (0..nv.max(1))
            .map(|v| {
                let start = (v * nu).min(values.len());
                let end = ((v + 1) * nu).min(values.len());
                PiecewiseConstant1D::new(&values[start..end])
            })
            .collect();
        let marginal =
            PiecewiseConstant1D::new(&rows.iter().map(|r| r.integral()).collect::<Vec<_>>());
        PiecewiseConstant2D { rows, marginal }
    }

    /// The values' mean over the unit square (0 when every value is zero).
    pub fn integral(&self) -> f32 {
        self.marginal.integral()
    }

    /// Samples (u, v) in [0,1)² with its density.
    pub fn sample(&self, u0: f32, u1: f32) -> ([f32; 2], f32) {
        let (v, pdf_v, row) = self.marginal.sample_continuous(u1);
        let (u, pdf_u, _) = self.rows[row].sample_continuous(u0);
        ([u, v], pdf_u * pdf_v)
    }

    /// Density at (u, v).
    pub fn pdf(&self, u: f32, v: f32) -> f32 {
        let nv = self.rows.len();
        let row = ((v * nv as f32) as usize).min(nv - 1);
        self.marginal.pdf_bucket(row) * self.rows[row].pdf(u)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn discrete_probabilities_follow_weights() {
        let d = PiecewiseConstant1D::new(&[1.0, 0.0, 3.0]);
        assert!((d.discrete_pdf(0) - 0.25).abs() < 1e-6);
        assert_eq!(d.discrete_pdf(1), 0.0);
        assert!((d.discrete_pdf(2) - 0.75).abs() < 1e-6);
        assert_eq!(d.sample_discrete(0.1).0, 0);
        assert_eq!(d.sample_discrete(0.3).0, 2);
        assert_eq!(d.sample_discrete(0.999_999).0, 2);
    }

    #[test]
    fn all_zero_is_uniform() {
        let d = PiecewiseConstant1D::new(&[0.0, 0.0]);
        assert_eq!(d.integral(), 0.0);
        assert!((d.discrete_pdf(1) - 0.5).abs() < 1e-6);
    }

    #[test]
    fn continuous_pdf_matches_sampling_density() {
        let d = PiecewiseConstant2D::new(&[1.0, 2.0, 3.0, 4.0, 0.0, 6.0], 3, 2);
        // Monte Carlo check: E[1/pdf] over the support equals its area (1).
        let n = 200;
        let mut sum = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let (p, pdf) = d.sample((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                assert!((d.pdf(p[0], p[1]) - pdf).abs() < 1e-4 * pdf.max(1.0));
                sum += 1.0 / f64::from(pdf);
            }
        }
        let support = 5.0 / 6.0;
        assert!(
            (sum / (n * n) as f64 - support).abs() < 1e-2,
            "{}",
            sum / (n * n) as f64
        );
    }
}
