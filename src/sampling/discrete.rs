//! A discrete distribution: picks an item proportionally to non-negative weights (triangles
//! by area, quadric bands by area) through an f64 cumulative table.

/// Discrete distribution over `weights.len()` items.
#[derive(Clone, Debug, PartialEq)]
pub struct DiscreteDistribution {
    /// cdf[i] = sum of weights[..i] / total; cdf.len() == n + 1, last entry 1.
    cdf: Vec<f64>,
    weights: Vec<f64>,
    total: f64,
}

impl DiscreteDistribution {
    /// `None` when there is no item or the weights do not sum to a positive finite value.
    pub fn new(weights: &[f64]) -> Option<DiscreteDistribution> {
        let mut cdf = Vec::with_capacity(weights.len() + 1);
        let mut sum = 0.0;
        cdf.push(0.0);
        for &w in weights {
            sum += if w.is_finite() && w > 0.0 { w } else { 0.0 };
            cdf.push(sum);
        }
        if !(sum > 0.0 && sum.is_finite()) {
            return None;
        }
        for c in &mut cdf {
            *c /= sum;
        }
        let weights = weights
            .iter()
            .map(|&w| if w.is_finite() && w > 0.0 { w } else { 0.0 })
            .collect();
        Some(DiscreteDistribution {
            cdf,
            weights,
            total: sum,
        })
    }

    pub fn total(&self) -> f64 {
        self.total
    }

    pub fn len(&self) -> usize {
        self.weights.len()
    }

    pub fn is_empty(&self) -> bool {
        self.weights.is_empty()
    }

    /// Probability of item `i`.
    pub fn pmf(&self, i: usize) -> f64 {
        self.weights.get(i).map_or(0.0, |w| w / self.total)
    }

    /// The item [`Self::sample`] picks for `u`, without the remapped `u` (and its division).
    pub fn pick(&self, u: f32) -> usize {
        let u = (u as f64).clamp(0.0, 1.0);
        // The first index with cdf[i+1] > u: the number of entries of cdf[1..] that are <= u
        // (the table is sorted). Short tables (a quad light's two triangles) are counted
        // without branches, as a binary search there mispredicts every other time.
        let mut i = if self.cdf.len() <= 17 {
            self.cdf[1..].iter().map(|&c| usize::from(c <= u)).sum()
        } else {
            self.cdf.partition_point(|&c| c <= u).saturating_sub(1)
        };
        i = i.min(self.weights.len() - 1);
        while self.weights[i] == 0.0 && i > 0 {
            i -= 1;
        }
        while self.weights[i] == 0.0 && i + 1 < self.weights.len() {
            i += 1;
        }
        i
    }

    /// Picks an item for `u` in [0, 1); returns it and `u` remapped to [0, 1) inside it.
    /// Zero-weight items are never picked.
    pub fn sample(&self, u: f32) -> (usize, f32) {
        let i = self.pick(u);
        let u = (u as f64).clamp(0.0, 1.0);
        let lo = self.cdf[i];
        let width = self.cdf[i + 1] - lo;
        let rem = if width > 0.0 {
            ((u - lo) / width).clamp(0.0, 1.0 - f64::EPSILON)
        } else {
            0.0
        };
        (i, (rem as f32).min(1.0 - f32::EPSILON / 2.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_and_long_tables_pick_alike() {
        // Up to 16 items are counted, longer tables binary-searched: both must agree with
        // the definition (the first item whose cdf end exceeds u, zero weights skipped).
        for n in 1..=40usize {
            let w: Vec<f64> = (0..n).map(|i| [1.0, 0.0, 2.5, 0.5][i % 4]).collect();
            let Some(d) = DiscreteDistribution::new(&w) else {
                continue;
            };
            for k in 0..=200 {
                let u = k as f32 / 200.0;
                let i = d.pick(u);
                assert!(w[i] > 0.0, "n {n} u {u}: zero-weight item {i}");
                let uf = f64::from(u);
                let expect = (0..n)
                    .find(|&j| w[j] > 0.0 && d.cdf[j + 1] > uf)
                    .unwrap_or_else(|| (0..n).rev().find(|&j| w[j] > 0.0).unwrap());
                assert_eq!(i, expect, "n {n} u {u}");
            }
        }
    }

    #[test]
    fn picks_by_weight_and_skips_zero_weights() {
        let d = DiscreteDistribution::new(&[1.0, 0.0, 3.0]).unwrap();
        assert_eq!(d.sample(0.1).0, 0);
        assert_eq!(d.sample(0.25).0, 2);
        assert_eq!(d.sample(0.999).0, 2);
        assert!((d.pmf(2) - 0.75).abs() < 1e-12);
        let (_, r) = d.sample(0.625);
        assert!((r - 0.5).abs() < 1e-6);
        assert!(DiscreteDistribution::new(&[0.0]).is_none());
        assert!(DiscreteDistribution::new(&[]).is_none());
    }
}
