//! `object "name" ... group ... end group ... end object`: polygon geometry, and the meshes
//! luxfarm renders from it.
//!
//! ```text
//! object block --parse--> MiObject { flags, groups: [Group] }
//! Group: vectors (x y z ...), vertex records (v i [n i] [t i ...] ...),
//!        polygons (c|p [tag | "material"] refs... [hole refs...])
//!     --mesh_parts--> one MeshPart (points, normals, uvs, triangles) per material reference
//! ```
//!
//! A group lists every vector once — positions, normals and texture coordinates alike —
//! then vertex records that pick them by index (`v` position, `n` normal, `t` texture; the
//! first texture space is kept, `d`/`m`/`u`/`b` vectors are read and ignored), then polygons
//! over the records (0-based). In a `tagged` object each polygon's first number is its
//! material tag, an index into its instance's material array; otherwise a polygon may name
//! its material. `c` polygons are convex (fanned); `p` polygons are triangulated by ear
//! clipping with their holes ([`super::triangulate`]). Every index is checked where it is
//! written. Free-form surfaces, subdivision surfaces and hair are not supported: the object
//! is skipped with a located note.

use super::cursor::{Cursor, MiResult};
use super::lexer::Tok;
use super::triangulate::{triangulate, Method};
use crate::lxs::{Diagnostic, Loc, LxsError, LxsErrorKind};
use glam::DVec3;
use std::collections::HashMap;

/// The material a polygon asks for.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum PolyMat {
    /// The instance's (or an inherited) material.
    Inherit,
    /// Index into the instance's material array (tagged objects).
    Tag(u32),
    /// A material named on the polygon.
    Name(String),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexRec {
    pub v: u32,
    pub n: Option<u32>,
    pub t: Option<u32>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Poly {
    /// First of its vertex-record references in `Group::refs`.
    pub start: u32,
    /// References of the outer loop.
    pub outer: u32,
    /// Lengths of its hole loops, which follow the outer loop.
    pub holes: Vec<u32>,
    /// Index into `Group::mats`.
    pub mat: u32,
    pub convex: bool,
    pub line: u32,
    pub col: u32,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Group {
    pub loc: Loc,
    pub vectors: Vec<[f32; 3]>,
    pub verts: Vec<VertexRec>,
    pub refs: Vec<u32>,
    pub polys: Vec<Poly>,
    pub mats: Vec<PolyMat>,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct MiObject {
    pub name: String,
    pub loc: Loc,
    pub tagged: bool,
    pub visible: bool,
    pub groups: Vec<Group>,
    /// Why the object has no polygon geometry luxfarm can render, if so.
    pub unsupported: Option<(String, Loc)>,
}

/// Keywords that begin free-form or other non-polygon geometry.
const UNSUPPORTED: &[&str] = &[
    "basis",
    "surface",
    "curve",
    "spacecurve",
    "faces",
    "subdivision",
    "hair",
    "trilist",
    "trilist2",
    "approximate",
];

/// Reads the block after `object "name"` up to and including `end object`.
pub fn parse(c: &mut Cursor, name: String, loc: Loc, max_len: usize) -> MiResult<MiObject> {
    let mut obj = MiObject {
        name,
        loc,
        visible: true,
        ..MiObject::default()
    };
    loop {
        let at = c.loc()?;
        let w = match c.peek()? {
            Tok::Word(w) => *w,
            _ => return Err(c.unexpected("an object flag, 'group' or 'end object'")),
        };
        c.next()?;
        match w {
            "end" => {
                c.expect_word("object")?;
                return Ok(obj);
            }
            "group" => {
                if obj.groups.len() >= max_len {
                    return Err(c.error(LxsErrorKind::ArrayTooLong, "too many groups"));
                }
                obj.groups.push(group(c, at, obj.tagged, max_len)?);
            }
            "tagged" => obj.tagged = c.flag()?,
            "visible" => obj.visible = c.flag()?,
            w if UNSUPPORTED.contains(&w) => {
                obj.unsupported.get_or_insert((w.to_string(), at));
                skip_to_end_object(c)?;
                return Ok(obj);
            }
            // shadow, trace, caustic, globillum, finalgather, tag, box, motion box,
            // max displace, transparency, reflection, refraction, data, ...
            _ => c.skip_values()?,
        }
    }
}

/// Skips tokens up to and including `end object`.
fn skip_to_end_object(c: &mut Cursor) -> MiResult<()> {
    loop {
        match c.next()? {
            Tok::Word("end") if c.at_word("object")? => {
                c.next()?;
                return Ok(());
            }
            Tok::Eof => return Err(c.unexpected("'end object'")),
            _ => {}
        }
    }
}

fn limit(c: &mut Cursor, len: usize, max: usize, what: &str) -> MiResult<()> {
    if len >= max {
        Err(c.error(
            LxsErrorKind::ArrayTooLong,
            format!("more than {max} {what} (ParseOptions::max_array_len)"),
        ))
    } else {
        Ok(())
    }
}

/// An index that must be below `len`.
fn index(c: &mut Cursor, len: usize, what: &str) -> MiResult<u32> {
    let loc = c.loc()?;
    let v = c.number(what)?;
    if v.fract() == 0.0 && v >= 0.0 && v < len as f64 {
        Ok(v as u32)
    } else {
        Err(LxsError::new(
            LxsErrorKind::InvalidValue,
            loc,
            format!("{what} {v} is out of range (there are {len})"),
        ))
    }
}

/// Reads a group after `group` up to and including `end group`.
fn group(c: &mut Cursor, loc: Loc, tagged: bool, max: usize) -> MiResult<Group> {
    let mut g = Group {
        loc,
        ..Group::default()
    };
    if c.eat_word("merge")? {
        c.number("a merge distance")?;
    }
    while c.at_number()? {
        limit(c, g.vectors.len(), max, "vectors")?;
        let [x, y, z] = c.numbers::<3>("a vector's three numbers")?;
        g.vectors.push([x as f32, y as f32, z as f32]);
    }
    let mut mat_ids: HashMap<PolyMat, u32> = HashMap::new();
    loop {
        let at = c.loc()?;
        let w = match c.peek()? {
            Tok::Word(w) => *w,
            _ => return Err(c.unexpected("'v', a polygon ('c', 'p'), 'hole' or 'end group'")),
        };
        c.next()?;
        match w {
            "v" => {
                limit(c, g.verts.len(), max, "vertices")?;
                if !g.polys.is_empty() {
                    return Err(LxsError::new(
                        LxsErrorKind::Syntax,
                        at,
                        "vertex records must come before the polygons",
                    ));
                }
                g.verts.push(vertex(c, g.vectors.len())?);
            }
            "c" | "p" | "cp" => {
                limit(c, g.polys.len(), max, "polygons")?;
                let mat = if tagged {
                    let tag = c.int("a material tag", 0, i64::from(u32::MAX))?;
                    PolyMat::Tag(tag as u32)
                } else if c.at_string()? {
                    PolyMat::Name(c.string("a material name")?)
                } else {
                    PolyMat::Inherit
                };
                let next = mat_ids.len() as u32;
                let id = *mat_ids.entry(mat.clone()).or_insert(next);
                if id == next {
                    g.mats.push(mat);
                }
                let start = g.refs.len() as u32;
                let n = refs(c, &mut g, max)?;
                if n < 3 {
                    return Err(LxsError::new(
                        LxsErrorKind::WrongValueCount,
                        at,
                        format!("polygon with {n} vertices (at least 3)"),
                    ));
                }
                g.polys.push(Poly {
                    start,
                    outer: n,
                    holes: Vec::new(),
                    mat: id,
                    convex: w != "p",
                    line: at.line,
                    col: at.col,
                });
            }
            "hole" => {
                let n = refs(c, &mut g, max)?;
                match g.polys.last_mut() {
                    Some(p) if n >= 3 => p.holes.push(n),
                    Some(_) => {
                        return Err(LxsError::new(
                            LxsErrorKind::WrongValueCount,
                            at,
                            format!("hole with {n} vertices (at least 3)"),
                        ))
                    }
                    None => {
                        return Err(LxsError::new(
                            LxsErrorKind::Syntax,
                            at,
                            "'hole' before any polygon",
                        ))
                    }
                }
            }
            "end" => {
                c.expect_word("group")?;
                return Ok(g);
            }
            other => {
                return Err(LxsError::new(
                    LxsErrorKind::Unsupported,
                    at,
                    format!("'{other}' in a polygon group is not supported"),
                ))
            }
        }
    }
}

/// A vertex record after `v`.
fn vertex(c: &mut Cursor, nvec: usize) -> MiResult<VertexRec> {
    let v = index(c, nvec, "vector index")?;
    let mut rec = VertexRec {
        v,
        n: None,
        t: None,
    };
    loop {
        match c.peek()? {
            Tok::Word("n") => {
                c.next()?;
                rec.n = Some(index(c, nvec, "normal vector index")?);
            }
            Tok::Word("t") => {
                c.next()?;
                rec.t = Some(index(c, nvec, "texture vector index")?);
                while c.at_number()? {
                    index(c, nvec, "texture vector index")?;
                }
            }
            Tok::Word("d" | "m" | "u" | "b" | "d2") => {
                c.next()?;
                while c.at_number()? {
                    index(c, nvec, "vector index")?;
                }
            }
            _ => return Ok(rec),
        }
    }
}

/// Vertex-record references up to the next keyword; returns how many.
fn refs(c: &mut Cursor, g: &mut Group, max: usize) -> MiResult<u32> {
    let mut n = 0u32;
    while c.at_number()? {
        limit(c, g.refs.len(), max, "polygon vertex references")?;
        let r = index(c, g.verts.len(), "vertex reference")?;
        g.refs.push(r);
        n += 1;
    }
    Ok(n)
}

/// Triangles of one material reference of an object, in object space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshPart {
    pub mat: Option<PolyMat>,
    pub p: Vec<[f32; 3]>,
    /// Per-vertex normals, when every vertex of the part has one.
    pub n: Option<Vec<[f32; 3]>>,
    pub uv: Option<Vec<[f32; 2]>>,
    pub tris: Vec<[u32; 3]>,
    pub loc: Loc,
}

/// Per group, what is being gathered for one of its parts.
struct Gathering {
    part: usize,
    /// The part's mesh vertex for each vertex record used.
    remap: HashMap<u32, u32>,
    normals: Option<Vec<[f32; 3]>>,
    uvs: Option<Vec<[f32; 2]>>,
}

/// The object's polygons as one triangle mesh per group and material reference, in
/// first-use order.
pub fn mesh_parts(obj: &MiObject, warnings: &mut Vec<Diagnostic>) -> Vec<MeshPart> {
    let mut parts: Vec<MeshPart> = Vec::new();
    for g in &obj.groups {
        let mut local: HashMap<u32, Gathering> = HashMap::new();
        let mut fallbacks = 0usize;
        for poly in &g.polys {
            let gather = local.entry(poly.mat).or_insert_with(|| {
                parts.push(MeshPart {
                    mat: g.mats.get(poly.mat as usize).cloned(),
                    loc: g.loc.clone(),
                    ..MeshPart::default()
                });
                Gathering {
                    part: parts.len() - 1,
                    remap: HashMap::new(),
                    normals: Some(Vec::new()),
                    uvs: Some(Vec::new()),
                }
            });
            let total = poly.outer as usize + poly.holes.iter().map(|h| *h as usize).sum::<usize>();
            let start = poly.start as usize;
            let Some(loop_refs) = g.refs.get(start..start + total) else {
                continue;
            };
            let pts: Vec<DVec3> = loop_refs
                .iter()
                .map(|&r| {
                    let v = g
                        .verts
                        .get(r as usize)
                        .map_or([0.0; 3], |rec| vec3(g, rec.v));
                    DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]))
                })
                .collect();
            let holes: Vec<usize> = poly.holes.iter().map(|h| *h as usize).collect();
            let (tris, method) = triangulate(&pts, poly.outer as usize, &holes, poly.convex);
            if method == Method::FannedFallback {
                fallbacks += 1;
            }
            let Some(part) = parts.get_mut(gather.part) else {
                continue;
            };
            for t in tris {
                let mut out = [0u32; 3];
                for (o, i) in out.iter_mut().zip(t) {
                    let r = loop_refs[i as usize];
                    let next = part.p.len() as u32;
                    *o = *gather.remap.entry(r).or_insert_with(|| {
                        let rec = g.verts.get(r as usize).copied().unwrap_or(VertexRec {
                            v: 0,
                            n: None,
                            t: None,
                        });
                        part.p.push(vec3(g, rec.v));
                        match (rec.n, gather.normals.as_mut()) {
                            (Some(n), Some(ns)) => ns.push(vec3(g, n)),
                            _ => gather.normals = None,
                        }
                        match (rec.t, gather.uvs.as_mut()) {
                            (Some(t), Some(uvs)) => {
                                let tv = vec3(g, t);
                                uvs.push([tv[0], tv[1]]);
                            }
                            _ => gather.uvs = None,
                        }
                        next
                    });
                }
                part.tris.push(out);
            }
        }
        for gather in local.into_values() {
            if let Some(part) = parts.get_mut(gather.part) {
                part.n = gather
                    .normals
                    .filter(|n| n.len() == part.p.len() && !n.is_empty());
                part.uv = gather
                    .uvs
                    .filter(|u| u.len() == part.p.len() && !u.is_empty());
            }
        }
        if fallbacks > 0 {
            warnings.push(Diagnostic {
                loc: g.loc.clone(),
                message: format!(
                    "{fallbacks} degenerate or very large polygons were fanned rather than \
                     ear-clipped (holes dropped)"
                ),
            });
        }
    }
    parts.retain(|p| !p.tris.is_empty());
    parts
}

fn vec3(g: &Group, i: u32) -> [f32; 3] {
    g.vectors.get(i as usize).copied().unwrap_or([0.0; 3])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn object(text: &str) -> MiResult<MiObject> {
        let mut c = Cursor::new(text, "t.mi".into());
        parse(&mut c, "o".into(), Loc::default(), 1000)
    }

    const QUAD: &str = "visible on\n shadow on\n tagged on\n group\n\
        0 0 0  1 0 0  1 1 0  0 1 0  0 0 1\n\
        v 0 n 4\n v 1 n 4\n v 2 n 4\n v 3 n 4\n\
        p 1 0 1 2 3\n end group\nend object";

    #[test]
    fn a_tagged_quad_becomes_two_triangles() {
        let o = object(QUAD).unwrap();
        assert!(o.tagged);
        let parts = mesh_parts(&o, &mut Vec::new());
        assert_eq!(parts.len(), 1);
        let p = &parts[0];
        assert_eq!(p.mat, Some(PolyMat::Tag(1)));
        assert_eq!(p.tris.len(), 2);
        assert_eq!(p.p.len(), 4);
        assert_eq!(p.n.as_ref().unwrap()[0], [0.0, 0.0, 1.0]);
        assert!(p.uv.is_none());
    }

    #[test]
    fn named_materials_split_parts_and_texture_vectors_give_uvs() {
        let o = object(
            "group 0 0 0 1 0 0 1 1 0 0 1 0 0.5 0.5 0\n v 0 t 4\n v 1 t 4\n v 2 t 4\n v 3 t 4\n\
             c \"red\" 0 1 2\n c \"blue\" 0 2 3\n c \"red\" 0 2 3\n end group end object",
        )
        .unwrap();
        let parts = mesh_parts(&o, &mut Vec::new());
        assert_eq!(parts.len(), 2);
        assert_eq!(parts[0].mat, Some(PolyMat::Name("red".into())));
        assert_eq!(parts[0].tris.len(), 2);
        assert_eq!(parts[0].uv.as_ref().unwrap()[0], [0.5, 0.5]);
    }

    #[test]
    fn bad_indices_are_located() {
        for (text, line) in [
            ("group 0 0 0\n v 1\n end group end object", 2),
            (
                "group 0 0 0 1 1 1 2 2 2\n v 0\n v 1 n 7\n end group end object",
                3,
            ),
            ("group 0 0 0\n v 0\n p 0 0 1\n end group end object", 3),
            ("group 0 0 0\n v 0\n p 0 0\n end group end object", 3),
            ("group 0 0\n end group end object", 2),
            ("group 0 0 0\n v 0\n hole 0 0 0\n end group end object", 3),
            (
                "tagged on group 0 0 0\n v 0\n p -1 0 0 0\n end group end object",
                3,
            ),
        ] {
            let e = object(text).unwrap_err();
            assert_eq!(e.loc.line, line, "{text}: {e}");
        }
    }

    #[test]
    fn free_form_objects_are_skipped_with_a_reason() {
        let o = object("basis \"b\" rational bezier 3\n group 1 2 3 end group end object").unwrap();
        assert_eq!(o.unsupported.as_ref().unwrap().0, "basis");
        assert!(o.groups.is_empty());
    }
}
