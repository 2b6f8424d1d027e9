//! `heightfield`: a grid of `nu` x `nv` heights `float Pz` over the unit square [0, 1]², turned
//! into a triangle mesh with uv = (x, y), as LuxRender's heightfield.cpp does.

use super::mesh::{MeshData, TriangleMesh};
use super::{Build, BuildError};

pub(crate) fn build(b: &Build) -> Result<TriangleMesh, BuildError> {
    let ps = b.params();
    let nu = ps.int_or("nu", -1);
    let nv = ps.int_or("nv", -1);
    let z = ps.floats("Pz").unwrap_or(&[]);
    if nu < 2 || nv < 2 {
        return Err(b.err(format!(
            "\"nu\" and \"nv\" must be at least 2 (got {nu}, {nv})"
        )));
    }
    let (nu, nv) = (nu as usize, nv as usize);
    if nu.checked_mul(nv) != Some(z.len()) {
        return Err(b.err(format!(
            "\"Pz\" has {} values, nu*nv = {}",
            z.len(),
            nu.saturating_mul(nv)
        )));
    }
    let mut data = MeshData::default();
    let mut uv = Vec::with_capacity(z.len());
    for y in 0..nv {
        for x in 0..nu {
            let (u, v) = (x as f32 / (nu - 1) as f32, y as f32 / (nv - 1) as f32);
            data.p.push([u, v, z[x + y * nu]]);
            uv.push([u, v]);
        }
    }
    data.uv = Some(uv);
    let vert = |x: usize, y: usize| (x + y * nu) as i64;
    for y in 0..nv - 1 {
        for x in 0..nu - 1 {
            data.tris
                .push([vert(x, y), vert(x + 1, y), vert(x + 1, y + 1)]);
            data.tris
                .push([vert(x, y), vert(x + 1, y + 1), vert(x, y + 1)]);
        }
    }
    TriangleMesh::build(b, data)
}
