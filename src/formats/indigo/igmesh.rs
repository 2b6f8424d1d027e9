//! The Indigo binary mesh format (`.igmesh`), versions 1 to 4, read into [`MeshData`].
//!
//! Layout (little endian; `String` is a u32 length, at most 1024, then that many bytes):
//!
//! ```text
//! u32 magic 5456751, u32 version (1..=4)
//! v4:  u32 compression (0 or 1), u32 data_filtering (0 or 1)
//! u32 num_uv_mappings, u32 n + String[n] used_materials, u32 n + (String, u32)[n] uv sets
//! compressed (v4, compression 1): u64 size, then a zstd frame holding the rest:
//! u32 n + f32x3[n] positions, u32 n + f32x3[n] normals (0 or one per position),
//! v3+: u32 uv_layout (0 vertex-major, 1 layer-major), u32 n + f32x2[n] uv pairs,
//! u32 n + u32x7[n] triangles (vertex x3, uv x3, material), v2+: u32 n + u32x9[n] quads
//! ```
//!
//! With data filtering the first vertex and uv index of a face are stored as the difference
//! from the previous face's, the other corners as the difference from the first (wrapping
//! u32 arithmetic). Every count is checked against the bytes that remain (and against
//! `max_array_len`) before anything is allocated; the zstd frame must declare its size, which
//! must fit the byte budget before it is decompressed.

use super::mesh::{Face, MeshData, UvLayout};

const MAGIC: u32 = 5_456_751;
const MAX_STRING: u32 = 1024;
const MAX_STRINGS: u32 = 10_000;
/// Largest decompressed payload accepted, whatever the budget (as Indigo's reader).
pub const MAX_DECOMPRESSED: u64 = 1 << 30;

/// Why an .igmesh could not be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct IgMeshError(pub String);

fn bad(msg: impl Into<String>) -> IgMeshError {
    IgMeshError(msg.into())
}

/// Limits for untrusted files.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Most elements in one array (`ParseOptions::max_array_len`).
    pub max_array_len: u64,
    /// Most bytes a compressed payload may expand to.
    pub max_decompressed: u64,
}

struct Reader<'a> {
    buf: &'a [u8],
    pos: usize,
    limits: Limits,
}

impl<'a> Reader<'a> {
    fn remaining(&self) -> usize {
        self.buf.len() - self.pos
    }

    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], IgMeshError> {
        if n > self.remaining() {
            return Err(bad(format!(
                "truncated: {what} needs {n} bytes, {} remain",
                self.remaining()
            )));
        }
        let s = &self.buf[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    fn u32(&mut self, what: &str) -> Result<u32, IgMeshError> {
        let b = self.take(4, what)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    fn u64(&mut self, what: &str) -> Result<u64, IgMeshError> {
        let b = self.take(8, what)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(b);
        Ok(u64::from_le_bytes(a))
    }

    /// A count followed by `count` records of `size` bytes: checked before allocation.
    fn array(&mut self, size: usize, what: &str) -> Result<(usize, &'a [u8]), IgMeshError> {
        let n = self.u32(what)? as u64;
        if n > self.limits.max_array_len {
            return Err(bad(format!(
                "{n} {what} exceed the limit of {}",
                self.limits.max_array_len
            )));
        }
        let bytes = n * size as u64;
        if bytes > self.remaining() as u64 {
            return Err(bad(format!(
                "truncated or corrupt: {n} {what} need {bytes} bytes, {} remain",
                self.remaining()
            )));
        }
        let data = self.take(bytes as usize, what)?;
        Ok((n as usize, data))
    }

    fn string(&mut self, what: &str) -> Result<String, IgMeshError> {
        let len = self.u32(what)?;
        if len > MAX_STRING {
            return Err(bad(format!(
                "{what}: string of {len} bytes (at most {MAX_STRING})"
            )));
        }
        let b = self.take(len as usize, what)?;
        Ok(String::from_utf8_lossy(b).into_owned())
    }

    fn strings(&mut self, what: &str, with_index: bool) -> Result<Vec<(String, u32)>, IgMeshError> {
        let n = self.u32(what)?;
        // Each entry takes at least 4 bytes (8 with an index).
        let min = if with_index { 8 } else { 4 };
        if n > MAX_STRINGS || n as usize > self.remaining() / min {
            return Err(bad(format!("{n} {what}: too many for the file")));
        }
        let mut v = Vec::with_capacity(n as usize);
        for _ in 0..n {
            let s = self.string(what)?;
            let i = if with_index { self.u32(what)? } else { 0 };
            v.push((s, i));
        }
        Ok(v)
    }
}

fn f32_at(b: &[u8], i: usize) -> f32 {
    f32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]])
}

fn u32_at(b: &[u8], i: usize) -> u32 {
    u32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]])
}

fn vecs<const N: usize>(data: &[u8], what: &str) -> Result<Vec<[f32; N]>, IgMeshError> {
    let mut out = Vec::with_capacity(data.len() / (4 * N));
    for c in data.chunks_exact(4 * N) {
        let mut v = [0f32; N];
        for (k, x) in v.iter_mut().enumerate() {
            *x = f32_at(c, 4 * k);
        }
        if v.iter().any(|x| !x.is_finite()) {
            return Err(bad(format!("{what}: a value is not finite")));
        }
        out.push(v);
    }
    Ok(out)
}

/// Faces of `N` corners: records of `2N + 1` u32, delta-coded when `filtered`.
fn faces<const N: usize>(data: &[u8], filtered: bool) -> Vec<Face<N>> {
    let rec = 4 * (2 * N + 1);
    let mut out = Vec::with_capacity(data.len() / rec);
    let (mut last_v, mut last_uv) = (0u32, 0u32);
    for c in data.chunks_exact(rec) {
        let w = |k: usize| u32_at(c, 4 * k);
        let mut f = Face {
            v: [0; N],
            uv: [0; N],
            mat: w(2 * N),
        };
        for k in 0..N {
            f.v[k] = w(k);
            f.uv[k] = w(N + k);
        }
        if filtered {
            let v0 = f.v[0].wrapping_add(last_v);
            let uv0 = f.uv[0].wrapping_add(last_uv);
            f.v[0] = v0;
            f.uv[0] = uv0;
            for k in 1..N {
                f.v[k] = f.v[k].wrapping_add(v0);
                f.uv[k] = f.uv[k].wrapping_add(uv0);
            }
            last_v = v0;
            last_uv = uv0;
        }
        out.push(f);
    }
    out
}

/// The geometry part (positions to quads) of a version-`version` file.
fn geometry(
    r: &mut Reader,
    m: &mut MeshData,
    version: u32,
    filtered: bool,
) -> Result<(), IgMeshError> {
    m.positions = vecs::<3>(r.array(12, "vertex positions")?.1, "vertex positions")?;
    m.normals = vecs::<3>(r.array(12, "vertex normals")?.1, "vertex normals")?;
    m.uv_layout = if version >= 3 {
        match r.u32("uv layout")? {
            0 => UvLayout::VertexLayer,
            1 => UvLayout::LayerVertex,
            other => return Err(bad(format!("invalid uv layout {other}"))),
        }
    } else {
        UvLayout::VertexLayer
    };
    m.uvs = vecs::<2>(r.array(8, "uv pairs")?.1, "uv pairs")?;
    m.tris = faces::<3>(r.array(28, "triangles")?.1, filtered);
    if version >= 2 {
        m.quads = faces::<4>(r.array(36, "quads")?.1, filtered);
    }
    Ok(())
}

/// Reads a whole .igmesh file.
pub fn read(bytes: &[u8], limits: Limits) -> Result<MeshData, IgMeshError> {
    let mut r = Reader {
        buf: bytes,
        pos: 0,
        limits,
    };
    let magic = r.u32("magic number")?;
    if magic != MAGIC {
        return Err(bad(format!(
            "not an Indigo mesh (magic number {magic}, expected {MAGIC})"
        )));
    }
    let version = r.u32("format version")?;
    if !(1..=4).contains(&version) {
        return Err(bad(format!(
            "unsupported .igmesh version {version} (1 to 4 are read)"
        )));
    }
    let (mut compression, mut filtering) = (0, 0);
    if version >= 4 {
        compression = r.u32("compression flag")?;
        filtering = r.u32("data filtering flag")?;
        if compression > 1 || filtering > 1 {
            return Err(bad(format!(
                "invalid compression/filtering flags {compression}/{filtering}"
            )));
        }
    }
    let mut m = MeshData {
        num_uv_sets: r.u32("uv mapping count")?,
        ..MeshData::default()
    };
    if m.num_uv_sets as u64 > limits.max_array_len {
        return Err(bad(format!("{} uv sets", m.num_uv_sets)));
    }
    m.material_names = r
        .strings("material names", false)?
        .into_iter()
        .map(|(s, _)| s)
        .collect();
    m.uv_set_names = r.strings("uv set names", true)?;
    if compression == 1 {
        let size = r.u64("compressed size")?;
        if size > r.remaining() as u64 {
            return Err(bad(format!(
                "truncated: compressed data of {size} bytes, {} remain",
                r.remaining()
            )));
        }
        let frame = r.take(size as usize, "compressed data")?;
        let content = zstd::zstd_safe::get_frame_content_size(frame)
            .map_err(|_| bad("compressed data is not a zstd frame"))?
            .ok_or_else(|| bad("compressed data does not declare its size"))?;
        let cap = limits.max_decompressed.min(MAX_DECOMPRESSED);
        if content > cap {
            return Err(bad(format!(
                "compressed data claims {content} bytes (at most {cap} accepted)"
            )));
        }
        let data = zstd::bulk::decompress(frame, content as usize)
            .map_err(|e| bad(format!("zstd: {e}")))?;
        if data.len() as u64 != content {
            return Err(bad(format!(
                "compressed data gave {} bytes, {content} declared",
                data.len()
            )));
        }
        let mut inner = Reader {
            buf: &data,
            pos: 0,
            limits,
        };
        geometry(&mut inner, &mut m, version, filtering == 1)?;
    } else {
        geometry(&mut r, &mut m, version, false)?;
    }
    m.validate().map_err(IgMeshError)?;
    Ok(m)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    pub const LIMITS: Limits = Limits {
        max_array_len: 1 << 28,
        max_decompressed: 1 << 30,
    };

    /// Writes a mesh as an .igmesh of `version` (for tests of every version and of damage).
    pub fn write(m: &MeshData, version: u32, compress: bool) -> Vec<u8> {
        let mut h = Vec::new();
        let u = |b: &mut Vec<u8>, v: u32| b.extend_from_slice(&v.to_le_bytes());
        u(&mut h, MAGIC);
        u(&mut h, version);
        if version >= 4 {
            u(&mut h, compress as u32);
            u(&mut h, compress as u32);
        }
        u(&mut h, m.num_uv_sets);
        u(&mut h, m.material_names.len() as u32);
        for s in &m.material_names {
            u(&mut h, s.len() as u32);
            h.extend_from_slice(s.as_bytes());
        }
        u(&mut h, m.uv_set_names.len() as u32);
        for (s, i) in &m.uv_set_names {
            u(&mut h, s.len() as u32);
            h.extend_from_slice(s.as_bytes());
            u(&mut h, *i);
        }
        let mut g = Vec::new();
        let fl = |b: &mut Vec<u8>, v: &[f32]| {
            v.iter().for_each(|x| b.extend_from_slice(&x.to_le_bytes()))
        };
        u(&mut g, m.positions.len() as u32);
        m.positions.iter().for_each(|p| fl(&mut g, p));
        u(&mut g, m.normals.len() as u32);
        m.normals.iter().for_each(|p| fl(&mut g, p));
        if version >= 3 {
            u(&mut g, (m.uv_layout == UvLayout::LayerVertex) as u32);
        }
        u(&mut g, m.uvs.len() as u32);
        m.uvs.iter().for_each(|p| fl(&mut g, p));
        let (mut lv, mut luv) = (0u32, 0u32);
        u(&mut g, m.tris.len() as u32);
        for t in &m.tris {
            if compress {
                u(&mut g, t.v[0].wrapping_sub(lv));
                u(&mut g, t.v[1].wrapping_sub(t.v[0]));
                u(&mut g, t.v[2].wrapping_sub(t.v[0]));
                u(&mut g, t.uv[0].wrapping_sub(luv));
                u(&mut g, t.uv[1].wrapping_sub(t.uv[0]));
                u(&mut g, t.uv[2].wrapping_sub(t.uv[0]));
                lv = t.v[0];
                luv = t.uv[0];
            } else {
                t.v.iter().chain(&t.uv).for_each(|&x| u(&mut g, x));
            }
            u(&mut g, t.mat);
        }
        if version >= 2 {
            let (mut lv, mut luv) = (0u32, 0u32);
            u(&mut g, m.quads.len() as u32);
            for q in &m.quads {
                if compress {
                    u(&mut g, q.v[0].wrapping_sub(lv));
                    for k in 1..4 {
                        u(&mut g, q.v[k].wrapping_sub(q.v[0]));
                    }
                    u(&mut g, q.uv[0].wrapping_sub(luv));
                    for k in 1..4 {
                        u(&mut g, q.uv[k].wrapping_sub(q.uv[0]));
                    }
                    lv = q.v[0];
                    luv = q.uv[0];
                } else {
                    q.v.iter().chain(&q.uv).for_each(|&x| u(&mut g, x));
                }
                u(&mut g, q.mat);
            }
        }
        if compress {
            let z = zstd::bulk::compress(&g, 1).unwrap();
            h.extend_from_slice(&(z.len() as u64).to_le_bytes());
            h.extend_from_slice(&z);
        } else {
            h.extend_from_slice(&g);
        }
        h
    }

    pub fn sample() -> MeshData {
        MeshData {
            positions: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
            ],
            normals: vec![[0.0, 0.0, 1.0]; 5],
            num_uv_sets: 1,
            uv_layout: UvLayout::VertexLayer,
            uvs: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]],
            tris: vec![
                Face {
                    v: [4, 1, 2],
                    uv: [4, 1, 2],
                    mat: 1,
                },
                Face {
                    v: [0, 1, 4],
                    uv: [0, 1, 4],
                    mat: 0,
                },
            ],
            quads: vec![Face {
                v: [0, 1, 2, 3],
                uv: [0, 1, 2, 3],
                mat: 0,
            }],
            material_names: vec!["a".into(), "b".into()],
            uv_set_names: vec![],
        }
    }

    #[test]
    fn every_version_round_trips() {
        for (version, compress) in [(1, false), (2, false), (3, false), (4, false), (4, true)] {
            let mut m = sample();
            if version == 1 {
                m.quads.clear();
            }
            let back = read(&write(&m, version, compress), LIMITS).unwrap();
            assert_eq!(back, m, "version {version} compressed {compress}");
        }
        let mut m = sample();
        m.uv_layout = UvLayout::LayerVertex;
        assert_eq!(
            read(&write(&m, 3, false), LIMITS).unwrap().uv_layout,
            UvLayout::LayerVertex
        );
    }

    #[test]
    fn every_truncation_is_an_error_not_a_panic() {
        for compress in [false, true] {
            let bytes = write(&sample(), 4, compress);
            for n in 0..bytes.len() {
                assert!(read(&bytes[..n], LIMITS).is_err(), "prefix {n}");
            }
        }
    }

    #[test]
    fn huge_counts_are_refused_before_allocation() {
        let mut bytes = write(&sample(), 3, false);
        // The position count sits after magic, version, uv count, 2 names (4+1 each), 0 sets.
        let at = 4 + 4 + 4 + 4 + (4 + 1) * 2 + 4;
        bytes[at..at + 4].copy_from_slice(&u32::MAX.to_le_bytes());
        let unlimited = Limits {
            max_array_len: u64::MAX,
            max_decompressed: 1 << 20,
        };
        let e = read(&bytes, unlimited).unwrap_err();
        assert!(e.0.contains("need"), "{e}");
        assert!(read(&bytes, LIMITS).unwrap_err().0.contains("limit"));
        let small = Limits {
            max_array_len: 3,
            max_decompressed: 1 << 20,
        };
        assert!(read(&write(&sample(), 3, false), small)
            .unwrap_err()
            .0
            .contains("limit"));
    }

    #[test]
    fn decompression_is_bounded_by_the_declared_size_and_the_limit() {
        let bytes = write(&sample(), 4, true);
        let tiny = Limits {
            max_array_len: 1 << 20,
            max_decompressed: 16,
        };
        assert!(read(&bytes, tiny).unwrap_err().0.contains("claims"));
        // A zstd bomb: 8 MiB of zeros in a few hundred bytes, declared.
        let zeros = vec![0u8; 8 << 20];
        let z = zstd::bulk::compress(&zeros, 3).unwrap();
        let mut h = write(&MeshData::default(), 4, true);
        let header = 4 * 5 + 4 + 4;
        h.truncate(header);
        h.extend_from_slice(&(z.len() as u64).to_le_bytes());
        h.extend_from_slice(&z);
        let lim = Limits {
            max_array_len: 1 << 28,
            max_decompressed: 1 << 20,
        };
        assert!(read(&h, lim).unwrap_err().0.contains("claims"));
    }

    #[test]
    fn bad_headers_and_indices_are_errors() {
        let mut b = write(&sample(), 2, false);
        b[0] = 0;
        assert!(read(&b, LIMITS).unwrap_err().0.contains("magic"));
        let mut b = write(&sample(), 2, false);
        b[4] = 9;
        assert!(read(&b, LIMITS).unwrap_err().0.contains("version 9"));
        let mut m = sample();
        m.tris[0].v[1] = 77;
        assert!(read(&write(&m, 2, false), LIMITS)
            .unwrap_err()
            .0
            .contains("77"));
        let mut m = sample();
        m.positions[2][1] = f32::NAN;
        assert!(read(&write(&m, 2, false), LIMITS)
            .unwrap_err()
            .0
            .contains("finite"));
        let mut b = write(&sample(), 3, false);
        let at = 4 + 4 + 4 + 4 + (4 + 1) * 2 + 4 + 4 + 5 * 12 + 4 + 5 * 12;
        b[at..at + 4].copy_from_slice(&7u32.to_le_bytes());
        assert!(read(&b, LIMITS).unwrap_err().0.contains("uv layout"));
    }
}
