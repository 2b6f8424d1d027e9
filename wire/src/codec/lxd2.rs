//! `lxd2`: the lossless compressed film encoding of uploads.
//!
//! After the common header (magic `LXD2`, see [`super`]): the compressor u8 (1 lz4 block,
//! 2 zstd frame), the band height u32 (rows), then per group and buffer, per band of rows, the
//! compressed length u32 (0: every value of the band is +0.0) and the compressed bytes.
//!
//! A band of `n` pixels is transformed before compression, every step reversible bit for bit:
//! the interleaved X, Y, Z, alpha, weight sums become five planes of `n` values; alpha's bits
//! are XORed with the weight's (alpha is 1 for most samples, so the sums are equal and the
//! XOR is zero); then the `5n` u64 bit patterns are byte-shuffled (all first bytes, all second
//! bytes, ...), which puts the slowly varying sign/exponent bytes together for the compressor.
//! Bands are independent, so both sides work on them in parallel.

use super::{bad, write_header, Reader};
use crate::{Result, WireError};
use luxfarm::film::{Film, PIXEL_VALUES};
use rayon::prelude::*;
use std::cell::RefCell;

/// Magic of the encoding.
pub const MAGIC: &[u8; 4] = b"LXD2";
/// Rows per independently compressed band.
const BAND_ROWS: u32 = 16;
/// Index of alpha and of the weight among a pixel's values.
const ALPHA: usize = 3;
const WEIGHT: usize = 4;

/// The byte compressor of an `lxd2` film.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compressor {
    /// lz4 block format (lz4_flex).
    Lz4,
    /// zstd at a level (negative levels are zstd's fast modes).
    Zstd(i32),
}

impl Default for Compressor {
    /// zstd level 1: see `luxfarm bench transport` for the measurements behind the choice.
    fn default() -> Compressor {
        Compressor::Zstd(1)
    }
}

impl Compressor {
    fn tag(self) -> u8 {
        match self {
            Compressor::Lz4 => 1,
            Compressor::Zstd(_) => 2,
        }
    }

    fn compress(self, raw: &[u8]) -> Vec<u8> {
        match self {
            Compressor::Lz4 => lz4_flex::block::compress(raw),
            // Compressing a memory buffer cannot fail; fall back to lz4 if it ever did.
            Compressor::Zstd(level) => {
                zstd::bulk::compress(raw, level).unwrap_or_else(|_| lz4_flex::block::compress(raw))
            }
        }
    }
}

thread_local! {
    /// Per-thread zstd context and band buffer, reused across bands and uploads (a fresh
    /// context and a fresh megabyte buffer per band cost more than the decoding).
    static SCRATCH: RefCell<(Option<zstd::bulk::Decompressor<'static>>, Vec<u8>)> =
        const { RefCell::new((None, Vec::new())) };
}

/// Decompresses into exactly `out.len()` bytes.
fn decompress(
    tag: u8,
    src: &[u8],
    out: &mut [u8],
    zctx: &mut Option<zstd::bulk::Decompressor<'static>>,
) -> Result<()> {
    let n = match tag {
        1 => lz4_flex::block::decompress_into(src, out).map_err(|e| bad(&e.to_string()))?,
        2 => {
            if zctx.is_none() {
                *zctx =
                    Some(zstd::bulk::Decompressor::new().map_err(|e| bad(&format!("zstd: {e}")))?);
            }
            let d = zctx.as_mut().ok_or_else(|| bad("zstd context"))?;
            d.decompress_to_buffer(src, out)
                .map_err(|e| bad(&format!("zstd: {e}")))?
        }
        _ => return Err(bad("unknown compressor")),
    };
    if n != out.len() {
        return Err(bad("band has the wrong size"));
    }
    Ok(())
}

/// Encodes a film as `lxd2` with a compressor.
pub fn encode(film: &Film, comp: Compressor) -> Vec<u8> {
    let mut out = Vec::with_capacity(1 << 20);
    write_header(&mut out, MAGIC, film);
    out.push(comp.tag());
    out.extend_from_slice(&BAND_ROWS.to_le_bytes());
    let band_values = BAND_ROWS as usize * film.width() as usize * PIXEL_VALUES;
    for g in 0..film.groups().len() {
        for b in 0..film.buffer_types().len() {
            let Some(buf) = film.buffer(g, b) else {
                continue;
            };
            let bands: Vec<Vec<u8>> = buf
                .par_chunks(band_values)
                .map(|band| encode_band(band, comp))
                .collect();
            for band in bands {
                out.extend_from_slice(&(band.len() as u32).to_le_bytes());
                out.extend_from_slice(&band);
            }
        }
    }
    out.extend_from_slice(&super::depth_section(film));
    out.extend_from_slice(&super::variance_section(film));
    out
}

/// One band: planes, alpha XOR weight, byte shuffle, compression (empty when all +0.0).
fn encode_band(band: &[f64], comp: Compressor) -> Vec<u8> {
    if band.iter().all(|v| v.to_bits() == 0) {
        return Vec::new();
    }
    let n = band.len() / PIXEL_VALUES;
    let mut planes = vec![0u64; n * PIXEL_VALUES];
    for (i, p) in band.chunks_exact(PIXEL_VALUES).enumerate() {
        let weight = p[WEIGHT].to_bits();
        for (c, v) in p.iter().enumerate() {
            let bits = v.to_bits();
            planes[c * n + i] = if c == ALPHA { bits ^ weight } else { bits };
        }
    }
    let m = planes.len();
    let mut shuffled = vec![0u8; m * 8];
    // One sequential pass per byte position (vectorises well).
    for (k, out) in shuffled.chunks_exact_mut(m).enumerate() {
        let shift = 8 * k as u32;
        for (o, v) in out.iter_mut().zip(&planes) {
            *o = (v >> shift) as u8;
        }
    }
    comp.compress(&shuffled)
}

/// Reads the values after the header into the film's buffers.
pub(super) fn read_values(r: &mut Reader, film: &mut Film) -> Result<()> {
    let tag = r.u8()?;
    let rows = r.u32()?;
    if rows == 0 {
        return Err(bad("zero band height"));
    }
    let band_values = (rows as usize)
        .min(film.height() as usize)
        .saturating_mul(film.width() as usize * PIXEL_VALUES);
    let nbands = film.height().div_ceil(rows) as usize;
    let (ngroups, nbuf) = (film.groups().len(), film.buffer_types().len());
    for g in 0..ngroups {
        for b in 0..nbuf {
            let mut blocks = Vec::with_capacity(nbands);
            for _ in 0..nbands {
                let len = r.u32()? as usize;
                blocks.push(r.take(len)?);
            }
            let dst = film.buffer_mut(g, b).ok_or_else(|| bad("buffer missing"))?;
            dst.par_chunks_mut(band_values)
                .zip(blocks)
                .try_for_each(|(d, src)| decode_band(tag, src, d))?;
        }
    }
    Ok(())
}

/// Reverses [`encode_band`] into `dst` (interleaved pixel values).
fn decode_band(tag: u8, src: &[u8], dst: &mut [f64]) -> Result<(), WireError> {
    if src.is_empty() {
        dst.fill(0.0);
        return Ok(());
    }
    SCRATCH.with(|cell| {
        let mut scratch = cell.borrow_mut();
        let (zctx, shuffled) = &mut *scratch;
        shuffled.resize(dst.len() * 8, 0);
        decompress(tag, src, shuffled, zctx)?;
        unshuffle(shuffled, dst)
    })
}

/// Bits of a float's exponent: all set for infinities and NaNs.
const EXPONENT: u64 = 0x7ff0_0000_0000_0000;

/// Gathers each value's 8 bytes from the byte planes straight into the interleaved pixels,
/// undoes alpha XOR weight and checks that every value is finite. Eight pixels at a time:
/// per channel, the 8 bytes of each plane are one word and the 8 x 8 byte matrix is
/// transposed in registers ([`transpose8`]), so every plane is read a word at a time and the
/// pixels are written in order.
fn unshuffle(shuffled: &[u8], dst: &mut [f64]) -> Result<(), WireError> {
    let m = dst.len();
    let n = m / PIXEL_VALUES;
    if n * PIXEL_VALUES != m || shuffled.len() != m * 8 {
        return Err(bad("band has the wrong size"));
    }
    let mut planes: [&[u8]; 8] = [&[]; 8];
    for (k, p) in shuffled.chunks_exact(m).enumerate() {
        if let Some(slot) = planes.get_mut(k) {
            *slot = p;
        }
    }
    // Every index below is under m: value c of pixel i sits at c * n + i with i < n.
    let mut nonfinite = false;
    let full = n / 8;
    for (block, px) in dst.chunks_exact_mut(8 * PIXEL_VALUES).enumerate() {
        let i = block * 8;
        let mut words = [[0u64; 8]; PIXEL_VALUES];
        for (c, w) in words.iter_mut().enumerate() {
            let at = c * n + i;
            for (row, plane) in w.iter_mut().zip(&planes) {
                let mut b = [0u8; 8];
                b.copy_from_slice(&plane[at..at + 8]);
                *row = u64::from_le_bytes(b);
            }
            transpose8(w);
        }
        let weight = words[WEIGHT];
        for (a, w) in words[ALPHA].iter_mut().zip(weight) {
            *a ^= w;
        }
        for (j, p) in px.chunks_exact_mut(PIXEL_VALUES).enumerate() {
            for (v, w) in p.iter_mut().zip(&words) {
                let bits = w[j];
                nonfinite |= bits & EXPONENT == EXPONENT;
                *v = f64::from_bits(bits);
            }
        }
    }
    for i in full * 8..n {
        let value = |c: usize| {
            let at = c * n + i;
            u64::from_le_bytes(planes.map(|p| p[at]))
        };
        let weight = value(WEIGHT);
        for c in 0..PIXEL_VALUES {
            let bits = if c == ALPHA {
                value(c) ^ weight
            } else {
                value(c)
            };
            nonfinite |= bits & EXPONENT == EXPONENT;
            dst[i * PIXEL_VALUES + c] = f64::from_bits(bits);
        }
    }
    if nonfinite {
        Err(bad("non-finite pixel value"))
    } else {
        Ok(())
    }
}

/// Transposes an 8 x 8 byte matrix held as 8 little-endian words (byte j of word k becomes
/// byte k of word j): three rounds swap the off-diagonal blocks of 4, 2 and 1 bytes.
fn transpose8(r: &mut [u64; 8]) {
    const ROUNDS: [(usize, u64); 3] = [
        (4, 0x0000_0000_ffff_ffff),
        (2, 0x0000_ffff_0000_ffff),
        (1, 0x00ff_00ff_00ff_00ff),
    ];
    for (s, mask) in ROUNDS {
        let shift = 8 * s as u32;
        for a in (0..8).filter(|a| a & s == 0) {
            let t = ((r[a] >> shift) ^ r[a + s]) & mask;
            r[a + s] ^= t;
            r[a] ^= t << shift;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::decode;
    use super::*;

    /// A film with noisy values in several bands, one empty band, two groups.
    fn noisy(w: u32, h: u32) -> Film {
        let mut f = Film::new(w, h, vec!["a".into(), "b".into()]);
        let mut s: u32 = 7;
        for y in 0..h.saturating_sub(BAND_ROWS) {
            for x in 0..w {
                s ^= s << 13;
                s ^= s >> 17;
                s ^= s << 5;
                let v = (s >> 8) as f32 / 16_777_216.0;
                f.add_splat(
                    (s & 1) as usize,
                    x,
                    y,
                    [v * 0.3, v, v * 1.7],
                    v.min(0.9),
                    0.5 + v,
                );
            }
        }
        f.add_rejected(3);
        f.add_sample_count(f64::from(w * h));
        f
    }

    #[test]
    fn round_trip_is_exact_for_both_compressors() {
        let f = noisy(37, 53);
        for comp in [Compressor::Lz4, Compressor::Zstd(1), Compressor::Zstd(-3)] {
            let bytes = encode(&f, comp);
            assert_eq!(decode(&bytes).unwrap(), f, "{comp:?}");
        }
    }

    #[test]
    fn negative_zero_and_negative_lobes_survive() {
        let mut f = Film::new(4, 4, vec![]);
        f.add_splat(0, 1, 1, [0.5, 0.25, 0.1], 1.0, -0.3);
        if let Some(b) = f.buffer_mut(0, 0) {
            b[0] = -0.0;
        }
        let g = decode(&encode(&f, Compressor::default())).unwrap();
        assert_eq!(g.buffer(0, 0).unwrap()[0].to_bits(), (-0.0f64).to_bits());
        assert_eq!(f, g);
    }

    /// The byte planes of `values` as `encode_band` lays them out before compression.
    fn shuffle(values: &[u64]) -> Vec<u8> {
        let m = values.len();
        let mut out = vec![0u8; m * 8];
        for (k, plane) in out.chunks_exact_mut(m).enumerate() {
            for (o, v) in plane.iter_mut().zip(values) {
                *o = (v >> (8 * k)) as u8;
            }
        }
        out
    }

    #[test]
    fn transpose8_moves_byte_j_of_word_k_to_byte_k_of_word_j() {
        let mut r = [0u64; 8];
        for (k, w) in r.iter_mut().enumerate() {
            *w = u64::from_le_bytes(std::array::from_fn(|j| (16 * k + j) as u8));
        }
        let before = r;
        transpose8(&mut r);
        for (k, row) in before.iter().enumerate() {
            for (j, word) in r.iter().enumerate() {
                assert_eq!(word.to_le_bytes()[k], row.to_le_bytes()[j]);
            }
        }
    }

    #[test]
    fn unshuffle_restores_pixels_for_every_band_width() {
        // Pixel counts with and without a tail after the blocks of eight.
        for n in [1usize, 7, 8, 9, 16, 23, 64] {
            let mut rng: u64 = 0x2545_f491_4f6c_dd1d ^ n as u64;
            let mut next = || {
                rng ^= rng << 13;
                rng ^= rng >> 7;
                rng ^= rng << 17;
                f64::from_bits(rng >> 2)
            };
            let pixels: Vec<[f64; PIXEL_VALUES]> =
                (0..n).map(|_| std::array::from_fn(|_| next())).collect();
            // Planes as the encoder lays them out: channel by channel, alpha XOR weight.
            let mut planes = vec![0u64; n * PIXEL_VALUES];
            for (i, p) in pixels.iter().enumerate() {
                for (c, v) in p.iter().enumerate() {
                    let bits = v.to_bits();
                    planes[c * n + i] = if c == ALPHA {
                        bits ^ p[WEIGHT].to_bits()
                    } else {
                        bits
                    };
                }
            }
            let mut dst = vec![-1.0; n * PIXEL_VALUES];
            unshuffle(&shuffle(&planes), &mut dst).unwrap();
            let want: Vec<u64> = pixels.iter().flatten().map(|v| v.to_bits()).collect();
            let got: Vec<u64> = dst.iter().map(|v| v.to_bits()).collect();
            assert_eq!(got, want, "{n} pixels");
            // A non-finite value anywhere, in a block or in the tail, is refused.
            for at in [0, planes.len() - 1] {
                let mut bad_planes = planes.clone();
                bad_planes[at] = f64::INFINITY.to_bits();
                if at / n == ALPHA {
                    bad_planes[at] ^= planes[WEIGHT * n + at % n];
                }
                assert!(
                    unshuffle(&shuffle(&bad_planes), &mut dst).is_err(),
                    "{n} {at}"
                );
            }
            assert!(unshuffle(&shuffle(&planes)[1..], &mut dst).is_err());
        }
    }

    #[test]
    fn corrupt_bands_refused() {
        let f = noisy(20, 40);
        let good = encode(&f, Compressor::Zstd(1));
        assert!(decode(&good[..good.len() - 3]).is_err());
        let mut extra = good.clone();
        extra.push(0);
        assert!(decode(&extra).is_err());
        let mut flipped = good.clone();
        let n = flipped.len();
        flipped[n - 10] ^= 0xff;
        // Either refused or decoded to other values; never a panic.
        let _ = decode(&flipped);
        let mut nan = Film::new(2, 2, vec![]);
        if let Some(b) = nan.buffer_mut(0, 0) {
            b[1] = f64::NAN;
        }
        assert!(decode(&encode(&nan, Compressor::Lz4)).is_err());
    }
}
