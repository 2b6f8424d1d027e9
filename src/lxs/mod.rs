//! The .lxs scene language: lexer, parser, graphics state, and the resulting
//! [`SceneDescription`]. The parser drives a [`SceneBuilder`]-style interface mirroring
//! LuxRender's API and never creates render objects.

pub mod description;
pub mod params;

pub use description::*;
pub use params::{Loc, Param, ParamSet, ParamType, ParamValue, SpectrumValue};
