//! Light selection strategies for direct lighting, as LuxRender 1.x names and defines them
//! (`lightstrategy`, also read from the older `strategy`; the bidirectional integrator's
//! `lightpathstrategy` for its light paths):
//!
//! | name | draws per estimate | light i chosen with weight |
//! |---|---|---|
//! | `one` | 1 | 1 (uniform) |
//! | `all` | every light, each with its `nsamples` shadow rays | — |
//! | `auto` | `all` up to 5 lights, `one` beyond | |
//! | `importance` | 1 | its `importance` |
//! | `powerimp` | 1 | `importance` × power |
//! | `allpowerimp` | as many as there are lights, draw k at (k + u) / n | `importance` × power |
//! | `autopowerimp` | `allpowerimp` up to 5 lights, `powerimp` beyond | |
//! | `logpowerimp` | 1 | ln(1 + `importance` × power) |
//!
//! `importance` is every light's parameter (default 1, negative counts as 0). A light with
//! weight 0 is never drawn (nor is any light when every weight is 0), so a point-like one
//! then lights nothing, as in LuxRender. An area light of weight 0 is still reached by the
//! BSDF-sampled rays, which luxfarm traces from every surface (LuxRender only from surfaces
//! with a non-diffuse component, so there a diffuse surface loses it). LuxRender's
//! `logpowerimp` weighs by
//! ln(importance × power), which is negative or undefined below 1 W; ln(1 + x) keeps its
//! ordering and stays a weight. Unknown names fall back to `auto` with a warning by the
//! caller.

use super::Light;
use crate::sampling::PiecewiseConstant1D;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightStrategy {
    One,
    All,
    Auto,
    Importance,
    PowerImp,
    AllPowerImp,
    AutoPowerImp,
    LogPowerImp,
}

impl LightStrategy {
    pub fn parse(name: &str) -> Option<LightStrategy> {
        Some(match name {
            "one" => LightStrategy::One,
            "all" => LightStrategy::All,
            "auto" => LightStrategy::Auto,
            "importance" => LightStrategy::Importance,
            "powerimp" => LightStrategy::PowerImp,
            "allpowerimp" => LightStrategy::AllPowerImp,
            "autopowerimp" => LightStrategy::AutoPowerImp,
            "logpowerimp" => LightStrategy::LogPowerImp,
            _ => return None,
        })
    }

    /// The strategy named by parameter `name` of an integrator (falling back to the older
    /// `strategy`, then `auto`); an unknown name is returned as the error.
    pub fn from_params(p: &crate::lxs::ParamSet, name: &str) -> Result<LightStrategy, String> {
        let v = p
            .string(name)
            .or_else(|| p.string("strategy"))
            .unwrap_or("auto");
        LightStrategy::parse(v).ok_or_else(|| v.to_string())
    }
}

/// The resolved strategy for a scene's lights.
#[derive(Clone, Debug)]
pub enum LightSelector {
    /// Every light each time.
    All,
    /// `draws` lights per estimate, each drawn from `dist` (draw k of n at (k + u) / n).
    Drawn {
        dist: PiecewiseConstant1D,
        draws: u32,
    },
}

/// The cutoff of LuxRender's automatic strategies: all lights up to this many.
const AUTO_ALL: usize = 5;

impl LightSelector {
    pub fn new(strategy: LightStrategy, lights: &[Light]) -> LightSelector {
        let n = lights.len();
        let weighted = |w: &dyn Fn(&Light) -> f32, draws: usize| {
            let weights: Vec<f32> = lights.iter().map(w).collect();
            let dist = PiecewiseConstant1D::new(&weights);
            // No weight anywhere: no light is drawn (LuxRender's distribution is undefined
            // there and adds nothing).
            let draws = if dist.integral() > 0.0 {
                draws.max(1)
            } else {
                0
            };
            LightSelector::Drawn {
                dist,
                draws: draws as u32,
            }
        };
        // In f64: a product past f32's range stays the largest weight instead of becoming
        // infinite (which would count as no weight).
        let power = |l: &Light| {
            (f64::from(l.importance()) * f64::from(l.power())).min(f64::from(f32::MAX)) as f32
        };
        match strategy {
            LightStrategy::All => LightSelector::All,
            LightStrategy::Auto if n <= AUTO_ALL => LightSelector::All,
            LightStrategy::One | LightStrategy::Auto => weighted(&|_| 1.0, 1),
            LightStrategy::Importance => weighted(&Light::importance, 1),
            LightStrategy::PowerImp => weighted(&power, 1),
            LightStrategy::AutoPowerImp if n > AUTO_ALL => weighted(&power, 1),
            LightStrategy::AllPowerImp | LightStrategy::AutoPowerImp => weighted(&power, n),
            LightStrategy::LogPowerImp => weighted(&|l| power(l).ln_1p(), 1),
        }
    }

    /// Light picks per estimate among `n_lights` lights.
    pub fn count(&self, n_lights: usize) -> u32 {
        match self {
            LightSelector::All => n_lights as u32,
            LightSelector::Drawn { draws, .. } => {
                if n_lights > 0 {
                    *draws
                } else {
                    0
                }
            }
        }
    }

    /// Pick `k` of an estimate with the uniform `u`: the light and its expected draws per
    /// estimate (the pick's contribution is divided by it). `None`: the pick drew a light of
    /// weight 0 (nothing to estimate).
    pub fn pick(&self, k: u32, u: f32) -> Option<(usize, f32)> {
        match self {
            LightSelector::All => Some((k as usize, 1.0)),
            LightSelector::Drawn { draws: 0, .. } => None,
            LightSelector::Drawn { dist, draws } => {
                let n = *draws;
                let v = ((k.min(n - 1) as f32 + u) / n as f32).min(1.0 - f32::EPSILON / 2.0);
                let (i, q, _) = dist.sample_discrete(v);
                (q > 0.0).then_some((i, q * n as f32))
            }
        }
    }

    /// Expected draws of light `i` per estimate (1 for `All`).
    pub fn pdf(&self, i: usize) -> f32 {
        match self {
            LightSelector::All => 1.0,
            LightSelector::Drawn { dist, draws } => dist.discrete_pdf(i) * *draws as f32,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::PiecewiseConstant1D;

    fn drawn(w: &[f32], draws: u32) -> LightSelector {
        LightSelector::Drawn {
            dist: PiecewiseConstant1D::new(w),
            draws,
        }
    }

    #[test]
    fn names_are_luxrenders() {
        for (name, s) in [
            ("one", LightStrategy::One),
            ("all", LightStrategy::All),
            ("auto", LightStrategy::Auto),
            ("importance", LightStrategy::Importance),
            ("powerimp", LightStrategy::PowerImp),
            ("allpowerimp", LightStrategy::AllPowerImp),
            ("autopowerimp", LightStrategy::AutoPowerImp),
            ("logpowerimp", LightStrategy::LogPowerImp),
        ] {
            assert_eq!(LightStrategy::parse(name), Some(s));
        }
        assert_eq!(LightStrategy::parse("nearest"), None);
        let mut p = crate::lxs::ParamSet::new();
        assert_eq!(
            LightStrategy::from_params(&p, "lightstrategy"),
            Ok(LightStrategy::Auto)
        );
        p.add(
            "strategy",
            crate::lxs::ParamValue::String(vec!["one".into()]),
        );
        assert_eq!(
            LightStrategy::from_params(&p, "lightstrategy"),
            Ok(LightStrategy::One)
        );
        p.add(
            "lightstrategy",
            crate::lxs::ParamValue::String(vec!["bogus".into()]),
        );
        assert_eq!(
            LightStrategy::from_params(&p, "lightstrategy"),
            Err("bogus".into())
        );
    }

    /// Stratified draws: summing f(i) / expected draws over the n picks of an estimate
    /// gives Σ f(i) on average over u, for any weights; each pick's expected draws add up
    /// to n; a light of weight 0 is never picked.
    #[test]
    fn drawn_estimates_are_unbiased_and_skip_zero_weights() {
        let f = [3.0f64, 0.5, 7.0, 1.25];
        let total: f64 = f.iter().sum();
        for (w, draws) in [
            (vec![1.0, 1.0, 1.0, 1.0], 1),
            (vec![5.0, 1.0, 0.2, 3.0], 1),
            (vec![5.0, 1.0, 0.2, 3.0], 4),
            (vec![2.0, 1.0, 4.0, 0.5], 3),
        ] {
            let sel = drawn(&w, draws);
            let m = 20_000;
            let mut sum = 0.0f64;
            for j in 0..m {
                let u = (j as f32 + 0.5) / m as f32;
                for k in 0..draws {
                    let (i, q) = sel.pick(k, u).expect("positive weights");
                    sum += f[i] / f64::from(q);
                }
            }
            let mean = sum / f64::from(m);
            assert!(
                (mean - total).abs() < 1e-3 * total,
                "{w:?} x{draws}: {mean}"
            );
            let expected: f32 = (0..4).map(|i| sel.pdf(i)).sum();
            assert!((expected - draws as f32).abs() < 1e-5);
        }
        let none = LightSelector::new(LightStrategy::Importance, &[]);
        assert_eq!(none.count(0), 0);
        let sel = drawn(&[1.0, 0.0, 1.0], 1);
        assert_eq!(sel.pdf(1), 0.0);
        assert!((0..100).all(|j| sel.pick(0, j as f32 / 100.0).map(|p| p.0) != Some(1)));
    }
}
