//! Meshes (`<mesh>`: embedded, or external .igmesh, .obj, .ply) and their placements
//! (`<model>` of Indigo ≤ 2.x naming meshes and materials by name, `<model2>` of 3.x/4.x
//! naming them by uid, with keyframes).
//!
//! ```text
//! <mesh> name, uid, scale, normal_smoothing, embedded | external/path --> MeshEntry
//! <model>/<model2> pos | keyframe*, rotation (matrix | axis_rotation), scale, mesh, materials
//!     --> Model { keys: [(time, object-to-world)], mesh, LuxRender material per mesh index }
//! ```
//!
//! Indigo positions are column vectors: world = T(pos) · R(keyframe rotation) · M(rotation
//! matrix, given row by row) · S(scale) · object.

use super::camera::{axis_angle, keyframes};
use super::ctx::{err, Ctx};
use super::igmesh;
use super::material::Lookup;
use super::mesh::{Face, MeshData, UvLayout};
use super::node::Elem;
use super::obj;
use crate::lxs::{Loc, LxsError, LxsErrorKind};
use glam::{DMat3, DMat4, DQuat, DVec3};
use std::collections::HashMap;
use std::path::Path;

/// A mesh element, read.
#[derive(Debug)]
pub struct MeshEntry {
    pub name: String,
    /// None when its external file is missing (recorded for the final error).
    pub data: Option<MeshData>,
    pub smooth: bool,
    pub scale: f32,
    pub loc: Loc,
}

/// All meshes by name and uid.
#[derive(Default)]
pub struct Meshes {
    pub list: Vec<MeshEntry>,
    pub by_name: HashMap<String, usize>,
    pub by_uid: HashMap<i64, usize>,
}

impl Meshes {
    pub fn add(&mut self, m: MeshEntry, uid: Option<i64>, ctx: &Ctx) {
        let i = self.list.len();
        if let Some(u) = uid {
            self.by_uid.insert(u, i);
        }
        match self.by_name.get(&m.name) {
            Some(&first) => ctx.warn(
                &m.loc,
                format!(
                    "a mesh named \"{}\" is already defined at {}: references by name use the first",
                    m.name, self.list[first].loc
                ),
            ),
            None => {
                self.by_name.insert(m.name.clone(), i);
            }
        }
        self.list.push(m);
    }

    fn find(&self, name: Option<&str>, uid: Option<i64>, loc: &Loc) -> Result<usize, LxsError> {
        let found = match (name, uid) {
            (_, Some(u)) => self.by_uid.get(&u),
            (Some(n), None) => self.by_name.get(n),
            _ => None,
        };
        found.copied().ok_or_else(|| {
            err(
                LxsErrorKind::Undefined,
                loc,
                match (name, uid) {
                    (_, Some(u)) => {
                        format!("geometry uid {u} is not defined before this reference")
                    }
                    (Some(n), _) => format!("mesh \"{n}\" is not defined before this reference"),
                    _ => "no mesh named (mesh_name or geometry_uid)".into(),
                },
            )
        })
    }
}

/// Subdivision settings luxfarm does not apply (it never subdivides).
const SUBDIVISION: [&str; 7] = [
    "max_num_subdivisions",
    "subdivide_pixel_threshold",
    "subdivide_curvature_threshold",
    "displacement_error_threshold",
    "view_dependent_subdivision",
    "subdivision_smoothing",
    "merge_vertices_with_same_pos_and_normal",
];

/// Reads `<mesh>` written in a file of directory `dir`.
pub fn read_mesh(e: &Elem, dir: &Path, ctx: &Ctx) -> Result<(MeshEntry, Option<i64>), LxsError> {
    e.mark_used();
    let name = e.child_str(ctx, "name").unwrap_or("").to_string();
    let uid = e.child_int(ctx, "uid")?;
    let scale = match e.child(ctx, "scale") {
        Some(s) => s.positive(ctx)? as f32,
        None => 1.0,
    };
    let smooth = e.child_bool_or(ctx, "normal_smoothing", true)?;
    if let Some(n) = e.child_int(ctx, "max_num_subdivisions")? {
        if n > 0 {
            ctx.warn(
                &e.loc,
                format!(
                    "mesh \"{name}\": {n} subdivision levels asked, luxfarm does not subdivide"
                ),
            );
        }
    }
    e.ignore(&SUBDIVISION);
    let data = if let Some(emb) = e.child(ctx, "embedded") {
        Some(super::mesh::read_embedded(emb, ctx)?)
    } else if let Some(ext) = e.child(ctx, "external") {
        let p = ext.need(ctx, "path")?;
        external(p, dir, ctx)?
    } else {
        return Err(err(
            LxsErrorKind::WrongValueCount,
            &e.loc,
            format!("mesh \"{name}\" needs <embedded> or <external>"),
        ));
    };
    Ok((
        MeshEntry {
            name,
            data,
            smooth,
            scale,
            loc: e.loc.clone(),
        },
        uid,
    ))
}

/// Reads an external mesh file by its extension.
fn external(p: &Elem, dir: &Path, ctx: &Ctx) -> Result<Option<MeshData>, LxsError> {
    let written = p.str();
    let lower = written.to_ascii_lowercase();
    let ext = lower.rsplit('.').next().unwrap_or("");
    if !matches!(ext, "igmesh" | "obj" | "ply") {
        return Err(err(
            LxsErrorKind::Unsupported,
            &p.loc,
            format!("external mesh \"{written}\": .{ext} meshes are not supported (.igmesh, .obj, .ply)"),
        ));
    }
    let Some((path, bytes)) = ctx.read(written, dir, &p.loc, "mesh")? else {
        return Ok(None);
    };
    let fail = |msg: String| {
        err(
            LxsErrorKind::InvalidValue,
            &p.loc,
            format!("mesh file {}: {msg}", path.display()),
        )
    };
    let data = match ext {
        "igmesh" => {
            let limits = igmesh::Limits {
                max_array_len: ctx.opts.max_array_len as u64,
                max_decompressed: ctx.budget_left(),
            };
            let m = igmesh::read(&bytes, limits).map_err(|e| fail(e.0))?;
            let held = (m.positions.len() + m.normals.len()) * 12
                + m.uvs.len() * 8
                + m.tris.len() * 28
                + m.quads.len() * 36;
            ctx.charge(held.saturating_sub(bytes.len()) as u64, &p.loc)?;
            m
        }
        "obj" => obj::parse(&String::from_utf8_lossy(&bytes)).map_err(fail)?,
        _ => ply(&bytes).map_err(fail)?,
    };
    ctx.check_count(data.positions.len() as u64, "mesh vertices", &p.loc)?;
    ctx.check_count(
        (data.tris.len() + data.quads.len()) as u64,
        "mesh faces",
        &p.loc,
    )?;
    Ok(Some(data))
}

/// A PLY file through the render core's reader.
fn ply(bytes: &[u8]) -> Result<MeshData, String> {
    let d = crate::shape::plymesh::parse(bytes)?;
    let idx = |i: i64| u32::try_from(i).map_err(|_| format!("vertex index {i} out of range"));
    let mut m = MeshData {
        positions: d.p,
        normals: d.n.unwrap_or_default(),
        uv_layout: UvLayout::VertexLayer,
        ..MeshData::default()
    };
    if let Some(uv) = d.uv {
        m.num_uv_sets = 1;
        m.uvs = uv;
    }
    for t in d.tris {
        let v = [idx(t[0])?, idx(t[1])?, idx(t[2])?];
        m.tris.push(Face { v, uv: v, mat: 0 });
    }
    for q in d.quads {
        let v = [idx(q[0])?, idx(q[1])?, idx(q[2])?, idx(q[3])?];
        m.quads.push(Face { v, uv: v, mat: 0 });
    }
    m.validate()?;
    Ok(m)
}

/// `rotation` (a row-major `matrix` or an `axis_rotation`) times the uniform `scale`.
pub fn linear_part(e: &Elem, ctx: &Ctx) -> Result<DMat3, LxsError> {
    let scale = match e.child(ctx, "scale") {
        Some(s) => s.num(ctx)?,
        None => 1.0,
    };
    let rot = match e.child(ctx, "rotation") {
        Some(r) => {
            if let Some(m) = r.child(ctx, "matrix") {
                let v = m.n_nums(ctx, 9)?;
                DMat3::from_cols_array(&[v[0], v[3], v[6], v[1], v[4], v[7], v[2], v[5], v[8]])
            } else if let Some(a) = r.child(ctx, "axis_rotation") {
                DMat3::from_quat(axis_angle(a, ctx)?)
            } else {
                return Err(err(
                    LxsErrorKind::WrongValueCount,
                    &r.loc,
                    "<rotation> needs <matrix> or <axis_rotation>",
                ));
            }
        }
        None => DMat3::IDENTITY,
    };
    let m = rot * scale;
    if !m.is_finite() || m.determinant().abs() <= 1e-300 {
        return Err(err(
            LxsErrorKind::InvalidValue,
            &e.loc,
            "the rotation and scale are not invertible",
        ));
    }
    Ok(m)
}

/// The object-to-world keys of an element with `pos` or keyframes, rotation and scale.
pub fn placement(e: &Elem, ctx: &Ctx) -> Result<Vec<(f32, DMat4)>, LxsError> {
    let lin = linear_part(e, ctx)?;
    let mut frames = keyframes(e, ctx)?;
    if let Some(pos) = e.child_vec3(ctx, "pos")? {
        if frames.is_empty() {
            frames.push((0.0, DVec3::from(pos), DQuat::IDENTITY));
        } else {
            ctx.warn(&e.loc, "both <pos> and keyframes: the keyframes are used");
        }
    }
    if frames.is_empty() {
        frames.push((0.0, DVec3::ZERO, DQuat::IDENTITY));
    }
    Ok(frames
        .into_iter()
        .map(|(t, pos, q)| {
            let m = DMat3::from_quat(q) * lin;
            (t, DMat4::from_mat3_translation(m, pos))
        })
        .collect())
}

/// How a model asks for light output to be scaled (`emission_scale`).
#[derive(Clone, Debug)]
pub struct EmissionScale {
    pub material: String,
    /// Luminous flux in lm the material's surface on this model emits.
    pub measure: String,
    pub value: f64,
    pub loc: Loc,
}

/// A placed mesh.
#[derive(Debug)]
pub struct Model {
    pub mesh: usize,
    pub keys: Vec<(f32, DMat4)>,
    /// LuxRender material per mesh material index.
    pub materials: Vec<String>,
    pub emission_scales: Vec<EmissionScale>,
    /// IES profiles by LuxRender material name.
    pub ies: Vec<(String, String)>,
    pub loc: Loc,
}

/// Reads `<model>` or `<model2>`.
pub fn read_model(
    e: &Elem,
    dir: &Path,
    meshes: &Meshes,
    look: &Lookup,
    ctx: &Ctx,
) -> Result<Model, LxsError> {
    e.mark_used();
    e.ignore(&["uid", "name", "light_path_expression"]);
    let mesh_name = e.child_str(ctx, "mesh_name");
    let geometry_uid = e.child_int(ctx, "geometry_uid")?;
    let mesh = meshes.find(mesh_name, geometry_uid, &e.loc)?;
    let keys = placement(e, ctx)?;
    let entry = &meshes.list[mesh];
    let mut materials = Vec::new();
    if let Some(list) = e.child(ctx, "materials") {
        for c in &list.children {
            c.mark_used();
            let name = match c.name.as_str() {
                "material_uid" => look.material(None, Some(c.int(ctx)?), &c.loc)?,
                "material_name" => look.material(Some(c.str()), None, &c.loc)?,
                other => {
                    return Err(err(
                        LxsErrorKind::Syntax,
                        &c.loc,
                        format!("<{other}> in <materials>: material_uid or material_name expected"),
                    ))
                }
            };
            materials.push(name);
        }
    } else if let Some(n) = e.child(ctx, "material_name") {
        materials.push(look.material(Some(n.str()), None, &n.loc)?);
    } else if let Some(data) = &entry.data {
        for n in &data.material_names {
            materials.push(look.material(Some(n), None, &e.loc).map_err(|x| {
                err(
                    x.kind,
                    &e.loc,
                    format!("{} (named by mesh \"{}\")", x.message, entry.name),
                )
            })?);
        }
    }
    if materials.is_empty() && entry.data.is_some() {
        return Err(err(
            LxsErrorKind::Undefined,
            &e.loc,
            format!("the model of mesh \"{}\" names no material", entry.name),
        ));
    }
    let mut emission_scales = Vec::new();
    for s in e.all("emission_scale") {
        let material = match (
            s.child_str(ctx, "material_name"),
            s.child_int(ctx, "material_uid")?,
        ) {
            (n, u) if n.is_some() || u.is_some() => look.material(n, u, &s.loc)?,
            _ => materials.first().cloned().unwrap_or_default(),
        };
        emission_scales.push(EmissionScale {
            material,
            measure: s.need(ctx, "measure")?.str().to_string(),
            value: s.need(ctx, "value")?.positive(ctx)?,
            loc: s.loc.clone(),
        });
    }
    let mut ies = Vec::new();
    for i in e.all("ies_profile") {
        let m = look.material(
            i.child_str(ctx, "material_name"),
            i.child_int(ctx, "material_uid")?,
            &i.loc,
        )?;
        let p = i.need(ctx, "path")?;
        ies.push((m, ctx.scene_relative(p.str(), dir, &p.loc)?));
    }
    Ok(Model {
        mesh,
        keys,
        materials,
        emission_scales,
        ies,
        loc: e.loc.clone(),
    })
}

/// The luminous flux (lm) an emission_scale asks of a surface of `area` m².
pub fn flux(s: &EmissionScale, area: f64, ctx: &Ctx) -> Option<f64> {
    let pi = std::f64::consts::PI;
    match s.measure.as_str() {
        "luminous_flux" => Some(s.value),
        // A flat Lambertian emitter: I = L A, Φ = π L A; M = π L.
        "luminous_intensity" => Some(pi * s.value),
        "luminance" => Some(pi * s.value * area),
        "luminous_emittance" => Some(s.value * area),
        other => {
            ctx.warn(&s.loc, format!("emission_scale measure \"{other}\" is not known (luminous_flux, luminous_intensity, luminance, luminous_emittance): ignored"));
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::indigo::xml;
    use crate::lxs::ParseOptions;

    #[test]
    fn placement_composes_pos_rotation_rows_and_scale() {
        let ctx = Ctx::new(Path::new("t.igs"), &ParseOptions::default());
        let p = xml::parse(
            b"<model><pos>1 2 3</pos><scale>2</scale><rotation><matrix>0 -1 0 1 0 0 0 0 1</matrix></rotation></model>",
            &"t.igs".into(),
        )
        .unwrap();
        let keys = placement(&p.root, &ctx).unwrap();
        // Row-major (0 -1 0 / 1 0 0 / 0 0 1): x -> (0, 1, 0); scaled by 2, moved by pos.
        let x = keys[0].1.transform_point3(DVec3::X);
        assert!((x - DVec3::new(1.0, 4.0, 3.0)).length() < 1e-12, "{x}");
        let p = xml::parse(
            b"<model><rotation><matrix>1 0 0 0 0 0 0 0 1</matrix></rotation></model>",
            &"t.igs".into(),
        )
        .unwrap();
        assert_eq!(
            placement(&p.root, &ctx).unwrap_err().kind,
            LxsErrorKind::InvalidValue
        );
    }

    #[test]
    fn flux_of_each_measure() {
        let ctx = Ctx::new(Path::new("t.igs"), &ParseOptions::default());
        let s = |m: &str| EmissionScale {
            material: "m".into(),
            measure: m.into(),
            value: 10.0,
            loc: Loc::default(),
        };
        assert_eq!(flux(&s("luminous_flux"), 2.0, &ctx), Some(10.0));
        assert_eq!(flux(&s("luminous_emittance"), 2.0, &ctx), Some(20.0));
        assert!(
            (flux(&s("luminance"), 2.0, &ctx).unwrap() - 20.0 * std::f64::consts::PI).abs() < 1e-9
        );
        assert_eq!(flux(&s("watts"), 2.0, &ctx), None);
    }
}
