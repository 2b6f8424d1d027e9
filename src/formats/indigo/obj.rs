//! Wavefront OBJ meshes (external Indigo meshes), read into [`MeshData`].
//!
//! ```text
//! v x y z | vt u v | vn x y z | usemtl name | f v[/vt][/vn] ... (polygons fanned into triangles,
//! negative indices relative to the end)  --> positions, uvs (one set), faces, material names
//! ```
//!
//! OBJ normals are indexed per corner; they are kept only when every corner uses the normal
//! of its own position (else the mesh's smoothing recomputes them). `g`, `o`, `s`, `mtllib`
//! and other statements do not change the geometry and are skipped. Counts are bounded by the
//! file's size, which the byte budget bounds.

use super::mesh::{Face, MeshData, UvLayout};
use std::collections::HashMap;

fn num(tok: Option<&str>, line: usize) -> Result<f32, String> {
    let t = tok.ok_or_else(|| format!("line {line}: missing number"))?;
    let v: f32 = t.parse().map_err(|_| {
        format!(
            "line {line}: \"{}\" is not a number",
            t.chars().take(32).collect::<String>()
        )
    })?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("line {line}: number is not finite"))
    }
}

/// An OBJ index (1-based, negative from the end) into a list of `len` items.
fn index(tok: &str, len: usize, line: usize) -> Result<u32, String> {
    let i: i64 = tok.parse().map_err(|_| {
        format!(
            "line {line}: \"{}\" is not an index",
            tok.chars().take(32).collect::<String>()
        )
    })?;
    let k = if i > 0 { i - 1 } else { len as i64 + i };
    if i == 0 || k < 0 || k >= len as i64 {
        return Err(format!(
            "line {line}: index {i} out of range ({len} defined)"
        ));
    }
    Ok(k as u32)
}

/// Parses OBJ text.
pub fn parse(text: &str) -> Result<MeshData, String> {
    let mut m = MeshData {
        num_uv_sets: 0,
        uv_layout: UvLayout::VertexLayer,
        ..MeshData::default()
    };
    let mut normals: Vec<[f32; 3]> = Vec::new();
    let mut normal_of: Vec<Option<u32>> = Vec::new();
    let mut normals_consistent = true;
    let mut mats: HashMap<String, u32> = HashMap::new();
    let mut mat = 0u32;
    let mut any_uv = false;
    for (n, raw) in text.lines().enumerate() {
        let line = n + 1;
        let l = raw.split('#').next().unwrap_or("").trim();
        let mut t = l.split_whitespace();
        match t.next() {
            Some("v") => {
                m.positions.push([
                    num(t.next(), line)?,
                    num(t.next(), line)?,
                    num(t.next(), line)?,
                ]);
                normal_of.push(None);
            }
            Some("vt") => {
                let u = num(t.next(), line)?;
                let v = t
                    .next()
                    .map(|x| num(Some(x), line))
                    .transpose()?
                    .unwrap_or(0.0);
                m.uvs.push([u, v]);
            }
            Some("vn") => normals.push([
                num(t.next(), line)?,
                num(t.next(), line)?,
                num(t.next(), line)?,
            ]),
            Some("usemtl") => {
                let name = t.collect::<Vec<_>>().join(" ");
                let next = mats.len() as u32;
                mat = *mats.entry(name.clone()).or_insert_with(|| {
                    m.material_names.push(name);
                    next
                });
            }
            Some("f") => {
                let mut corners: Vec<(u32, u32)> = Vec::new();
                for c in t {
                    let mut parts = c.split('/');
                    let v = index(parts.next().unwrap_or(""), m.positions.len(), line)?;
                    let vt = match parts.next() {
                        Some(s) if !s.is_empty() => {
                            any_uv = true;
                            index(s, m.uvs.len(), line)?
                        }
                        _ => 0,
                    };
                    if let Some(s) = parts.next().filter(|s| !s.is_empty()) {
                        let vn = index(s, normals.len(), line)?;
                        match normal_of[v as usize] {
                            None => normal_of[v as usize] = Some(vn),
                            Some(prev)
                                if prev != vn && normals[prev as usize] != normals[vn as usize] =>
                            {
                                normals_consistent = false
                            }
                            Some(_) => {}
                        }
                    } else {
                        normals_consistent = false;
                    }
                    corners.push((v, vt));
                }
                if corners.len() < 3 {
                    return Err(format!("line {line}: a face needs at least 3 vertices"));
                }
                for k in 1..corners.len() - 1 {
                    let (a, b, c) = (corners[0], corners[k], corners[k + 1]);
                    m.tris.push(Face {
                        v: [a.0, b.0, c.0],
                        uv: [a.1, b.1, c.1],
                        mat,
                    });
                }
            }
            _ => {}
        }
    }
    if any_uv && !m.uvs.is_empty() {
        m.num_uv_sets = 1;
    } else {
        m.uvs.clear();
    }
    if normals_consistent && !normals.is_empty() && normal_of.iter().all(Option::is_some) {
        m.normals = normal_of
            .iter()
            .map(|i| normals[i.unwrap_or(0) as usize])
            .collect();
    }
    m.validate()?;
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quads_fan_and_materials_index() {
        let text = "# cube face\nmtllib x.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n\
                    usemtl red\nf 1/1/1 2/2/1 3/3/1 4/4/1\nusemtl blue\nf -4//1 -2//1 -1//1\n";
        let m = parse(text).unwrap();
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.tris.len(), 3);
        assert_eq!(m.tris[1].v, [0, 2, 3]);
        assert_eq!(m.tris[2].mat, 1);
        assert_eq!(
            m.material_names,
            vec!["red".to_string(), "blue".to_string()]
        );
        assert_eq!(m.num_uv_sets, 1);
        assert_eq!(m.normals.len(), 4);
    }

    #[test]
    fn bad_obj_is_an_error() {
        for bad in [
            "v 0 0\n",
            "v 0 0 0\nf 1 2 3\n",
            "v 0 0 0\nf 1\n",
            "v 0 0 x\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
        ] {
            assert!(parse(bad).is_err(), "{bad}");
        }
    }
}
