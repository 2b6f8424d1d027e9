//! Indigo meshes as data ([`MeshData`]: positions, normals, uv sets, triangles and quads with
//! per-corner uv indices and a material index), and their conversion into LuxRender
//! `trianglemesh` parameter lists, one per material.
//!
//! ```text
//! <embedded> / .igmesh / .obj / .ply --> MeshData --split per material, unweld (vertex, uv)-->
//!     ParamSet { point P, integer triindices, integer quadindices, normal N, float uv }
//! ```
//!
//! LuxRender stores one uv per vertex, Indigo one uv index per corner: a vertex used with
//! two uvs becomes two vertices. Meshes with `normal_smoothing` off lose their normals
//! (geometric normals, as Indigo renders them); with it on and no normals in the data, vertex
//! normals are the average of the adjacent face normals.

use super::ctx::{err, Ctx};
use super::node::{parse_numbers, Elem};
use crate::lxs::{Loc, LxsError, LxsErrorKind, ParamSet, ParamValue};
use std::collections::HashMap;

/// How uv pairs of several sets are laid out (the .igmesh `uv_layout` field).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UvLayout {
    /// uv 0 of every set, then uv 1 of every set, ...
    VertexLayer,
    /// every uv of set 0, then every uv of set 1, ...
    LayerVertex,
}

/// A face: vertex indices, uv indices (one per corner), material index.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Face<const N: usize> {
    pub v: [u32; N],
    pub uv: [u32; N],
    pub mat: u32,
}

/// A mesh as Indigo describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshData {
    pub positions: Vec<[f32; 3]>,
    /// Empty, or one per position.
    pub normals: Vec<[f32; 3]>,
    pub num_uv_sets: u32,
    pub uv_layout: UvLayout,
    pub uvs: Vec<[f32; 2]>,
    pub tris: Vec<Face<3>>,
    pub quads: Vec<Face<4>>,
    /// Material names by material index (`model` dialect; may be empty).
    pub material_names: Vec<String>,
    /// uv set names exposed to materials, with their set index.
    pub uv_set_names: Vec<(String, u32)>,
}

impl Default for MeshData {
    fn default() -> Self {
        MeshData {
            positions: Vec::new(),
            normals: Vec::new(),
            num_uv_sets: 0,
            uv_layout: UvLayout::VertexLayer,
            uvs: Vec::new(),
            tris: Vec::new(),
            quads: Vec::new(),
            material_names: Vec::new(),
            uv_set_names: Vec::new(),
        }
    }
}

impl MeshData {
    /// uvs per set.
    pub fn uvs_per_set(&self) -> usize {
        match self.num_uv_sets {
            0 => 0,
            n => self.uvs.len() / n as usize,
        }
    }

    /// The uv of corner index `i` in set `set`.
    pub fn uv(&self, i: u32, set: u32) -> Option<[f32; 2]> {
        let n = self.num_uv_sets as usize;
        if set as usize >= n {
            return None;
        }
        let k = match self.uv_layout {
            UvLayout::VertexLayer => (i as usize).checked_mul(n)?.checked_add(set as usize)?,
            UvLayout::LayerVertex => (set as usize)
                .checked_mul(self.uvs_per_set())?
                .checked_add(i as usize)?,
        };
        self.uvs.get(k).copied()
    }

    /// Checks the invariants every reader must give: normals count, index ranges.
    pub fn validate(&self) -> Result<(), String> {
        if !self.normals.is_empty() && self.normals.len() != self.positions.len() {
            return Err(format!(
                "{} normals for {} vertex positions (need none or one each)",
                self.normals.len(),
                self.positions.len()
            ));
        }
        if self.num_uv_sets > 0 && !self.uvs.len().is_multiple_of(self.num_uv_sets as usize) {
            return Err(format!(
                "{} uv pairs is not a multiple of the {} uv sets",
                self.uvs.len(),
                self.num_uv_sets
            ));
        }
        let nv = self.positions.len();
        let nuv = self.uvs_per_set();
        let check = |v: &[u32], uv: &[u32]| -> Result<(), String> {
            if let Some(bad) = v.iter().find(|&&i| i as usize >= nv) {
                return Err(format!("vertex index {bad} out of range ({nv} vertices)"));
            }
            if self.num_uv_sets > 0 {
                if let Some(bad) = uv.iter().find(|&&i| i as usize >= nuv) {
                    return Err(format!("uv index {bad} out of range ({nuv} uvs per set)"));
                }
            }
            Ok(())
        };
        for t in &self.tris {
            check(&t.v, &t.uv)?;
        }
        for q in &self.quads {
            check(&q.v, &q.uv)?;
        }
        Ok(())
    }

    /// The material indices used by faces, sorted.
    pub fn materials_used(&self) -> Vec<u32> {
        let mut m: Vec<u32> = self
            .tris
            .iter()
            .map(|t| t.mat)
            .chain(self.quads.iter().map(|q| q.mat))
            .collect();
        m.sort_unstable();
        m.dedup();
        m
    }

    /// Area of the faces of material `mat` after `xf` (a point transform).
    pub fn area(&self, mat: u32, xf: &dyn Fn([f32; 3]) -> glam::DVec3) -> f64 {
        let p = |i: u32| xf(self.positions[i as usize]);
        let tri = |a: u32, b: u32, c: u32| 0.5 * (p(b) - p(a)).cross(p(c) - p(a)).length();
        let t: f64 = self
            .tris
            .iter()
            .filter(|f| f.mat == mat)
            .map(|f| tri(f.v[0], f.v[1], f.v[2]))
            .sum();
        let q: f64 = self
            .quads
            .iter()
            .filter(|f| f.mat == mat)
            .map(|f| tri(f.v[0], f.v[1], f.v[2]) + tri(f.v[0], f.v[2], f.v[3]))
            .sum();
        t + q
    }

    /// The `trianglemesh` parameters of the faces of material `mat`, or None when it has none.
    /// `uv_set` picks the uv set, `smooth` keeps (or computes) vertex normals, `scale`
    /// multiplies positions (the mesh's own `scale`).
    pub fn to_params(&self, mat: u32, uv_set: u32, smooth: bool, scale: f32) -> Option<ParamSet> {
        let mut remap: HashMap<(u32, u32), i32> = HashMap::new();
        let mut p: Vec<[f32; 3]> = Vec::new();
        let mut n: Vec<[f32; 3]> = Vec::new();
        let mut uv: Vec<f32> = Vec::new();
        let has_uv = uv_set < self.num_uv_sets;
        let normals = smooth.then(|| self.vertex_normals());
        let mut corner = |v: u32, t: u32| -> i32 {
            let key = (v, if has_uv { t } else { 0 });
            *remap.entry(key).or_insert_with(|| {
                let pos = self.positions[v as usize];
                p.push(pos.map(|c| c * scale));
                if let Some(ns) = &normals {
                    n.push(ns[v as usize]);
                }
                if has_uv {
                    uv.extend(self.uv(t, uv_set).unwrap_or([0.0, 0.0]));
                }
                (p.len() - 1) as i32
            })
        };
        let mut tris = Vec::new();
        for f in self.tris.iter().filter(|f| f.mat == mat) {
            for k in 0..3 {
                tris.push(corner(f.v[k], f.uv[k]));
            }
        }
        let mut quads = Vec::new();
        for f in self.quads.iter().filter(|f| f.mat == mat) {
            for k in 0..4 {
                quads.push(corner(f.v[k], f.uv[k]));
            }
        }
        if tris.is_empty() && quads.is_empty() {
            return None;
        }
        let mut ps = ParamSet::new();
        ps.add("P", ParamValue::Point(p));
        if !tris.is_empty() {
            ps.add("triindices", ParamValue::Integer(tris));
        }
        if !quads.is_empty() {
            ps.add("quadindices", ParamValue::Integer(quads));
        }
        if normals.is_some() {
            ps.add("N", ParamValue::Normal(n));
        }
        if has_uv {
            ps.add("uv", ParamValue::Float(uv));
        }
        Some(ps)
    }

    /// The mesh's normals, or the average of adjacent face normals when it has none.
    fn vertex_normals(&self) -> Vec<[f32; 3]> {
        if !self.normals.is_empty() {
            return self.normals.clone();
        }
        use glam::Vec3;
        let mut acc = vec![Vec3::ZERO; self.positions.len()];
        let p = |i: u32| Vec3::from_array(self.positions[i as usize]);
        let mut add = |t: [u32; 3]| {
            let n = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
            for i in t {
                acc[i as usize] += n;
            }
        };
        for f in &self.tris {
            add(f.v);
        }
        for f in &self.quads {
            add([f.v[0], f.v[1], f.v[2]]);
            add([f.v[0], f.v[2], f.v[3]]);
        }
        acc.iter()
            .map(|n| n.normalize_or(Vec3::Z).to_array())
            .collect()
    }
}

fn f32s<const N: usize>(
    text: &str,
    loc: &Loc,
    ctx: &Ctx,
    what: &str,
) -> Result<[f32; N], LxsError> {
    let v = parse_numbers(text, loc, ctx)?;
    if v.len() != N {
        return Err(err(
            LxsErrorKind::WrongValueCount,
            loc,
            format!("{what} needs {N} numbers, got {}", v.len()),
        ));
    }
    let mut out = [0f32; N];
    for (o, x) in out.iter_mut().zip(&v) {
        *o = *x as f32;
    }
    Ok(out)
}

/// Reads an `<embedded>` mesh: `expose_uv_set`, `vertex` (attributes `pos`, `normal`,
/// `uv0`..`uv3`) and `triangle_set` (`material_name`, `tri`, and `quad`) elements. Triangles
/// index the vertices defined before them.
pub fn read_embedded(e: &Elem, ctx: &Ctx) -> Result<MeshData, LxsError> {
    let mut m = MeshData::default();
    let mut with_normals = 0usize;
    let mut uv_cols: [Vec<[f32; 2]>; 4] = Default::default();
    let mut mat_index: HashMap<String, u32> = HashMap::new();
    let count = e.children.len();
    ctx.check_count(count as u64, "mesh elements", &e.loc)?;
    for c in &e.children {
        match c.name.as_str() {
            "expose_uv_set" => {
                c.mark_used();
                let idx = c.need(ctx, "index")?.int(ctx)?;
                let name = c.need(ctx, "name")?.str().to_string();
                let idx = u32::try_from(idx).ok().filter(|&i| i < 4).ok_or_else(|| {
                    err(
                        LxsErrorKind::InvalidValue,
                        &c.loc,
                        format!("uv set index {idx} must be 0 to 3"),
                    )
                })?;
                m.uv_set_names.push((name, idx));
            }
            "vertex" => {
                c.mark_used();
                let pos = c.attr("pos").ok_or_else(|| {
                    err(
                        LxsErrorKind::WrongValueCount,
                        &c.loc,
                        "<vertex> needs a pos attribute",
                    )
                })?;
                m.positions.push(f32s::<3>(pos, &c.loc, ctx, "vertex pos")?);
                if let Some(n) = c.attr("normal") {
                    m.normals.push(f32s::<3>(n, &c.loc, ctx, "vertex normal")?);
                    with_normals += 1;
                }
                for (k, col) in uv_cols.iter_mut().enumerate() {
                    if let Some(t) = c.attr(&format!("uv{k}")) {
                        let uv = f32s::<2>(t, &c.loc, ctx, "vertex uv")?;
                        col.resize(m.positions.len() - 1, [0.0, 0.0]);
                        col.push(uv);
                    }
                }
            }
            "triangle_set" => {
                c.mark_used();
                let name = c.child_str(ctx, "material_name").unwrap_or("").to_string();
                let next = mat_index.len() as u32;
                let mat = *mat_index.entry(name.clone()).or_insert_with(|| {
                    m.material_names.push(name.clone());
                    next
                });
                for t in c.all("tri") {
                    let v = indices::<3>(t, ctx, m.positions.len())?;
                    m.tris.push(Face { v, uv: v, mat });
                }
                for q in c.all("quad") {
                    let v = indices::<4>(q, ctx, m.positions.len())?;
                    m.quads.push(Face { v, uv: v, mat });
                }
            }
            _ => {}
        }
    }
    if with_normals != 0 && with_normals != m.positions.len() {
        ctx.warn(
            &e.loc,
            "only some vertices have a normal: normals ignored for this mesh",
        );
        m.normals.clear();
    }
    let sets = uv_cols
        .iter()
        .rposition(|c| !c.is_empty())
        .map_or(0, |k| k + 1);
    m.num_uv_sets = sets as u32;
    m.uv_layout = UvLayout::LayerVertex;
    for col in uv_cols.iter_mut().take(sets) {
        col.resize(m.positions.len(), [0.0, 0.0]);
        m.uvs.extend_from_slice(col);
    }
    m.validate()
        .map_err(|msg| err(LxsErrorKind::InvalidValue, &e.loc, msg))?;
    Ok(m)
}

fn indices<const N: usize>(e: &Elem, ctx: &Ctx, nv: usize) -> Result<[u32; N], LxsError> {
    let v = e.n_nums(ctx, N)?;
    let mut out = [0u32; N];
    for (o, x) in out.iter_mut().zip(&v) {
        if *x < 0.0 || x.fract() != 0.0 || *x >= nv as f64 {
            return Err(err(
                LxsErrorKind::InvalidValue,
                &e.loc,
                format!("vertex index {x} is not one of the {nv} vertices defined before it"),
            ));
        }
        *o = *x as u32;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad_mesh() -> MeshData {
        MeshData {
            positions: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ],
            num_uv_sets: 1,
            uvs: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]],
            tris: vec![
                Face {
                    v: [0, 1, 2],
                    uv: [0, 1, 2],
                    mat: 0,
                },
                Face {
                    v: [0, 2, 3],
                    uv: [4, 2, 3],
                    mat: 1,
                },
            ],
            ..MeshData::default()
        }
    }

    #[test]
    fn faces_split_per_material_and_vertices_unweld_per_uv() {
        let m = quad_mesh();
        m.validate().unwrap();
        assert_eq!(m.materials_used(), vec![0, 1]);
        let a = m.to_params(0, 0, false, 2.0).unwrap();
        assert_eq!(a.points("P").unwrap().len(), 3);
        assert_eq!(a.points("P").unwrap()[1], [2.0, 0.0, 0.0]);
        assert_eq!(a.ints("triindices").unwrap(), &[0, 1, 2]);
        let b = m.to_params(1, 0, true, 1.0).unwrap();
        // Vertex 0 with uv 4 is a new vertex of its own.
        assert_eq!(b.floats("uv").unwrap(), &[0.5, 0.5, 1.0, 1.0, 0.0, 1.0]);
        assert_eq!(b.normals("N").unwrap()[0], [0.0, 0.0, 1.0]);
        assert!(m.to_params(7, 0, false, 1.0).is_none());
        let id = |p: [f32; 3]| glam::DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64);
        assert!((m.area(0, &id) - 0.5).abs() < 1e-9);
    }

    #[test]
    fn uv_layouts_address_the_same_uvs() {
        let mut m = MeshData {
            num_uv_sets: 2,
            uvs: vec![[0.0, 0.0], [10.0, 10.0], [1.0, 1.0], [11.0, 11.0]],
            ..MeshData::default()
        };
        assert_eq!(m.uv(1, 1), Some([11.0, 11.0]));
        m.uv_layout = UvLayout::LayerVertex;
        assert_eq!(m.uv(1, 1), Some([11.0, 11.0]));
        assert_eq!(m.uv(0, 1), Some([1.0, 1.0]));
        assert_eq!(m.uv(0, 2), None);
    }

    #[test]
    fn out_of_range_indices_are_refused() {
        let mut m = quad_mesh();
        m.tris[0].v[2] = 9;
        assert!(m.validate().unwrap_err().contains("vertex index 9"));
        let mut m = quad_mesh();
        m.tris[0].uv[2] = 5;
        assert!(m.validate().unwrap_err().contains("uv index 5"));
        let mut m = quad_mesh();
        m.normals = vec![[0.0, 0.0, 1.0]];
        assert!(m.validate().is_err());
    }
}
