//! FLM v0 files, byte-compatible with LuxRender: a gzip stream holding a little-endian header
//! (see `flm_header`) and, per buffer group, a double sample count then per buffer
//! configuration, row by row, five f32 per pixel (X, Y, Z, alpha, weight sums).
//!
//! Reading decodes the stream row by row straight into the film (no second copy of the
//! decompressed file). Merging a delta into an existing film first decodes the delta's f32
//! data into a reusable scratch buffer ([`FlmDelta`]) and validates it, then adds it in
//! parallel: a corrupt or truncated upload is refused without touching the accumulated film.
//! Deltas held in memory decode fastest with [`FlmDelta::decode_slice`] (libdeflate). Writing converts
//! row by row into the compressor; files are written atomically
//! ([`crate::atomic_write`]).

use super::flm_header::{params_for, read_f64, FlmHeader};
use super::{BufferType, Film, FilmError, FilmParams, PIXEL_VALUES};
use crate::atomic_write::write_atomic;
use flate2::read::GzDecoder;
use flate2::write::GzEncoder;
use flate2::Compression;
use rayon::prelude::*;
use std::fs::File;
use std::io::{BufReader, Read, Write};
use std::path::Path;

/// gzip level of written FLMs: 0, stored blocks. Film sums are noisy floats that deflate
/// shrinks by only 12-26% (levels 1-4), while stored gzip decodes and encodes about 6 times
/// faster (`luxfarm bench flm`); LuxRender reads it like any gzip stream. Use
/// [`write_flm_level`] for a compressed file.
pub const DEFAULT_LEVEL: u32 = 0;

/// Deflate expands at most about 1032:1 (a 258-byte match coded in 2 bits); a gzip stream
/// claiming more output than this times its size is not a real stream.
const MAX_DEFLATE_RATIO: u64 = 1032;

fn corrupt(context: &'static str) -> impl Fn(std::io::Error) -> FilmError {
    move |source| FilmError::Corrupt { context, source }
}

/// Reads the whole gzip stream to its end so that the CRC and length are checked, and
/// refuses data after the film.
fn finish<R: Read>(r: &mut R) -> Result<(), FilmError> {
    let mut b = [0u8; 64];
    let n = r.read(&mut b).map_err(corrupt("end of stream"))?;
    if n > 0 {
        return Err(FilmError::BadHeader(
            "data continues after the last buffer".into(),
        ));
    }
    Ok(())
}

fn sample_count<R: Read>(r: &mut R, group: usize) -> Result<f64, FilmError> {
    let n = read_f64(r, "sample count")?;
    if !n.is_finite() || n < 0.0 {
        return Err(FilmError::BadHeader(format!(
            "group {group} has sample count {n}"
        )));
    }
    Ok(n)
}

/// Reads an FLM (gzip-compressed, as LuxRender writes it) into a new film.
pub fn read_flm(r: impl Read) -> Result<(Film, FlmHeader), FilmError> {
    let mut r = GzDecoder::new(BufReader::with_capacity(1 << 16, r));
    let header = FlmHeader::read(&mut r)?;
    let mut film = Film::with_buffers(
        header.width,
        header.height,
        header.group_names(),
        header.buffer_types.clone(),
    )?;
    let width = header.width as usize;
    let mut row = vec![0u8; width * PIXEL_VALUES * 4];
    for g in 0..header.groups as usize {
        let n = sample_count(&mut r, g)?;
        film.set_sample_count(g, n);
        for b in 0..header.buffer_types.len() {
            let Some(buf) = film.buffer_mut(g, b) else {
                return Err(FilmError::BadHeader("buffer layout".into()));
            };
            for (y, dst) in buf.chunks_exact_mut(width * PIXEL_VALUES).enumerate() {
                r.read_exact(&mut row).map_err(corrupt("pixel data"))?;
                decode_row(&row, dst).map_err(|x| non_finite(g, b, x, y, width))?;
            }
        }
    }
    finish(&mut r)?;
    Ok((film, header))
}

fn non_finite(group: usize, buffer: usize, index: usize, y: usize, width: usize) -> FilmError {
    FilmError::NonFinite {
        group,
        buffer,
        x: (index / PIXEL_VALUES % width.max(1)) as u32,
        y: y as u32,
    }
}

/// Converts one row of little-endian f32 into f64; `Err(i)`: value i is not finite.
fn decode_row(row: &[u8], dst: &mut [f64]) -> Result<(), usize> {
    let mut ok = true;
    for (d, b) in dst.iter_mut().zip(row.chunks_exact(4)) {
        let v = f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        ok &= v.is_finite();
        *d = f64::from(v);
    }
    if ok {
        return Ok(());
    }
    Err(dst.iter().position(|v| !v.is_finite()).unwrap_or(0))
}

/// A decoded FLM delta: header, sample counts and the raw little-endian f32 sums, validated
/// and ready to be added. Reuse one to merge many deltas without reallocating.
#[derive(Clone, Debug, Default)]
pub struct FlmDelta {
    pub header: Option<FlmHeader>,
    pub samples: Vec<f64>,
    /// Decompressed bytes; group g's pixel data starts at `offsets[g]`.
    bytes: Vec<u8>,
    offsets: Vec<usize>,
}

fn group_len(h: &FlmHeader) -> usize {
    h.width as usize * h.height as usize * PIXEL_VALUES * 4 * h.buffer_types.len()
}

impl FlmDelta {
    /// Decodes an FLM from a stream (zlib-rs inflate), reusing this delta's memory.
    pub fn decode(&mut self, r: impl Read) -> Result<&FlmHeader, FilmError> {
        self.decode_for(r, None)
    }

    /// As [`Self::decode`]; with `into`, a header whose layout differs from that film's is
    /// refused before any pixel memory is allocated. The pixel bytes grow as they are
    /// inflated, so a small stream whose header declares a huge film fails at its end
    /// instead of allocating what the header claims.
    fn decode_for(&mut self, r: impl Read, into: Option<&Film>) -> Result<&FlmHeader, FilmError> {
        self.header = None;
        let mut r = GzDecoder::new(BufReader::with_capacity(1 << 16, r));
        let header = FlmHeader::read(&mut r)?;
        if let Some(film) = into {
            film.check_flm_layout(&header)?;
        }
        let len = group_len(&header);
        self.bytes.clear();
        self.samples.clear();
        self.offsets.clear();
        for g in 0..header.groups as usize {
            self.samples.push(sample_count(&mut r, g)?);
            self.offsets.push(self.bytes.len());
            let got = (&mut r)
                .take(len as u64)
                .read_to_end(&mut self.bytes)
                .map_err(corrupt("pixel data"))?;
            if got != len {
                return Err(corrupt("pixel data")(std::io::Error::new(
                    std::io::ErrorKind::UnexpectedEof,
                    format!("group {g} holds {got} of its {len} bytes"),
                )));
            }
        }
        finish(&mut r)?;
        self.validate(header)
    }

    /// Decodes an FLM held in memory with libdeflate's one-shot gzip decompressor (faster
    /// than streaming). The header is parsed first, so the output size is known and checked
    /// against the gzip trailer before anything large is allocated.
    pub fn decode_slice(&mut self, gz: &[u8]) -> Result<&FlmHeader, FilmError> {
        self.decode_slice_for(gz, None)
    }

    /// As [`Self::decode_slice`]; with `into`, a header whose layout differs from that
    /// film's is refused before anything large is allocated. Whatever the trailer says, a
    /// header declaring more than deflate can expand the stream to is refused too.
    fn decode_slice_for(
        &mut self,
        gz: &[u8],
        into: Option<&Film>,
    ) -> Result<&FlmHeader, FilmError> {
        self.header = None;
        let header = FlmHeader::read(&mut GzDecoder::new(gz))?;
        if let Some(film) = into {
            film.check_flm_layout(&header)?;
        }
        let mut head = Vec::new();
        header.write(&mut head)?;
        let len = group_len(&header);
        let total = head.len() + header.groups as usize * (8 + len);
        if total as u64 > (gz.len() as u64).saturating_mul(MAX_DEFLATE_RATIO) {
            return Err(FilmError::Corrupt {
                context: "gzip stream",
                source: std::io::Error::new(
                    std::io::ErrorKind::InvalidData,
                    format!(
                        "{} compressed bytes cannot hold the {total} bytes the header declares",
                        gz.len()
                    ),
                ),
            });
        }
        let trailer = gz
            .len()
            .checked_sub(4)
            .and_then(|i| gz.get(i..))
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        if trailer != Some(total as u32) {
            return Err(FilmError::Corrupt {
                context: "gzip trailer",
                source: std::io::Error::new(
                    std::io::ErrorKind::InvalidData,
                    format!("stream length does not match the header ({total} bytes expected)"),
                ),
            });
        }
        self.bytes.clear();
        self.bytes.resize(total, 0);
        let n = libdeflater::Decompressor::new()
            .gzip_decompress(gz, &mut self.bytes)
            .map_err(|e| FilmError::Corrupt {
                context: "gzip stream",
                source: std::io::Error::new(std::io::ErrorKind::InvalidData, format!("{e:?}")),
            })?;
        if n != total {
            return Err(FilmError::BadHeader(format!(
                "{n} bytes of data, {total} expected"
            )));
        }
        self.samples.clear();
        self.offsets.clear();
        for g in 0..header.groups as usize {
            let at = head.len() + g * (8 + len);
            let mut b = [0u8; 8];
            b.copy_from_slice(&self.bytes[at..at + 8]);
            let count = f64::from_le_bytes(b);
            if !count.is_finite() || count < 0.0 {
                return Err(FilmError::BadHeader(format!(
                    "group {g} has sample count {count}"
                )));
            }
            self.samples.push(count);
            self.offsets.push(at + 8);
        }
        self.validate(header)
    }

    fn validate(&mut self, header: FlmHeader) -> Result<&FlmHeader, FilmError> {
        let len = group_len(&header);
        for (g, &o) in self.offsets.iter().enumerate() {
            let data = &self.bytes[o..o + len];
            if let Some(i) = first_non_finite(data) {
                let w = header.width as usize;
                let per_buffer = w * header.height as usize * PIXEL_VALUES;
                let px = i % per_buffer / PIXEL_VALUES;
                return Err(FilmError::NonFinite {
                    group: g,
                    buffer: i / per_buffer,
                    x: (px % w) as u32,
                    y: (px / w) as u32,
                });
            }
        }
        Ok(self.header.insert(header))
    }

    /// Group g's sums as little-endian f32 bytes (5 per pixel, buffer after buffer).
    fn group_bytes(&self, g: usize) -> Option<&[u8]> {
        let h = self.header.as_ref()?;
        let o = *self.offsets.get(g)?;
        self.bytes.get(o..o + group_len(h))
    }
}

/// Index (in f32 values) of the first non-finite value of little-endian f32 bytes.
fn first_non_finite(bytes: &[u8]) -> Option<usize> {
    const CHUNK: usize = 1 << 16;
    bytes
        .par_chunks(CHUNK * 4)
        .enumerate()
        .find_map_first(|(c, s)| {
            s.chunks_exact(4)
                .position(|b| !f32::from_le_bytes([b[0], b[1], b[2], b[3]]).is_finite())
                .map(|i| c * CHUNK + i)
        })
}

impl Film {
    /// Whether an FLM header describes this film's layout.
    pub fn check_flm_layout(&self, h: &FlmHeader) -> Result<(), FilmError> {
        if h.width != self.width() || h.height != self.height() {
            return Err(FilmError::Mismatch(format!(
                "FLM is {}x{}, film is {}x{}",
                h.width,
                h.height,
                self.width(),
                self.height()
            )));
        }
        if h.groups as usize != self.groups().len() {
            return Err(FilmError::Mismatch(format!(
                "FLM has {} light groups, film has {}",
                h.groups,
                self.groups().len()
            )));
        }
        if h.buffer_types != self.buffer_types() {
            return Err(FilmError::Mismatch(format!(
                "FLM buffers {:?}, film buffers {:?}",
                h.buffer_types,
                self.buffer_types()
            )));
        }
        Ok(())
    }

    /// Adds a decoded delta (sums and sample counts), in parallel.
    pub fn add_delta(&mut self, d: &FlmDelta) -> Result<(), FilmError> {
        let Some(h) = &d.header else {
            return Err(FilmError::Mismatch("empty delta".into()));
        };
        self.check_flm_layout(h)?;
        let per_buffer = self.pixel_count() * PIXEL_VALUES * 4;
        for g in 0..self.groups().len() {
            for b in 0..self.buffer_types().len() {
                let src = d
                    .group_bytes(g)
                    .and_then(|s| s.get(b * per_buffer..(b + 1) * per_buffer));
                let (Some(src), Some(dst)) = (src, self.buffer_mut(g, b)) else {
                    return Err(FilmError::Mismatch("delta data size".into()));
                };
                add_f32_le(dst, src);
            }
            let n = self.sample_count(g) + d.samples.get(g).copied().unwrap_or(0.0);
            self.set_sample_count(g, n);
        }
        Ok(())
    }
}

/// `dst += src` where src holds little-endian f32, in parallel.
fn add_f32_le(dst: &mut [f64], src: &[u8]) {
    const CHUNK: usize = 1 << 15;
    dst.par_chunks_mut(CHUNK)
        .zip(src.par_chunks(CHUNK * 4))
        .for_each(|(d, s)| {
            d.iter_mut()
                .zip(s.chunks_exact(4))
                .for_each(|(a, b)| *a += f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])))
        });
}

/// Decodes an FLM held in memory (libdeflate) and adds it to `film`; on any error the film
/// is unchanged.
pub fn merge_flm_bytes(film: &mut Film, gz: &[u8]) -> Result<FlmHeader, FilmError> {
    let mut delta = FlmDelta::default();
    delta.decode_slice_for(gz, Some(film))?;
    film.add_delta(&delta)?;
    delta
        .header
        .ok_or_else(|| FilmError::Mismatch("empty delta".into()))
}

/// Decodes an FLM delta from a stream and adds it to `film`; on any error the film is
/// unchanged.
pub fn merge_flm(film: &mut Film, r: impl Read) -> Result<FlmHeader, FilmError> {
    let mut delta = FlmDelta::default();
    delta.decode_for(r, Some(film))?;
    film.add_delta(&delta)?;
    delta
        .header
        .ok_or_else(|| FilmError::Mismatch("empty delta".into()))
}

/// Writes a film as an FLM with the parameters LuxRender writes (gzip level [`DEFAULT_LEVEL`]).
pub fn write_flm(film: &Film, params: &FilmParams, w: impl Write) -> Result<(), FilmError> {
    write_flm_level(film, params, w, DEFAULT_LEVEL)
}

/// The header an FLM of this film carries.
pub fn header_for(film: &Film, params: &FilmParams) -> FlmHeader {
    FlmHeader {
        width: film.width(),
        height: film.height(),
        groups: film.groups().len() as u32,
        buffer_types: film.buffer_types().to_vec(),
        params: params_for(params, film.groups()),
    }
}

/// Writes a film as an FLM at a given gzip level (0-9). A sum beyond f32's range is refused
/// ([`FilmError::Overflow`], naming the pixel) instead of being written as an infinity that
/// every FLM reader refuses; what was already written to `w` is then incomplete.
pub fn write_flm_level(
    film: &Film,
    params: &FilmParams,
    w: impl Write,
    level: u32,
) -> Result<(), FilmError> {
    let mut enc = GzEncoder::new(w, Compression::new(level.min(9)));
    header_for(film, params).write(&mut enc)?;
    const CHUNK: usize = 1 << 18;
    let mut bytes = vec![0u8; CHUNK * 4];
    for g in 0..film.groups().len() {
        enc.write_all(&film.sample_count(g).to_le_bytes())?;
        for b in 0..film.buffer_types().len() {
            let Some(buf) = film.buffer(g, b) else {
                continue;
            };
            for (c, src) in buf.chunks(CHUNK).enumerate() {
                let out = &mut bytes[..src.len() * 4];
                let overflow = out
                    .par_chunks_mut(4096 * 4)
                    .zip(src.par_chunks(4096))
                    .map(|(o, s)| {
                        let mut ok = true;
                        for (d, &v) in o.chunks_exact_mut(4).zip(s) {
                            let f = v as f32;
                            ok &= f.is_finite();
                            d.copy_from_slice(&f.to_le_bytes());
                        }
                        !ok
                    })
                    .reduce(|| false, |a, b| a || b);
                if overflow {
                    return Err(overflow_error(film, g, b, c * CHUNK, src));
                }
                enc.write_all(out)?;
            }
        }
    }
    enc.finish()?.flush()?;
    Ok(())
}

/// The error for the first value of `src` (starting at value `start` of its buffer) that f32
/// cannot hold.
fn overflow_error(
    film: &Film,
    group: usize,
    buffer: usize,
    start: usize,
    src: &[f64],
) -> FilmError {
    let i = src
        .iter()
        .position(|v| !(*v as f32).is_finite())
        .unwrap_or(0);
    let px = (start + i) / PIXEL_VALUES;
    let w = film.width().max(1) as usize;
    FilmError::Overflow {
        value: src.get(i).copied().unwrap_or(f64::INFINITY),
        group,
        buffer,
        x: (px % w) as u32,
        y: (px / w) as u32,
    }
}

/// Reads an FLM file.
pub fn read_flm_file(path: &Path) -> Result<(Film, FlmHeader), FilmError> {
    let f = File::open(path).map_err(|e| FilmError::file(path, e))?;
    read_flm(f)
}

/// Writes a film to an FLM file atomically.
pub fn write_flm_file(path: &Path, film: &Film, params: &FilmParams) -> Result<(), FilmError> {
    write_atomic(path, |w| write_flm(film, params, w))
}

/// The buffer types LuxRender's fleximage uses for an ordinary render.
pub fn default_buffers() -> Vec<BufferType> {
    vec![BufferType::PerPixel]
}
