//! `trianglemesh` and `mesh` (also `waldtrianglemesh`, `barytrianglemesh`, `loopsubdiv`): all
//! read by LuxRender's mesh.cpp. Parameters: `point P`, `integer triindices` (or `indices`),
//! `integer quadindices`, `normal N`, `float uv` (or `st`), `float C` (vertex colours, three
//! per vertex) and `float A` (vertex alphas), `string tritype`/`quadtype`/
//! `acceltype` (LuxRender-internal choices, read and ignored); the subdivision and
//! displacement parameters (`nsubdivlevels`/`nlevels`, `displacementmap`, `dm*`) are read by
//! [`super::loopsubdiv`] when the mesh is built.

use super::mesh::{MeshData, TriangleMesh};
use super::{Build, BuildError};

pub(crate) fn build(b: &Build) -> Result<TriangleMesh, BuildError> {
    let ps = b.params();
    let p = ps
        .points("P")
        .ok_or_else(|| b.err("missing \"point P\""))?
        .to_vec();
    let tris_raw = ps
        .ints("triindices")
        .or_else(|| ps.ints("indices"))
        .unwrap_or(&[]);
    let quads_raw = ps.ints("quadindices").unwrap_or(&[]);
    if tris_raw.is_empty() && quads_raw.is_empty() {
        return Err(b.err("missing \"integer indices\" (or triindices/quadindices)"));
    }
    if !tris_raw.len().is_multiple_of(3) {
        b.warn(&format!(
            "{} triangle indices is not a multiple of 3: the last {} are ignored",
            tris_raw.len(),
            tris_raw.len() % 3
        ));
    }
    if !quads_raw.len().is_multiple_of(4) {
        b.warn("quad index count is not a multiple of 4: the remainder is ignored");
    }
    let tris = tris_raw
        .chunks_exact(3)
        .map(|c| [c[0] as i64, c[1] as i64, c[2] as i64])
        .collect();
    let quads = quads_raw
        .chunks_exact(4)
        .map(|c| [c[0] as i64, c[1] as i64, c[2] as i64, c[3] as i64])
        .collect();
    let uv_raw = ps.floats("uv").or_else(|| ps.floats("st"));
    let uv = match uv_raw {
        Some(f) if f.len() == 2 * p.len() => {
            Some(f.chunks_exact(2).map(|c| [c[0], c[1]]).collect())
        }
        Some(f) => {
            b.warn(&format!(
                "{} uv values for {} vertices (need 2 per vertex): ignoring uv",
                f.len(),
                p.len()
            ));
            None
        }
        None => None,
    };
    let n = ps.normals("N").map(|n| n.to_vec());
    let cols = ps
        .floats("C")
        .map(|c| c.chunks_exact(3).map(|v| [v[0], v[1], v[2]]).collect());
    let alphas = ps.floats("A").map(|a| a.to_vec());
    check_unsupported(b)?;
    TriangleMesh::build(
        b,
        MeshData {
            p,
            n,
            uv,
            cols,
            alphas,
            tris,
            quads,
        },
    )
}

/// Reads the LuxRender-internal mesh options (accepted, no effect here) and warns about the
/// ones that are not implemented.
pub(crate) fn check_unsupported(b: &Build) -> Result<(), BuildError> {
    let ps = b.params();
    for name in ["tritype", "quadtype", "acceltype", "name"] {
        let _ = ps.string(name);
    }
    let _ = ps.float("gamma");
    if ps.bool_or("generatetangents", false) {
        b.warn("\"generatetangents\" is ignored (tangent-space normal maps are not implemented)");
    }
    for tangent in ["S", "tangents"] {
        if ps.get(tangent).is_some() {
            b.warn(&format!("\"{tangent}\" (tangents) is ignored"));
        }
    }
    Ok(())
}
