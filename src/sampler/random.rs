//! The random sampler: every dimension of every sample is an independent hash of
//! (pixel key, sample index, dimension).
//!
//! LuxRender parameters: `pixelsamples` (default 4); the deprecated `xsamples`/`ysamples`
//! (default 2 each) multiply into it when given.

use super::{pixel_samples, xy_samples, SamplerKind};
use crate::plugin::{BuildError, Stmt};

use super::hash::{combine, mix64, unit_f32};

/// The key of one sample: mixes the pixel key with the sample index.
#[inline]
pub(super) fn sample_key(pixel_key: u64, index: u64) -> u64 {
    combine(pixel_key, index)
}

/// Dimension `dim` of the sample with key `key`.
#[inline]
pub(super) fn value(key: u64, dim: u32) -> f32 {
    unit_f32(mix64(
        key ^ (u64::from(dim) + 1).wrapping_mul(0xd605_bbb5_8c8a_bbd3),
    ))
}

/// Reads a `random` statement: `pixelsamples`, or the deprecated `xsamples` × `ysamples`.
pub(super) fn build(s: &mut Stmt) -> Result<(SamplerKind, u32), BuildError> {
    let mut n = pixel_samples(s)?;
    let (xs, ys) = (s.params().int("xsamples"), s.params().int("ysamples"));
    if xs.is_some() || ys.is_some() {
        s.warn("'xsamples'/'ysamples' are deprecated, use 'pixelsamples'");
        n = xy_samples(s, xs, ys)?;
    }
    Ok((SamplerKind::Random, n))
}
