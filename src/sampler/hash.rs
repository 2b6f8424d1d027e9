//! Hashing that turns (seed, stream, pixel, sample index, dimension) into random bits.
//!
//! Everything a sampler returns is a pure function of those inputs, so a film does not depend
//! on thread count or on the order pixels are visited, and two streams are independent.

/// A strong 64-bit bit mixer (the splitmix64 finaliser): every input bit affects every output
/// bit; a bijection on u64.
#[inline]
pub fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

const GOLDEN: u64 = 0x9e37_79b9_7f4a_7c15;

/// Combines a key with one more value (order matters).
#[inline]
pub fn combine(key: u64, v: u64) -> u64 {
    mix64(key ^ mix64(v.wrapping_add(GOLDEN)))
}

/// The key of one pixel's sample stream: depends on the job seed, the stream id and the pixel.
pub fn pixel_key(seed: u64, stream: u64, px: u32, py: u32) -> u64 {
    let k = combine(mix64(seed ^ 0x6c75_7866_6172_6d31), stream);
    combine(k, ((px as u64) << 32) | py as u64)
}

/// A float in [0, 1) from the top 24 bits of `h` (exactly representable, never 1).
#[inline]
pub fn unit_f32(h: u64) -> f32 {
    (h >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
}

/// A float in [0, 1) from the top 24 bits of a 32-bit pattern.
#[inline]
pub fn unit_from_u32(v: u32) -> f32 {
    (v >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// A pseudo-random permutation of `0 .. 2^bits` selected by `key` (`bits` <= 32): xor, odd
/// multiply and xorshift rounds, each a bijection on `bits`-bit integers.
pub fn permute_pow2(j: u32, bits: u32, key: u64) -> u32 {
    if bits == 0 {
        return 0;
    }
    let mask = if bits >= 32 {
        u64::from(u32::MAX)
    } else {
        (1u64 << bits) - 1
    };
    let shift = bits.div_ceil(2).max(1);
    let mut x = u64::from(j) & mask;
    let mut r = key;
    for _ in 0..2 {
        r = mix64(r ^ GOLDEN);
        x ^= r & mask;
        x = x.wrapping_mul((r >> 32) | 1) & mask;
        x ^= x >> shift;
    }
    x as u32
}
