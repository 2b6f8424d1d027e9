//! Film encodings of the farm, all lossless (the master's merged film is the exact sum of the
//! acknowledged deltas); FLM (f32, gzip) stays the download and output format.
//!
//! Data flow: a worker's session film -> [`encode_delta`] -> upload chunks -> the master's
//! [`decode_as_into`] (checked against the upload's `encoding` name) -> a reused [`Film`] of
//! the job's layout, every value, count and the rejection count overwritten with exactly the
//! sent sums, which the master adds to the job's film ([`decode_as`] allocates a fresh film
//! instead). Checkpoints go through [`encode`] and [`decode`].
//!
//! - `lxd1`: the film's f64 sums and sample counts, little endian, uncompressed. Checkpoints use
//!   it (as fast to write and read as a copy) and old workers upload it.
//! - `lxd2` ([`lxd2`]): the same header, then the f64 values split into channel planes, byte
//!   shuffled and compressed (zstd or lz4) in independent row bands. The worker's upload
//!   encoding ([`DELTA_ENCODING`]): 14-42 % of lxd1's bytes on rendered 1080p Cornell deltas
//!   (box / Mitchell filter), for ~50 ms of encoding and decoding each (`luxfarm bench
//!   transport`).
//!
//! Both may end with a depth section (a Film writing Z: the depth sums and weights of the
//! `write_exr_ZBuf` channel, zstd-compressed, see `depth_section`); a film without it has no
//! depth. A variance section may follow (a noise-aware render: each pixel's luminance spread
//! sums, zstd-compressed, see `variance_section`); a film without it has none.
//!
//! Common header: magic, width u32, height u32, group count u32, per group its name (u32
//! length + UTF-8), buffer count u32, per buffer its type i32, rejected u64, per group the
//! sample count f64. `lxd1` then holds per group and buffer `width*height*5` f64 values.

pub mod lxd2;

use crate::{Result, WireError};
use luxfarm::film::{BufferType, Film, VarianceBuffer, ZBuffer, PIXEL_VALUES};

pub use lxd2::Compressor;

const MAGIC: &[u8; 4] = b"LXD1";
/// Tag of the optional depth section (Z buffer sums) after a film's values.
const DEPTH_TAG: &[u8; 4] = b"ZBF1";
/// Tag of the optional variance section (noise-aware sums) after the depth section, if any.
const VARIANCE_TAG: &[u8; 4] = b"VAR1";
/// Most light groups a delta may carry.
pub const MAX_GROUPS: usize = 1024;
const MAX_BUFFERS: usize = 8;
const MAX_NAME: usize = 4096;
/// Largest decoded film (bytes of f64 values), as large as the largest accepted upload.
pub const MAX_DECODED: u64 = 4 << 30;

/// The encoding workers upload deltas in (the `encoding` field of `UploadHeader`).
pub const DELTA_ENCODING: &str = "lxd2";

/// Encodes a delta in the upload encoding ([`DELTA_ENCODING`]).
pub fn encode_delta(film: &Film) -> Vec<u8> {
    lxd2::encode(film, Compressor::default())
}

/// Decodes a delta sent with the named encoding into a fresh film.
pub fn decode_as(encoding: &str, bytes: &[u8]) -> Result<Film> {
    check_encoding(encoding, bytes)?;
    decode(bytes)
}

/// Decodes a delta sent with the named encoding into `film`, which must have the delta's
/// layout (resolution, light group count, buffers): every value, sample count and the
/// rejection count are overwritten, so a film reused across deltas needs no clearing and
/// touches no fresh pages. A delta of another layout is refused before any value is read. On
/// an error `film` holds unspecified values (the next successful decode overwrites them all).
pub fn decode_as_into(encoding: &str, bytes: &[u8], film: &mut Film) -> Result<()> {
    check_encoding(encoding, bytes)?;
    decode_into(bytes, film)
}

/// The upload's encoding name must be known and match the bytes' magic.
fn check_encoding(encoding: &str, bytes: &[u8]) -> Result<()> {
    let magic = bytes.get(..4).unwrap_or_default();
    match encoding {
        "lxd1" | "lxd2" if magic.eq_ignore_ascii_case(encoding.as_bytes()) => Ok(()),
        "lxd1" | "lxd2" => Err(bad(&format!("not an {encoding} film"))),
        other => Err(WireError::UnknownEncoding(other.to_string())),
    }
}

/// Encodes a film as `lxd1` (checkpoints).
pub fn encode(film: &Film) -> Vec<u8> {
    let values =
        film.pixel_count() * PIXEL_VALUES * film.groups().len() * film.buffer_types().len();
    let mut out = Vec::with_capacity(64 + values * 8);
    // Writing to a Vec cannot fail.
    let _ = encode_to(film, &mut out);
    out
}

/// Writes a film as `lxd1` to `w` (a checkpoint file), a few thousand values at a time.
pub fn encode_to(film: &Film, w: &mut impl std::io::Write) -> std::io::Result<()> {
    let mut header = Vec::new();
    write_header(&mut header, MAGIC, film);
    w.write_all(&header)?;
    let mut bytes = Vec::with_capacity(8 * 4096);
    for g in 0..film.groups().len() {
        for b in 0..film.buffer_types().len() {
            let Some(buf) = film.buffer(g, b) else {
                continue;
            };
            for chunk in buf.chunks(4096) {
                bytes.clear();
                for v in chunk {
                    bytes.extend_from_slice(&v.to_le_bytes());
                }
                w.write_all(&bytes)?;
            }
        }
    }
    w.write_all(&depth_section(film))?;
    w.write_all(&variance_section(film))
}

/// The optional depth section after the values (both encodings): [`DEPTH_TAG`], the
/// compressed length u32, then zstd of the sums and the weights (f64, little endian, row by
/// row). A film without depth writes nothing.
fn depth_section(film: &Film) -> Vec<u8> {
    let Some(z) = film.depth() else {
        return Vec::new();
    };
    packed_section(DEPTH_TAG, z.sums().iter().chain(z.weights()).copied())
}

/// A tagged section: `tag`, the compressed length u32, then zstd of `values` (f64, little
/// endian).
fn packed_section(tag: &[u8; 4], values: impl Iterator<Item = f64>) -> Vec<u8> {
    let raw: Vec<u8> = values.flat_map(f64::to_le_bytes).collect();
    let packed = zstd::bulk::compress(&raw, 1).unwrap_or_default();
    let mut out = Vec::with_capacity(8 + packed.len());
    out.extend_from_slice(tag);
    out.extend_from_slice(&(packed.len() as u32).to_le_bytes());
    out.extend_from_slice(&packed);
    out
}

/// Reads the optional sections after the values (see [`depth_section`] and
/// [`variance_section`]), each at most once and in that order; a section left out clears
/// that part of `film`. Nothing else may follow.
fn read_sections(r: &mut Reader, film: &mut Film) -> Result<()> {
    let (mut depth, mut variance) = (false, false);
    while r.rest() != 0 {
        let tag = r.take(4)?;
        if tag == DEPTH_TAG && !depth && !variance {
            let z = read_depth(r, film)?;
            film.set_depth(Some(z)).map_err(|e| bad(&e.to_string()))?;
            depth = true;
        } else if tag == VARIANCE_TAG && !variance {
            read_variance(r, film)?;
            variance = true;
        } else {
            return Err(bad("trailing bytes"));
        }
    }
    if !depth {
        film.set_depth(None).map_err(|e| bad(&e.to_string()))?;
    }
    if !variance {
        film.set_variance(None).map_err(|e| bad(&e.to_string()))?;
    }
    Ok(())
}

/// A section's zstd-compressed f64 values (after its tag): the compressed length u32, then
/// exactly `count` values once decompressed, as little-endian bytes.
fn read_f64_section(r: &mut Reader, count: usize, what: &str) -> Result<Vec<u8>> {
    let len = r.u32()? as usize;
    let packed = r.take(len)?;
    let want = count * 8;
    let raw =
        zstd::bulk::decompress(packed, want).map_err(|_| bad(&format!("bad {what} section")))?;
    if raw.len() != want {
        return Err(bad(&format!("{what} section of the wrong size")));
    }
    Ok(raw)
}

/// The `i`-th little-endian f64 of `raw` (in range by the section's checked size).
fn f64_at(raw: &[u8], i: usize) -> f64 {
    let mut b = [0u8; 8];
    if let Some(c) = raw.get(8 * i..8 * i + 8) {
        b.copy_from_slice(c);
    }
    f64::from_le_bytes(b)
}

/// The depth section's sums and weights: the film's pixel count of each, finite, weights
/// not negative.
fn read_depth(r: &mut Reader, film: &Film) -> Result<ZBuffer> {
    let n = film.pixel_count();
    let raw = read_f64_section(r, 2 * n, "depth")?;
    let sums = (0..n).map(|i| f64_at(&raw, i)).collect();
    let weights = (n..2 * n).map(|i| f64_at(&raw, i)).collect();
    ZBuffer::from_sums(film.width(), film.height(), sums, weights).map_err(|e| bad(&e))
}

/// The variance section's sums, three per pixel (Σw, Σw·Y, Σw·Y²), all finite, into
/// `film`: written over the sums the film already holds when it has them (a reused film
/// takes no fresh memory but the decompressed bytes).
fn read_variance(r: &mut Reader, film: &mut Film) -> Result<()> {
    let n = film.pixel_count();
    let raw = read_f64_section(r, 3 * n, "variance")?;
    let triple = |i: usize| [0, 1, 2].map(|k| f64_at(&raw, 3 * i + k));
    if film.variance().is_none() {
        let v = VarianceBuffer::new(film.width(), film.height());
        film.set_variance(Some(v))
            .map_err(|e| bad(&e.to_string()))?;
    }
    match film.variance_mut() {
        Some(v) => v.overwrite(n, triple).map_err(|e| bad(&e)),
        None => Err(bad("variance section for a film without variance sums")),
    }
}

/// The optional variance section after the depth section (both encodings): [`VARIANCE_TAG`],
/// the compressed length u32, then zstd of each pixel's three sums (f64, little endian, row
/// by row). A film without variance sums writes nothing.
fn variance_section(film: &Film) -> Vec<u8> {
    let Some(v) = film.variance() else {
        return Vec::new();
    };
    packed_section(VARIANCE_TAG, v.sums().iter().flatten().copied())
}

/// Writes the common header with its magic.
fn write_header(out: &mut Vec<u8>, magic: &[u8; 4], film: &Film) {
    out.extend_from_slice(magic);
    out.extend_from_slice(&film.width().to_le_bytes());
    out.extend_from_slice(&film.height().to_le_bytes());
    out.extend_from_slice(&(film.groups().len() as u32).to_le_bytes());
    for g in film.groups() {
        out.extend_from_slice(&(g.len() as u32).to_le_bytes());
        out.extend_from_slice(g.as_bytes());
    }
    out.extend_from_slice(&(film.buffer_types().len() as u32).to_le_bytes());
    for b in film.buffer_types() {
        out.extend_from_slice(&b.id().to_le_bytes());
    }
    out.extend_from_slice(&film.rejected().to_le_bytes());
    for g in 0..film.groups().len() {
        out.extend_from_slice(&film.sample_count(g).to_le_bytes());
    }
}

/// A cursor over untrusted bytes.
struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8]> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.bytes.len());
        let end = end.ok_or_else(|| bad("truncated"))?;
        let s = &self.bytes[self.pos..end];
        self.pos = end;
        Ok(s)
    }
    fn u8(&mut self) -> Result<u8> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> Result<u32> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    fn u64(&mut self) -> Result<u64> {
        let b = self.take(8)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(b);
        Ok(u64::from_le_bytes(a))
    }
    fn f64(&mut self) -> Result<f64> {
        Ok(f64::from_bits(self.u64()?))
    }
    fn rest(&self) -> usize {
        self.bytes.len() - self.pos
    }
}

/// A delta refused for the reason `why`.
fn bad(why: &str) -> WireError {
    WireError::Delta(why.to_string())
}

/// Decodes an `lxd1` or `lxd2` film (told apart by the magic) into a fresh film, refusing
/// malformed input and non-finite or negative counts and values.
pub fn decode(bytes: &[u8]) -> Result<Film> {
    let mut r = Reader { bytes, pos: 0 };
    let raw = read_magic(&mut r)?;
    let header = read_header(&mut r, raw)?;
    let mut film = header.new_film()?;
    read_values(&mut r, raw, &mut film)?;
    read_sections(&mut r, &mut film)?;
    Ok(film)
}

/// As [`decode`], into a film of the delta's layout (see [`decode_as_into`]).
pub fn decode_into(bytes: &[u8], film: &mut Film) -> Result<()> {
    let mut r = Reader { bytes, pos: 0 };
    let raw = read_magic(&mut r)?;
    let header = read_header(&mut r, raw)?;
    header.check_fits(film)?;
    read_values(&mut r, raw, film)?;
    read_sections(&mut r, film)?;
    header.set_counts(film);
    Ok(())
}

/// Reads the magic: true for `lxd1` (raw values), false for `lxd2`.
fn read_magic(r: &mut Reader) -> Result<bool> {
    let magic = r.take(4)?;
    if magic == lxd2::MAGIC {
        Ok(false)
    } else if magic == MAGIC {
        Ok(true)
    } else {
        Err(bad("not an lxd1 or lxd2 film"))
    }
}

/// Reads the values after the header into every buffer of `film` (raw `lxd1` or `lxd2`).
fn read_values(r: &mut Reader, raw: bool, film: &mut Film) -> Result<()> {
    if !raw {
        return lxd2::read_values(r, film);
    }
    let (ngroups, nbuf) = (film.groups().len(), film.buffer_types().len());
    let per_buffer = film.pixel_count() * PIXEL_VALUES;
    for g in 0..ngroups {
        for b in 0..nbuf {
            let src = r.take(per_buffer * 8)?;
            let dst = film.buffer_mut(g, b).ok_or_else(|| bad("buffer missing"))?;
            let mut finite = true;
            for (d, c) in dst.iter_mut().zip(src.chunks_exact(8)) {
                let mut a = [0u8; 8];
                a.copy_from_slice(c);
                *d = f64::from_le_bytes(a);
                finite &= d.is_finite();
            }
            if !finite {
                return Err(bad("non-finite pixel value"));
            }
        }
    }
    Ok(())
}

/// A film's common header, read and bounded before anything is allocated.
struct Header {
    width: u32,
    height: u32,
    groups: Vec<String>,
    types: Vec<BufferType>,
    rejected: u64,
    counts: Vec<f64>,
}

impl Header {
    /// A cleared film of this layout, holding the header's counts.
    fn new_film(self) -> Result<Film> {
        let mut film = Film::with_buffers(self.width, self.height, self.groups, self.types)
            .map_err(|e| bad(&e.to_string()))?;
        film.set_rejected(self.rejected);
        for (g, n) in self.counts.into_iter().enumerate() {
            film.set_sample_count(g, n);
        }
        Ok(film)
    }

    /// Refuses a film whose layout is not this header's (as `Film::check_layout` words it).
    fn check_fits(&self, film: &Film) -> Result<()> {
        if (film.width(), film.height()) != (self.width, self.height) {
            return Err(bad(&format!(
                "resolution {}x{} against {}x{}",
                film.width(),
                film.height(),
                self.width,
                self.height
            )));
        }
        if film.groups().len() != self.groups.len() {
            return Err(bad(&format!(
                "{} light groups against {}",
                film.groups().len(),
                self.groups.len()
            )));
        }
        if film.buffer_types() != self.types.as_slice() {
            return Err(bad(&format!(
                "buffers {:?} against {:?}",
                film.buffer_types(),
                self.types
            )));
        }
        Ok(())
    }

    /// Puts the header's sample counts and rejection count on a film of its layout.
    fn set_counts(&self, film: &mut Film) {
        film.set_rejected(self.rejected);
        for (g, &n) in self.counts.iter().enumerate() {
            film.set_sample_count(g, n);
        }
    }
}

/// Reads the common header (after the magic), bounded like an upload; with `raw`, only when
/// exactly its raw f64 values follow.
fn read_header(r: &mut Reader, raw: bool) -> Result<Header> {
    let (width, height) = (r.u32()?, r.u32()?);
    luxfarm::film::check_size(width, height).map_err(|e| bad(&e.to_string()))?;
    let ngroups = r.u32()? as usize;
    if ngroups == 0 || ngroups > MAX_GROUPS {
        return Err(bad("bad light group count"));
    }
    let mut groups = Vec::with_capacity(ngroups);
    for _ in 0..ngroups {
        let n = r.u32()? as usize;
        if n > MAX_NAME {
            return Err(bad("group name too long"));
        }
        let name = std::str::from_utf8(r.take(n)?).map_err(|_| bad("group name not UTF-8"))?;
        groups.push(name.to_string());
    }
    let nbuf = r.u32()? as usize;
    if nbuf == 0 || nbuf > MAX_BUFFERS {
        return Err(bad("bad buffer count"));
    }
    let mut types = Vec::with_capacity(nbuf);
    for _ in 0..nbuf {
        let id = r.u32()? as i32;
        types.push(BufferType::from_id(id).ok_or_else(|| bad("unknown buffer type"))?);
    }
    let rejected = r.u64()?;
    let mut counts = Vec::with_capacity(ngroups);
    for _ in 0..ngroups {
        let n = r.f64()?;
        if !(n.is_finite() && n >= 0.0) {
            return Err(bad("sample count not finite"));
        }
        counts.push(n);
    }
    // Bounded like an upload (the gRPC path refuses more than 4 GiB) before allocating.
    let bytes = (width as u64 * height as u64) * (PIXEL_VALUES * ngroups * nbuf * 8) as u64;
    if bytes > MAX_DECODED {
        return Err(bad(&format!("a film of {bytes} bytes is too large")));
    }
    // (Depth and variance sections may follow the values: `read_sections` checks them.)
    if raw && (r.rest() as u64) < bytes {
        let expected = r.pos as u64 + bytes;
        return Err(bad(&format!(
            "{} bytes, expected {expected}",
            r.bytes.len()
        )));
    }
    Ok(Header {
        width,
        height,
        groups,
        types,
        rejected,
        counts,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) fn sample_film() -> Film {
        let mut f = Film::new(3, 2, vec!["a".into(), "b".into()]);
        f.add_splat(0, 1, 1, [0.1, 0.2, 0.3], 1.0, 0.7);
        f.add_splat(1, 2, 0, [1e-30, 5.0, 3.0], 0.5, 1.0);
        f.add_sample_count(6.0);
        f
    }

    #[test]
    fn round_trip_is_exact() {
        let f = sample_film();
        let g = decode(&encode(&f)).unwrap();
        assert_eq!(f, g);
        assert_eq!(decode_as("lxd1", &encode(&f)).unwrap(), f);
        assert_eq!(decode_as("lxd2", &encode_delta(&f)).unwrap(), f);
    }

    fn with_depth(mut f: Film) -> Film {
        let mut z = ZBuffer::new(3, 2);
        z.add(0, 0, 2.5, 1.0);
        z.add(0, 0, 3.5, 1.0);
        z.add(2, 1, 7.25, 1.0);
        f.set_depth(Some(z)).unwrap();
        f
    }

    #[test]
    fn depth_sums_travel_exactly_in_both_encodings() {
        let f = with_depth(sample_film());
        for enc in [encode(&f), encode_delta(&f)] {
            let g = decode(&enc).unwrap();
            assert_eq!(g, f);
            assert_eq!(g.depth().unwrap().raw()[0], 3.0);
            // Into a used film: depth arrives, and leaves with a delta that has none.
            let mut used = sample_film();
            decode_into(&enc, &mut used).unwrap();
            assert_eq!(used.depth(), f.depth());
            decode_into(&encode_delta(&sample_film()), &mut used).unwrap();
            assert!(used.depth().is_none());
        }
        // Merging adds the sums and weights.
        let mut m = f.clone();
        m.merge(&f).unwrap();
        assert_eq!(m.depth().unwrap().weights()[0], 4.0);
        assert_eq!(m.depth().unwrap().raw()[0], 3.0);
    }

    #[test]
    fn bad_depth_sections_are_refused() {
        let f = with_depth(sample_film());
        let plain = encode_delta(&sample_film());
        let full = encode_delta(&f);
        // Truncated, wrong tag, and garbage after the section.
        assert!(decode(&full[..full.len() - 3]).is_err());
        let mut tag = full.clone();
        tag[plain.len()] = b'Q';
        assert!(decode(&tag).is_err());
        let mut extra = full.clone();
        extra.push(0);
        assert!(decode(&extra).is_err());
        // A section of the wrong pixel count, and a negative weight.
        let section = |sums: &[f64], weights: &[f64]| {
            let raw: Vec<u8> = sums
                .iter()
                .chain(weights)
                .flat_map(|v| v.to_le_bytes())
                .collect();
            let packed = zstd::bulk::compress(&raw, 1).unwrap();
            let mut out = plain.clone();
            out.extend_from_slice(DEPTH_TAG);
            out.extend_from_slice(&(packed.len() as u32).to_le_bytes());
            out.extend_from_slice(&packed);
            out
        };
        assert!(decode(&section(&[1.0; 6], &[1.0; 6])).is_ok());
        assert!(decode(&section(&[1.0; 7], &[1.0; 7])).is_err());
        assert!(decode(&section(&[1.0; 6], &[1.0, 1.0, -1.0, 1.0, 1.0, 1.0])).is_err());
        assert!(decode(&section(&[f64::NAN, 1.0, 1.0, 1.0, 1.0, 1.0], &[1.0; 6])).is_err());
    }

    fn with_variance(mut f: Film) -> Film {
        let mut v = VarianceBuffer::new(3, 2);
        v.add(0, 0, 1.0, 1.0);
        v.add(0, 0, 3.0, 1.0);
        v.add(2, 1, 0.5, 0.25);
        // a negative lobe (Mitchell, the default filter) on a dark pixel: negative sums
        v.add(1, 0, 0.5, -0.125);
        f.set_variance(Some(v)).unwrap();
        f
    }

    #[test]
    fn variance_sums_travel_exactly_alone_or_after_depth() {
        for f in [
            with_variance(sample_film()),
            with_variance(with_depth(sample_film())),
        ] {
            for enc in [encode(&f), encode_delta(&f)] {
                let g = decode(&enc).unwrap();
                assert_eq!(g, f);
                assert_eq!(g.variance().unwrap().variance(0, 0), Some(1.0));
                // Into a used film: the sums arrive, and leave with a delta that has none.
                let mut used = sample_film();
                decode_into(&enc, &mut used).unwrap();
                assert_eq!(used.variance(), f.variance());
                assert_eq!(used.depth(), f.depth());
                decode_into(&encode_delta(&sample_film()), &mut used).unwrap();
                assert!(used.variance().is_none() && used.depth().is_none());
            }
        }
        // Merging adds the sums.
        let f = with_variance(sample_film());
        let mut m = f.clone();
        m.merge(&f).unwrap();
        assert_eq!(m.variance().unwrap().sums()[0], [4.0, 8.0, 20.0]);
    }

    #[test]
    fn bad_variance_sections_are_refused() {
        let plain = encode_delta(&sample_film());
        let section = |tag: &[u8; 4], sums: &[f64]| {
            let raw: Vec<u8> = sums.iter().flat_map(|v| v.to_le_bytes()).collect();
            let packed = zstd::bulk::compress(&raw, 1).unwrap();
            let mut out = Vec::new();
            out.extend_from_slice(tag);
            out.extend_from_slice(&(packed.len() as u32).to_le_bytes());
            out.extend_from_slice(&packed);
            out
        };
        let with = |parts: &[Vec<u8>]| -> Vec<u8> {
            let mut out = plain.clone();
            parts.iter().for_each(|p| out.extend_from_slice(p));
            out
        };
        let good = section(VARIANCE_TAG, &[1.0; 18]);
        let depth = section(DEPTH_TAG, &[1.0; 12]);
        assert!(decode(&with(std::slice::from_ref(&good))).is_ok());
        assert!(decode(&with(&[depth.clone(), good.clone()])).is_ok());
        // Twice, or before the depth section, or truncated.
        assert!(decode(&with(&[good.clone(), good.clone()])).is_err());
        assert!(decode(&with(&[good.clone(), depth.clone()])).is_err());
        let full = with(std::slice::from_ref(&good));
        assert!(decode(&full[..full.len() - 2]).is_err());
        // The wrong count and a NaN are refused; negative sums (a filter's negative lobes) are not.
        let mut bad = vec![1.0; 18];
        assert!(decode(&with(&[section(VARIANCE_TAG, &bad[..15])])).is_err());
        bad[3] = -1.0;
        bad[5] = -1.0;
        assert!(decode(&with(&[section(VARIANCE_TAG, &bad)])).is_ok());
        bad[4] = f64::NAN;
        assert!(decode(&with(&[section(VARIANCE_TAG, &bad)])).is_err());
    }

    #[test]
    fn decoding_into_a_used_film_overwrites_everything() {
        let f = sample_film();
        let mut f2 = Film::new(3, 2, vec!["a".into(), "b".into()]);
        f2.add_splat(1, 0, 0, [4.0, 3.0, 2.0], 0.0, 0.25);
        f2.add_rejected(5);
        for enc in [encode(&f), encode_delta(&f)] {
            // A film of the layout holding other values, counts and rejections.
            let mut used = Film::new(3, 2, vec!["x".into(), "y".into()]);
            used.add_splat(0, 2, 1, [9.0, 9.0, 9.0], 1.0, 3.0);
            used.add_sample_count(99.0);
            used.add_rejected(7);
            decode_into(&enc, &mut used).unwrap();
            let mut want = f.clone();
            want.set_group_name(0, "x");
            want.set_group_name(1, "y");
            assert_eq!(used, want);
            // Again with another delta: nothing of the first stays.
            decode_into(&encode_delta(&f2), &mut used).unwrap();
            assert_eq!(used.rejected(), f2.rejected());
            assert_eq!(used.sample_count(1), 0.0);
            assert_eq!(used.buffer(0, 0), f2.buffer(0, 0));
            assert_eq!(used.buffer(1, 0), f2.buffer(1, 0));
        }
        let mut used = Film::new(3, 2, vec!["x".into(), "y".into()]);
        assert!(decode_as_into("lxd2", &encode_delta(&f), &mut used).is_ok());
        assert!(decode_as_into("lxd1", &encode_delta(&f), &mut used).is_err());
    }

    #[test]
    fn decoding_into_another_layout_is_refused() {
        let f = sample_film();
        for other in [
            Film::new(2, 3, vec!["a".into(), "b".into()]),
            Film::new(3, 2, vec!["a".into()]),
            Film::with_buffers(
                3,
                2,
                vec!["a".into(), "b".into()],
                vec![BufferType::PerPixel, BufferType::PerScreen],
            )
            .unwrap(),
        ] {
            let mut other = other;
            let untouched = other.clone();
            let e = decode_into(&encode_delta(&f), &mut other).unwrap_err();
            assert!(e.to_string().contains("against"), "{e}");
            assert_eq!(other, untouched);
        }
    }

    #[test]
    fn streamed_checkpoints_are_the_encoded_bytes() {
        // More values than one streamed chunk, in two groups.
        let mut f = Film::new(40, 30, vec!["a".into(), "b".into()]);
        for i in 0..1200u32 {
            f.add_splat(
                (i % 2) as usize,
                i % 40,
                i / 40,
                [i as f32, 1.0, 0.5],
                1.0,
                0.25,
            );
        }
        let mut streamed = Vec::new();
        encode_to(&f, &mut streamed).unwrap();
        assert_eq!(streamed, encode(&f));
        assert_eq!(decode(&streamed).unwrap(), f);
    }

    #[test]
    fn encoding_name_must_match_the_bytes() {
        let f = sample_film();
        assert!(decode_as("lxd2", &encode(&f)).is_err());
        assert!(decode_as("lxd1", &encode_delta(&f)).is_err());
        assert!(decode_as("flm", &encode(&f)).is_err());
    }

    #[test]
    fn malformed_refused() {
        let f = Film::new(2, 2, vec![]);
        let mut bytes = encode(&f);
        assert!(decode(&bytes[..bytes.len() - 1]).is_err());
        let n = bytes.len();
        bytes[n - 8..].copy_from_slice(&f64::NAN.to_le_bytes());
        assert!(decode(&bytes).is_err());
        assert!(decode(b"LXD1").is_err());
        assert!(decode(b"nope").is_err());
    }
}
