//! `stlmesh`: an STL file, binary (detected as LuxRender does: 80-byte header, face count,
//! and a file length of exactly 84 + 50 bytes per face) or ASCII (`facet ... vertex x y z`).
//! Parameters: `string filename` (relative to the scene directory), `bool recenter_mesh`
//! (default false: move the bounding box centre to the origin).

use super::mesh::{MeshData, TriangleMesh};
use super::trianglemesh::check_unsupported;
use super::{Build, BuildError};

/// LuxRender's limit on binary STL faces.
const MAX_FACES: usize = 16 * 1024 * 1024;

pub(crate) fn build(b: &Build) -> Result<TriangleMesh, BuildError> {
    let name = b
        .params()
        .string("filename")
        .ok_or_else(|| b.err("missing \"string filename\""))?
        .to_string();
    let recenter = b.params().bool_or("recenter_mesh", false);
    let _ = b.params().string("type");
    check_unsupported(b)?;
    tracing::info!("loading STL mesh {name}");
    let bytes = b
        .ctx
        .files
        .read(&name)
        .map_err(|e| b.err(format!("cannot read STL file: {e}")))?;
    let mut p = parse(&bytes).map_err(|e| b.err(format!("STL file \"{name}\": {e}")))?;
    if recenter {
        recenter_points(&mut p);
    }
    let tris = (0..p.len() as i64 / 3)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    TriangleMesh::build(
        b,
        MeshData {
            p,
            tris,
            ..MeshData::default()
        },
    )
}

fn recenter_points(p: &mut [[f32; 3]]) {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for v in p.iter() {
        for k in 0..3 {
            lo[k] = lo[k].min(v[k]);
            hi[k] = hi[k].max(v[k]);
        }
    }
    for v in p.iter_mut() {
        for k in 0..3 {
            v[k] -= 0.5 * (lo[k] + hi[k]);
        }
    }
}

/// Triangle corners, three per face.
pub fn parse(bytes: &[u8]) -> Result<Vec<[f32; 3]>, String> {
    if let Some(n) = binary_face_count(bytes) {
        return Ok(parse_binary(bytes, n));
    }
    parse_ascii(bytes)
}

fn binary_face_count(bytes: &[u8]) -> Option<usize> {
    let c = bytes.get(80..84)?;
    let n = u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as usize;
    (n > 0 && n <= MAX_FACES && bytes.len() == 84 + 50 * n).then_some(n)
}

fn parse_binary(bytes: &[u8], n: usize) -> Vec<[f32; 3]> {
    let f = |at: usize| {
        let s = &bytes[at..at + 4];
        f32::from_le_bytes([s[0], s[1], s[2], s[3]])
    };
    let mut p = Vec::with_capacity(3 * n);
    for face in 0..n {
        let base = 84 + 50 * face + 12; // skip the facet normal
        for corner in 0..3 {
            let at = base + 12 * corner;
            p.push([f(at), f(at + 4), f(at + 8)]);
        }
    }
    p
}

fn parse_ascii(bytes: &[u8]) -> Result<Vec<[f32; 3]>, String> {
    let text = std::str::from_utf8(bytes).map_err(|_| "neither binary STL nor text")?;
    let mut words = text.split_whitespace();
    if !words
        .next()
        .is_some_and(|w| w.eq_ignore_ascii_case("solid"))
    {
        return Err("ASCII STL must start with \"solid\"".into());
    }
    let mut p = Vec::new();
    while let Some(w) = words.next() {
        if w.eq_ignore_ascii_case("endsolid") {
            break;
        }
        if w.eq_ignore_ascii_case("vertex") {
            let mut v = [0.0f32; 3];
            for c in &mut v {
                let t = words.next().ok_or("truncated vertex")?;
                *c = t.parse().map_err(|_| format!("bad number \"{t}\""))?;
            }
            p.push(v);
        }
    }
    if p.is_empty() || p.len() % 3 != 0 {
        return Err(format!(
            "{} vertices is not a whole number of triangles",
            p.len()
        ));
    }
    Ok(p)
}
