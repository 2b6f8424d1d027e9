//! The film delta transport and checkpoint encoding ("lxd1"): the film's f64 sums and sample
//! counts, little endian, uncompressed. Lossless (the master's merged film is the exact sum of
//! the acknowledged deltas) and as fast to decode as a copy; FLM (f32, gzip) stays the
//! download and output format.
//!
//! Layout: magic `LXD1`, width u32, height u32, group count u32, per group its name (u32
//! length + UTF-8), buffer count u32, per buffer its type i32, rejected u64, per group the
//! sample count f64, then per group and buffer `width*height*5` f64 values.

use crate::error::{Result, ServerError};
use luxfarm::film::{BufferType, Film, PIXEL_VALUES};

const MAGIC: &[u8; 4] = b"LXD1";
const MAX_GROUPS: usize = 1024;
const MAX_BUFFERS: usize = 8;
const MAX_NAME: usize = 4096;

/// Encodes a film.
pub fn encode(film: &Film) -> Vec<u8> {
    let values =
        film.pixel_count() * PIXEL_VALUES * film.groups().len() * film.buffer_types().len();
    let mut out = Vec::with_capacity(64 + values * 8);
    out.extend_from_slice(MAGIC);
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
}

fn bad(why: &str) -> ServerError {
    ServerError::BadRequest(format!("film delta unreadable: {why}"))
}

/// Decodes a film, refusing malformed input and non-finite or negative counts.
pub fn decode(bytes: &[u8]) -> Result<Film> {
    let mut r = Reader { bytes, pos: 0 };
    if r.take(4)? != MAGIC {
        return Err(bad("not an lxd1 film"));
    }
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
    let per_buffer = width as usize * height as usize * PIXEL_VALUES;
    let expected = r.pos + 8 + ngroups * 8 + ngroups * nbuf * per_buffer * 8;
    if bytes.len() != expected {
        return Err(bad(&format!("{} bytes, expected {expected}", bytes.len())));
    }
    let mut film =
        Film::with_buffers(width, height, groups, types).map_err(|e| bad(&e.to_string()))?;
    film.add_rejected(r.u64()?);
    for g in 0..ngroups {
        let n = r.f64()?;
        if !(n.is_finite() && n >= 0.0) {
            return Err(bad("sample count not finite"));
        }
        film.set_sample_count(g, n);
    }
    for g in 0..ngroups {
        for b in 0..nbuf {
            let src = r.take(per_buffer * 8)?;
            let dst = film.buffer_mut(g, b).ok_or_else(|| bad("buffer missing"))?;
            for (d, c) in dst.iter_mut().zip(src.chunks_exact(8)) {
                let mut a = [0u8; 8];
                a.copy_from_slice(c);
                let v = f64::from_le_bytes(a);
                if !v.is_finite() {
                    return Err(bad("non-finite pixel value"));
                }
                *d = v;
            }
        }
    }
    Ok(film)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_is_exact() {
        let mut f = Film::new(3, 2, vec!["a".into(), "b".into()]);
        f.add_splat(0, 1, 1, [0.1, 0.2, 0.3], 1.0, 0.7);
        f.add_splat(1, 2, 0, [1e-30, 5.0, 3.0], 0.5, 1.0);
        f.add_sample_count(6.0);
        let g = decode(&encode(&f)).unwrap();
        assert_eq!(f, g);
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
