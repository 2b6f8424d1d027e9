//! Film encodings of the farm, all lossless (the master's merged film is the exact sum of the
//! acknowledged deltas); FLM (f32, gzip) stays the download and output format.
//!
//! Data flow: a worker's session film -> [`encode_delta`] -> upload chunks -> the master's
//! [`decode_as`] (checked against the upload's `encoding` name) -> a cleared [`Film`] holding
//! exactly the sent sums, which the master adds to the job's film. Checkpoints go through
//! [`encode`] and [`decode`].
//!
//! - `lxd1`: the film's f64 sums and sample counts, little endian, uncompressed. Checkpoints use
//!   it (as fast to write and read as a copy) and old workers upload it.
//! - `lxd2` ([`lxd2`]): the same header, then the f64 values split into channel planes, byte
//!   shuffled and compressed (zstd or lz4) in independent row bands. The worker's upload
//!   encoding ([`DELTA_ENCODING`]): 14-42 % of lxd1's bytes on rendered 1080p Cornell deltas
//!   (box / Mitchell filter), for ~50 ms of encoding and decoding each (`luxfarm bench
//!   transport`).
//!
//! Common header: magic, width u32, height u32, group count u32, per group its name (u32
//! length + UTF-8), buffer count u32, per buffer its type i32, rejected u64, per group the
//! sample count f64. `lxd1` then holds per group and buffer `width*height*5` f64 values.

pub mod lxd2;

use crate::{Result, WireError};
use luxfarm::film::{BufferType, Film, PIXEL_VALUES};

pub use lxd2::Compressor;

const MAGIC: &[u8; 4] = b"LXD1";
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

/// Decodes a delta sent with the named encoding.
pub fn decode_as(encoding: &str, bytes: &[u8]) -> Result<Film> {
    let magic = bytes.get(..4).unwrap_or_default();
    match encoding {
        "lxd1" | "lxd2" if magic.eq_ignore_ascii_case(encoding.as_bytes()) => decode(bytes),
        "lxd1" | "lxd2" => Err(bad(&format!("not an {encoding} film"))),
        other => Err(WireError::UnknownEncoding(other.to_string())),
    }
}

/// Encodes a film as `lxd1` (checkpoints).
pub fn encode(film: &Film) -> Vec<u8> {
    let values =
        film.pixel_count() * PIXEL_VALUES * film.groups().len() * film.buffer_types().len();
    let mut out = Vec::with_capacity(64 + values * 8);
    write_header(&mut out, MAGIC, film);
    for g in 0..film.groups().len() {
        for b in 0..film.buffer_types().len() {
            if let Some(buf) = film.buffer(g, b) {
                for v in buf {
                    out.extend_from_slice(&v.to_le_bytes());
                }
            }
        }
    }
    out
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

/// Decodes an `lxd1` or `lxd2` film (told apart by the magic), refusing malformed input and
/// non-finite or negative counts and values.
pub fn decode(bytes: &[u8]) -> Result<Film> {
    let mut r = Reader { bytes, pos: 0 };
    let magic = r.take(4)?;
    if magic == lxd2::MAGIC {
        let mut film = read_header(&mut r, false)?;
        lxd2::read_values(&mut r, &mut film)?;
        return Ok(film);
    }
    if magic != MAGIC {
        return Err(bad("not an lxd1 or lxd2 film"));
    }
    let mut film = read_header(&mut r, true)?;
    let (ngroups, nbuf) = (film.groups().len(), film.buffer_types().len());
    let per_buffer = film.pixel_count() * PIXEL_VALUES;
    for g in 0..ngroups {
        for b in 0..nbuf {
            let src = r.take(per_buffer * 8)?;
            let dst = film.buffer_mut(g, b).ok_or_else(|| bad("buffer missing"))?;
            for (d, c) in dst.iter_mut().zip(src.chunks_exact(8)) {
                let mut a = [0u8; 8];
                a.copy_from_slice(c);
                *d = finite(f64::from_le_bytes(a))?;
            }
        }
    }
    Ok(film)
}

/// A pixel value, refused when not finite.
fn finite(v: f64) -> Result<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(bad("non-finite pixel value"))
    }
}

/// Reads the common header (after the magic) and allocates the cleared film it describes;
/// with `raw`, only when exactly its raw f64 values follow.
fn read_header(r: &mut Reader, raw: bool) -> Result<Film> {
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
    if raw && r.rest() as u64 != bytes {
        let expected = r.pos as u64 + bytes;
        return Err(bad(&format!(
            "{} bytes, expected {expected}",
            r.bytes.len()
        )));
    }
    let mut film =
        Film::with_buffers(width, height, groups, types).map_err(|e| bad(&e.to_string()))?;
    film.add_rejected(rejected);
    for (g, n) in counts.into_iter().enumerate() {
        film.set_sample_count(g, n);
    }
    Ok(film)
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
