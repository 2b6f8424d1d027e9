//! Sampling building blocks shared by every plugin family: warps from the unit square to
//! directions and points ([`warp`]), discrete distributions over items ([`discrete`]) and
//! piecewise-constant densities in 1D and 2D ([`piecewise`]). Sample streams themselves are
//! the samplers' ([`crate::sampler`]).

pub mod discrete;
pub mod piecewise;
pub mod warp;

pub use discrete::DiscreteDistribution;
pub use piecewise::{PiecewiseConstant1D, PiecewiseConstant2D};
pub use warp::{
    concentric_disc, cosine_hemisphere, power_heuristic, uniform_cone, uniform_cone_pdf,
    uniform_sphere, UNIFORM_SPHERE_PDF,
};
