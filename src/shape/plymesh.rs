//! `plymesh`: a PLY file (ASCII, binary little- or big-endian) with vertex positions, optional
//! normals (`nx ny nz`), texture coordinates (`s t`, else `u v`), vertex colours (`red green
//! blue`, 8-bit values divided by 255) and alphas (`alpha`), triangles and quads
//! (`vertex_indices`). Parameters as LuxRender's plymesh.cpp: `string filename` (relative to
//! the scene directory), `bool smooth` (default false). As in LuxRender, when `smooth` is set
//! or the file has no normal per vertex, vertex normals are the average of the adjacent faces'
//! normals.

use super::mesh::{MeshData, TriangleMesh};
use super::trianglemesh::check_unsupported;
use super::{Build, BuildError};
use glam::Vec3;

pub(crate) fn build(b: &Build) -> Result<TriangleMesh, BuildError> {
    let name = b
        .params()
        .string("filename")
        .ok_or_else(|| b.err("missing \"string filename\""))?
        .to_string();
    let smooth = b.params().bool_or("smooth", false);
    check_unsupported(b)?;
    tracing::info!("loading PLY mesh {name}");
    let bytes = b
        .ctx
        .files
        .read(&name)
        .map_err(|e| b.err(format!("cannot read PLY file: {e}")))?;
    let mut data = parse(&bytes).map_err(|e| b.err(format!("PLY file \"{name}\": {e}")))?;
    if data.n.is_some() && smooth {
        tracing::debug!("plymesh: \"smooth\" overrides the file's normals");
    }
    if smooth || data.n.is_none() {
        data.n = Some(smooth_normals(&data));
    }
    TriangleMesh::build(b, data)
}

/// Per-vertex average of the unit normals of the faces around it (quads count as their two
/// triangles (0,1,2) and (0,2,3)).
pub fn smooth_normals(data: &MeshData) -> Vec<[f32; 3]> {
    let mut acc = vec![Vec3::ZERO; data.p.len()];
    let p = |i: i64| Vec3::from_array(data.p.get(i as usize).copied().unwrap_or_default());
    let mut add = |t: [i64; 3]| {
        let n = (p(t[1]) - p(t[0]))
            .cross(p(t[2]) - p(t[0]))
            .normalize_or_zero();
        for i in t {
            if let Some(a) = acc.get_mut(i as usize) {
                *a += n;
            }
        }
    };
    for t in &data.tris {
        add(*t);
    }
    for q in &data.quads {
        add([q[0], q[1], q[2]]);
        add([q[0], q[2], q[3]]);
    }
    acc.iter()
        .map(|n| n.normalize_or_zero().to_array())
        .collect()
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Format {
    Ascii,
    Le,
    Be,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(s: &str) -> Option<Scalar> {
        Some(match s {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
}

#[derive(Clone, Debug)]
struct Property {
    name: String,
    /// `Some(count type)` for list properties.
    list: Option<Scalar>,
    ty: Scalar,
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: usize,
    props: Vec<Property>,
}

/// Parses a whole PLY file.
pub fn parse(bytes: &[u8]) -> Result<MeshData, String> {
    let (format, elements, body) = header(bytes)?;
    let mut reader = Reader {
        format,
        bytes: body,
        pos: 0,
    };
    let mut data = MeshData::default();
    let mut skipped_faces = 0usize;
    for el in &elements {
        match el.name.as_str() {
            "vertex" => read_vertices(&mut reader, el, &mut data)?,
            "face" => skipped_faces += read_faces(&mut reader, el, &mut data)?,
            _ => {
                for _ in 0..el.count {
                    for p in &el.props {
                        reader.skip_property(p)?;
                    }
                }
            }
        }
    }
    if skipped_faces > 0 {
        tracing::warn!("PLY: {skipped_faces} faces with other than 3 or 4 vertices ignored");
    }
    if data.p.is_empty() {
        return Err("no vertices".into());
    }
    if data.tris.is_empty() && data.quads.is_empty() {
        return Err("no triangles or quads".into());
    }
    Ok(data)
}

fn header(bytes: &[u8]) -> Result<(Format, Vec<Element>, &[u8]), String> {
    const END: &[u8] = b"end_header";
    let end = bytes
        .windows(END.len())
        .position(|w| w == END)
        .ok_or("no end_header")?;
    let mut body_start = end + END.len();
    if bytes.get(body_start) == Some(&b'\r') {
        body_start += 1;
    }
    if bytes.get(body_start) == Some(&b'\n') {
        body_start += 1;
    }
    let text = std::str::from_utf8(&bytes[..end]).map_err(|_| "header is not text")?;
    let mut lines = text.lines();
    if lines.next().map(str::trim) != Some("ply") {
        return Err("not a PLY file (missing \"ply\" magic)".into());
    }
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    for line in lines {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.as_slice() {
            ["format", f, _] => {
                format = Some(match *f {
                    "ascii" => Format::Ascii,
                    "binary_little_endian" => Format::Le,
                    "binary_big_endian" => Format::Be,
                    other => return Err(format!("unknown format {other}")),
                })
            }
            ["element", name, count] => elements.push(Element {
                name: name.to_string(),
                count: count
                    .parse()
                    .map_err(|_| format!("bad element count {count}"))?,
                props: Vec::new(),
            }),
            ["property", "list", ct, it, name] => {
                let el = elements.last_mut().ok_or("property before element")?;
                el.props.push(Property {
                    name: name.to_string(),
                    list: Some(Scalar::parse(ct).ok_or(format!("bad type {ct}"))?),
                    ty: Scalar::parse(it).ok_or(format!("bad type {it}"))?,
                });
            }
            ["property", ty, name] => {
                let el = elements.last_mut().ok_or("property before element")?;
                el.props.push(Property {
                    name: name.to_string(),
                    list: None,
                    ty: Scalar::parse(ty).ok_or(format!("bad type {ty}"))?,
                });
            }
            [] | ["comment", ..] | ["obj_info", ..] => {}
            _ => return Err(format!("unexpected header line \"{line}\"")),
        }
    }
    let format = format.ok_or("missing format line")?;
    // Every element item takes at least one byte: reject absurd counts before allocating.
    let body = &bytes[body_start..];
    let total: usize = elements.iter().map(|e| e.count).sum();
    if total > body.len() {
        return Err(format!(
            "header declares {total} items but only {} bytes follow",
            body.len()
        ));
    }
    Ok((format, elements, body))
}

struct Reader<'a> {
    format: Format,
    bytes: &'a [u8],
    pos: usize,
}

impl Reader<'_> {
    fn value(&mut self, ty: Scalar) -> Result<f64, String> {
        if self.format == Format::Ascii {
            return self.ascii_token();
        }
        let n = ty.size();
        let s = self
            .bytes
            .get(self.pos..self.pos + n)
            .ok_or("unexpected end of file")?;
        self.pos += n;
        let mut b = [0u8; 8];
        b[..n].copy_from_slice(s);
        if self.format == Format::Be {
            b[..n].reverse();
        }
        Ok(match ty {
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::U8 => b[0] as f64,
            Scalar::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F64 => f64::from_le_bytes(b),
        })
    }

    fn ascii_token(&mut self) -> Result<f64, String> {
        while self.pos < self.bytes.len() && self.bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        let start = self.pos;
        while self.pos < self.bytes.len() && !self.bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        let tok = std::str::from_utf8(&self.bytes[start..self.pos]).map_err(|_| "bad token")?;
        if tok.is_empty() {
            return Err("unexpected end of file".into());
        }
        tok.parse::<f64>()
            .map_err(|_| format!("bad number \"{tok}\""))
    }

    fn list_len(&mut self, ct: Scalar) -> Result<usize, String> {
        let n = self.value(ct)?;
        if !(0.0..=1e6).contains(&n) || n.fract() != 0.0 {
            return Err(format!("bad list length {n}"));
        }
        Ok(n as usize)
    }

    fn skip_property(&mut self, p: &Property) -> Result<(), String> {
        let n = match p.list {
            Some(ct) => self.list_len(ct)?,
            None => 1,
        };
        for _ in 0..n {
            self.value(p.ty)?;
        }
        Ok(())
    }
}

fn read_vertices(r: &mut Reader, el: &Element, data: &mut MeshData) -> Result<(), String> {
    let find = |n: &str| {
        el.props
            .iter()
            .position(|p| p.name == n && p.list.is_none())
    };
    let xyz = [find("x"), find("y"), find("z")];
    let [Some(ix), Some(iy), Some(iz)] = xyz else {
        return Err("vertex element without x, y, z".into());
    };
    let nrm = match [find("nx"), find("ny"), find("nz")] {
        [Some(a), Some(b), Some(c)] => Some([a, b, c]),
        _ => None,
    };
    let uv = match [find("s"), find("t"), find("u"), find("v")] {
        [Some(a), Some(b), _, _] => Some([a, b]),
        [_, _, Some(a), Some(b)] => Some([a, b]),
        _ => None,
    };
    // Vertex colours as LuxRender's plymesh reads them: 8-bit values are divided by 255.
    let rgb = match [find("red"), find("green"), find("blue")] {
        [Some(a), Some(b), Some(c)] => Some([a, b, c]),
        _ => None,
    };
    let alpha = find("alpha");
    let unit = |k: usize, v: f64| -> f32 {
        match el.props.get(k).map(|p| p.ty) {
            Some(Scalar::U8) => (v / 255.0) as f32,
            Some(Scalar::U16) => (v / 65535.0) as f32,
            _ => v as f32,
        }
    };
    let mut vals = vec![0.0f64; el.props.len()];
    let (mut ps, mut ns, mut uvs) = (Vec::new(), Vec::new(), Vec::new());
    let (mut cols, mut alphas) = (Vec::new(), Vec::new());
    for _ in 0..el.count {
        for (k, p) in el.props.iter().enumerate() {
            if p.list.is_some() {
                r.skip_property(p)?;
            } else {
                vals[k] = r.value(p.ty)?;
            }
        }
        ps.push([vals[ix] as f32, vals[iy] as f32, vals[iz] as f32]);
        if let Some([a, b, c]) = nrm {
            ns.push([vals[a] as f32, vals[b] as f32, vals[c] as f32]);
        }
        if let Some([a, b]) = uv {
            uvs.push([vals[a] as f32, vals[b] as f32]);
        }
        if let Some([a, b, c]) = rgb {
            cols.push([unit(a, vals[a]), unit(b, vals[b]), unit(c, vals[c])]);
        }
        if let Some(a) = alpha {
            alphas.push(unit(a, vals[a]));
        }
    }
    data.p = ps;
    data.n = nrm.map(|_| ns);
    data.uv = uv.map(|_| uvs);
    data.cols = rgb.map(|_| cols);
    data.alphas = alpha.map(|_| alphas);
    Ok(())
}

/// Reads the faces; returns how many were skipped (not triangles or quads).
fn read_faces(r: &mut Reader, el: &Element, data: &mut MeshData) -> Result<usize, String> {
    let idx = el
        .props
        .iter()
        .position(|p| p.list.is_some() && (p.name == "vertex_indices" || p.name == "vertex_index"))
        .ok_or("face element without vertex_indices")?;
    let mut skipped = 0;
    let mut face = Vec::with_capacity(4);
    for _ in 0..el.count {
        for (k, p) in el.props.iter().enumerate() {
            if k != idx {
                r.skip_property(p)?;
                continue;
            }
            let n = r.list_len(p.list.unwrap_or(Scalar::U8))?;
            face.clear();
            for _ in 0..n {
                face.push(r.value(p.ty)? as i64);
            }
            match face.as_slice() {
                [a, b, c] => data.tris.push([*a, *b, *c]),
                [a, b, c, d] => data.quads.push([*a, *b, *c, *d]),
                _ => skipped += 1,
            }
        }
    }
    Ok(skipped)
}
