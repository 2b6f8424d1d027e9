//! Light selection strategies for direct lighting, as LuxRender names them
//! (`lightstrategy`): `one` (one light picked uniformly), `all` (every light, each with its
//! `nsamples` shadow rays), `auto` (`all` up to 5 lights, `one` beyond: the cost of a sample
//! stays bounded), `importance`/`powerimp` (one light picked with probability proportional
//! to its power). Unknown names fall back to `auto` with a warning by the caller.

use super::Light;
use crate::sampling::PiecewiseConstant1D;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightStrategy {
    One,
    All,
    Auto,
    Power,
}

impl LightStrategy {
    pub fn parse(name: &str) -> Option<LightStrategy> {
        Some(match name {
            "one" => LightStrategy::One,
            "all" => LightStrategy::All,
            "auto" => LightStrategy::Auto,
            "importance" | "powerimp" | "allpowerimp" | "logpowerimp" => LightStrategy::Power,
            _ => return None,
        })
    }
}

/// The resolved strategy for a scene's lights.
#[derive(Clone, Debug)]
pub enum LightSelector {
    /// Every light each time.
    All,
    /// One light, picked by this distribution (uniform or by power).
    One(PiecewiseConstant1D),
}

impl LightSelector {
    pub fn new(strategy: LightStrategy, lights: &[Light]) -> LightSelector {
        let n = lights.len();
        match strategy {
            LightStrategy::All => LightSelector::All,
            LightStrategy::Auto if n <= 5 => LightSelector::All,
            LightStrategy::One | LightStrategy::Auto => {
                LightSelector::One(PiecewiseConstant1D::new(&vec![1.0; n]))
            }
            LightStrategy::Power => {
                let p: Vec<f32> = lights.iter().map(Light::power).collect();
                LightSelector::One(PiecewiseConstant1D::new(&p))
            }
        }
    }

    /// Probability that one direct-lighting estimate samples light `i` (1 for `All`).
    pub fn pdf(&self, i: usize) -> f32 {
        match self {
            LightSelector::All => 1.0,
            LightSelector::One(d) => d.discrete_pdf(i),
        }
    }
}
