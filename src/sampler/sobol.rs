//! The Sobol sampler: Owen-scrambled, index-shuffled Sobol points per pixel
//! (`sobol_burley`'s parts: Burley's hash-based Owen scrambling), padded: every 1D or 2D request uses the
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
//! samples per pixel and pass; `noiseaware` draws pixels by a sampling map ([`super::map`]).

use super::{pixel_samples, SamplerKind};
use crate::plugin::{BuildError, Stmt};

use super::hash::{combine, mix64};
use glam::Vec2;
use sobol_burley::parts::{owen_scramble_rev, u32_to_f32_norm};

const SEQ_BITS: u32 = 16;

/// The key of one run of 2^16 samples of a pixel.
#[inline]
pub(super) fn run_key(pixel_key: u64, index: u64) -> u64 {
    combine(pixel_key, index >> SEQ_BITS)
}

/// The request key of dimension `dim` and the index within the run: one splitmix step of
/// the run key (as the random sampler keys its dimensions).
#[inline]
fn request(run_key: u64, index: u64, dim: u32) -> (u64, u32) {
    (
        mix64(run_key ^ (u64::from(dim) + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15)),
        (index & ((1 << SEQ_BITS) - 1)) as u32,
    )
}

/// The shuffled (bit-reversed) index: a nested uniform scramble of the index under the
/// request's key, so different requests visit the points in unrelated orders.
#[inline]
fn shuffled_rev(key: u64, i: u32) -> u32 {
    owen_scramble_rev(i.reverse_bits(), key as u32)
}

/// Sobol dimension 0 of the point at bit-reversed index `rev` (its top 16 bits), in the
/// reversed form `sobol_burley::parts::sobol_rev` returns: bit m of it is the (m + 1)-th binary
/// digit after the point. Dimension 0 is the van der Corput sequence, digit m + 1 being index
/// bit m: the reversed value is the index itself.
#[inline]
fn sobol_rev_0(rev: u32) -> u32 {
    (rev & 0xffff_0000).reverse_bits()
}

/// Sobol dimension 1 from dimension 0's reversed value `v0`, in the same form. Its generator
/// matrix is Pascal's triangle mod 2: digit m + 1 is the XOR of the index bits k with C(k, m)
/// odd, that is (Lucas) with m's bits a subset of k's — a superset-XOR transform over the five
/// bits of a bit position, one shift per bit (no loop over index bits, no table).
#[inline]
fn sobol_rev_1(v0: u32) -> u32 {
    let mut v = v0;
    v ^= (v >> 1) & 0x5555_5555;
    v ^= (v >> 2) & 0x3333_3333;
    v ^= (v >> 4) & 0x0f0f_0f0f;
    v ^= (v >> 8) & 0x00ff_00ff;
    v ^= (v >> 16) & 0x0000_ffff;
    v
}

/// The value in [0, 1) of a reversed Sobol coordinate under an Owen scramble.
#[inline]
fn scrambled(v: u32, scramble: u32) -> f32 {
    u32_to_f32_norm(owen_scramble_rev(v, scramble).reverse_bits())
}

/// The 1D request at dimension `dim` of sample `index`.
#[inline]
pub(super) fn value_1d(run_key: u64, index: u64, dim: u32) -> f32 {
    let (key, i) = request(run_key, index, dim);
    scrambled(sobol_rev_0(shuffled_rev(key, i)), (key >> 32) as u32)
}

/// The 2D request at dimensions `dim`, `dim + 1` of sample `index`.
#[inline]
pub(super) fn value_2d(run_key: u64, index: u64, dim: u32) -> Vec2 {
    let (key, i) = request(run_key, index, dim);
    let v0 = sobol_rev_0(shuffled_rev(key, i));
    Vec2::new(
        scrambled(v0, (key >> 32) as u32),
        scrambled(sobol_rev_1(v0), mix64(key) as u32),
    )
}

/// Reads a `sobol` statement.
pub(super) fn build(s: &Stmt) -> Result<(SamplerKind, u32), BuildError> {
    Ok((SamplerKind::Sobol, pixel_samples(s)?))
}

#[cfg(test)]
mod tests {
    #[test]
    fn both_dimensions_match_sobol_burley_for_every_index() {
        for top in 0..=u16::MAX as u32 {
            // The low bits are ignored, as sobol_burley ignores them.
            let rev = (top << 16) | (top.wrapping_mul(0x9e37) & 0xffff);
            let v0 = super::sobol_rev_0(rev);
            assert_eq!(v0, sobol_burley::parts::sobol_rev(rev, 0), "index {top:#x}");
            let v1 = super::sobol_rev_1(v0);
            assert_eq!(v1, sobol_burley::parts::sobol_rev(rev, 1), "index {top:#x}");
        }
    }
}
