//! The low-discrepancy sampler, after LuxRender's: per pixel and per block of `pixelsamples`
//! samples (a power of two, rounded up), every 1D or 2D request gets its own randomly
//! digit-scrambled (0,2)-sequence (van der Corput and Sobol's second dimension, Kollig-Keller
//! style), and the sample order is shuffled independently per request so dimensions are not
//! correlated (LuxRender's `LDShuffleScrambled1D/2D`). The `pixelsamples` samples of a block
//! form a (0, m, 2)-net in every 2D request: they are stratified in both axes and in every
//! elementary interval. A new block (the next pass over the pixel) draws fresh scrambles.
//!
//! Everything is derived by hashing (pixel key, block, dimension), so a value depends only on
//! (seed, stream, pixel, sample index, dimension).
//!
//! LuxRender parameters: `pixelsamples` (default 4, rounded up to a power of two);
//! `pixelsampler` (pixel visiting order, irrelevant here) is accepted.

use super::{pixel_samples, xy_samples, SamplerKind};
use crate::plugin::{BuildError, Stmt};

use super::hash::{combine, mix64, permute_pow2, unit_from_u32};
use glam::Vec2;

/// Van der Corput in base 2 (first dimension of the (0,2)-sequence), as 32 bits.
#[inline]
fn van_der_corput(i: u32) -> u32 {
    i.reverse_bits()
}

/// Sobol's second dimension (with van der Corput, a (0,2)-sequence), as 32 bits.
#[inline]
fn sobol2(mut i: u32) -> u32 {
    let mut v = 1u32 << 31;
    let mut r = 0u32;
    while i != 0 {
        if i & 1 != 0 {
            r ^= v;
        }
        i >>= 1;
        v ^= v >> 1;
    }
    r
}

/// The key of one block of `2^log2_n` samples of a pixel (one pass over it).
#[inline]
pub(super) fn block_key(pixel_key: u64, index: u64, log2_n: u32) -> u64 {
    combine(pixel_key, index >> log2_n)
}

/// Per-request scrambles: the shuffled point index within the block and two digit scrambles.
#[inline]
fn request(block_key: u64, index: u64, log2_n: u32, dim: u32) -> (u32, u32, u32) {
    let j = (index & ((1u64 << log2_n) - 1)) as u32;
    let key = combine(block_key, u64::from(dim));
    let point = permute_pow2(j, log2_n, key);
    let scr = mix64(key ^ 0x5c7a_3b1e_9d2f_4a61);
    (point, scr as u32, (scr >> 32) as u32)
}

/// A 1D value: the scrambled van der Corput point (stratified over the block).
pub(super) fn value_1d(block_key: u64, index: u64, log2_n: u32, dim: u32) -> f32 {
    let (p, sx, _) = request(block_key, index, log2_n, dim);
    unit_from_u32(van_der_corput(p) ^ sx)
}

/// A 2D value: the scrambled (0,2)-sequence point.
pub(super) fn value_2d(block_key: u64, index: u64, log2_n: u32, dim: u32) -> Vec2 {
    let (p, sx, sy) = request(block_key, index, log2_n, dim);
    Vec2::new(
        unit_from_u32(van_der_corput(p) ^ sx),
        unit_from_u32(sobol2(p) ^ sy),
    )
}

/// Reads a `lowdiscrepancy` statement.
pub(super) fn build(s: &Stmt) -> Result<(SamplerKind, u32), BuildError> {
    Ok((SamplerKind::LowDiscrepancy, pixel_samples(s)?))
}

/// LuxRender's older stratified samplers (`stratified` with `xsamples` × `ysamples` and
/// `jitter`; `bestcandidate` and `halton` with `pixelsamples`): rendered by this sampler,
/// which stratifies as well, with a located warning naming it.
pub(super) fn build_legacy(s: &mut Stmt) -> Result<(SamplerKind, u32), BuildError> {
    let n = if s.kind() == "stratified" {
        let _ = s.params().bool("jitter");
        xy_samples(s, s.params().int("xsamples"), s.params().int("ysamples"))?
    } else {
        pixel_samples(s)?
    };
    s.warn(format!(
        "sampler \"{}\" is not implemented; using \"lowdiscrepancy\" (unbiased, same samples per pixel)",
        s.kind()
    ));
    Ok((SamplerKind::LowDiscrepancy, n))
}
