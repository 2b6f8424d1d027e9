//! The Sobol sampler: Owen-scrambled, index-shuffled Sobol points per pixel
//! (`sobol_burley`, Burley's hash-based scrambling), padded: every 1D or 2D request uses the
//! first one or two Sobol dimensions (a (0,2)-sequence) under its own seed derived from
//! (pixel key, dimension), so every 2D request is stratified as well as the first pair, and
//! the index shuffling decorrelates requests from each other (Burley 2020, "padding").
//!
//! A pixel's samples continue one sequence across passes (indices 0, 1, 2, ...): after any
//! power-of-two count the set is a scrambled (0, m, 2)-net. `sobol_burley` serves 2^16
//! indices per seed; the index's high bits select a fresh seed beyond that.
//!
//! LuxRender's sobol sampler renders progressively over the whole image and has no
//! `pixelsamples`; ours samples pixel by pixel, so `pixelsamples` (default 4) sets the
//! samples per pixel and pass. `noiseaware` is accepted (not supported: uniform sampling).

use super::hash::combine;
use glam::Vec2;

const SEQ_BITS: u32 = 16;

/// The key of one run of 2^16 samples of a pixel.
#[inline]
pub(super) fn run_key(pixel_key: u64, index: u64) -> u64 {
    combine(pixel_key, index >> SEQ_BITS)
}

#[inline]
fn seed_and_index(run_key: u64, index: u64, dim: u32) -> (u32, u32) {
    let seed = combine(run_key, u64::from(dim));
    (
        (seed ^ (seed >> 32)) as u32,
        (index & ((1 << SEQ_BITS) - 1)) as u32,
    )
}

/// The 1D request at dimension `dim` of sample `index`.
#[inline]
pub(super) fn value_1d(run_key: u64, index: u64, dim: u32) -> f32 {
    let (seed, i) = seed_and_index(run_key, index, dim);
    sobol_burley::sample(i, 0, seed)
}

/// The 2D request at dimensions `dim`, `dim + 1` of sample `index`.
#[inline]
pub(super) fn value_2d(run_key: u64, index: u64, dim: u32) -> Vec2 {
    let (seed, i) = seed_and_index(run_key, index, dim);
    Vec2::new(
        sobol_burley::sample(i, 0, seed),
        sobol_burley::sample(i, 1, seed),
    )
}
