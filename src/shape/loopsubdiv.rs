//! Loop subdivision and displacement of the mesh shapes (`loopsubdiv`, `trianglemesh`, `mesh`,
//! `plymesh`, `stlmesh`), with the parameters and defaults of LuxRender 1.x's mesh.cpp:
//! `integer nsubdivlevels` (else `nlevels`; default 0, also for `loopsubdiv`, which LuxRender
//! 1.x builds with the mesh plugin), `string subdivscheme` ("loop", or "microdisplacement":
//! `nsubdivlevels` segments per edge of each triangle, see [`super::microdisplace`]),
//! `texture displacementmap` (or the older `string displacementmap`: a float
//! texture's name), `float dmscale` (0.1), `float dmoffset` (0), `bool dmnormalsmooth` (true:
//! the result gets limit-surface normals, else it is flat shaded), `bool dmsharpboundary`
//! (false) and `bool dmnormalsplit` (false: with normals given, vertices at one position but
//! with different normals are not joined, so the mesh opens along normal breaks).
//!
//! ```text
//! TriangleMesh::build (mesh.rs: vertices in the target space, quads split)
//!   --apply: read parameters, check the triangle count against MAX_TRIANGLES
//!   --subdiv::SubdivMesh (weld, refine x levels, push to limit)
//!   --displace (the texture from ShapeCtx::displacement, evaluated at each vertex)
//!   --limit normals--> MeshArrays back to mesh.rs
//! ```
//!
//! As in LuxRender the subdivision runs after the shape's transform (in world space for world
//! shapes), so displacement is measured in that space, along the counter-clockwise normal. A
//! mesh whose topology cannot be subdivided (inconsistent winding, an edge with three faces)
//! is kept as given with a warning, as LuxRender does.
//!
//! The unit tests are in `loopsubdiv_tests.rs`.

use super::mesh_arrays::evaluate_in;
use super::mesh_arrays::MeshArrays;
use super::subdiv::{Attr, Options, SubdivMesh};
use super::{Build, BuildError};
use crate::geometry::frame::coordinate_system;

use crate::lxs::{ParamSet, SceneDescription, ShapeDesc, TextureType};
use crate::texture::{param_loc, FloatTex, TextureError, TextureSet};
use glam::{DVec2, DVec3};
use std::collections::BTreeMap;

/// Most triangles one subdivided shape may have (checked before anything is allocated).
pub const MAX_TRIANGLES: u64 = 1 << 24;

/// The subdivision parameters of one shape.
#[derive(Clone, Debug)]
struct Params {
    levels: u32,
    /// `subdivscheme` "microdisplacement" (with a map and levels > 0).
    micro: bool,
    map: Option<String>,
    scale: f64,
    offset: f64,
    smooth: bool,
    sharp: bool,
    split: bool,
}

/// The number of levels asked for (`nsubdivlevels`, else `nlevels`; negative counts as 0).
fn levels_of(ps: &ParamSet) -> u32 {
    ps.int("nsubdivlevels")
        .or_else(|| ps.int("nlevels"))
        .unwrap_or(0)
        .max(0) as u32
}

/// The displacement texture's name (`texture`, or the older `string` form).
fn map_name(ps: &ParamSet) -> Option<&str> {
    ps.texture("displacementmap")
        .or_else(|| ps.string("displacementmap"))
}

fn read_params(b: &Build) -> Result<Params, BuildError> {
    let ps = b.params();
    let mut levels = levels_of(ps);
    let map = map_name(ps).map(str::to_string);
    let mut micro = false;
    match ps.string_or("subdivscheme", "loop") {
        "loop" => {}
        "microdisplacement" if levels > 0 => {
            micro = map.is_some();
            if !micro {
                b.warn("no displacement map for microdisplacement: not subdividing (as LuxRender)");
                levels = 0;
            }
        }
        "microdisplacement" => {}
        other => b.warn(&format!(
            "unknown subdivscheme \"{other}\": using \"loop\" (as LuxRender)"
        )),
    }
    if map.is_some() && levels == 0 {
        b.warn("\"displacementmap\" has no effect without nsubdivlevels > 0 (LuxRender displaces while subdividing)");
    }
    Ok(Params {
        levels,
        micro,
        map,
        scale: b.float("dmscale", 0.1)?,
        offset: b.float("dmoffset", 0.0)?,
        smooth: ps.bool_or("dmnormalsmooth", true),
        sharp: ps.bool_or("dmsharpboundary", false),
        split: ps.bool_or("dmnormalsplit", false),
    })
}

/// The triangle count after `levels` levels of `tris` triangles, or `None` past `limit`.
pub fn subdivided_count(tris: usize, levels: u32, limit: u64) -> Option<u64> {
    let mut n = tris as u64;
    for _ in 0..levels {
        n = n.checked_mul(4).filter(|&n| n <= limit)?;
    }
    (n <= limit).then_some(n)
}

/// Subdivides (and displaces) `mesh` when the shape asks for it; `flip` is the mesh's
/// geometric-normal flip, which the generated normals follow.
pub(crate) fn apply(b: &Build, flip: bool, mesh: MeshArrays) -> Result<MeshArrays, BuildError> {
    let prm = read_params(b)?;
    if prm.levels == 0 {
        return Ok(mesh);
    }
    if prm.micro {
        return microdisplaced(b, flip, mesh, &prm);
    }
    let ps = b.params();
    let Some(count) = subdivided_count(mesh.tris.len(), prm.levels, MAX_TRIANGLES) else {
        return Err(BuildError::new(
            &param_loc(ps, levels_param(ps), &b.desc.entity.loc),
            format!(
                "shape \"{}\": {} levels of subdivision of {} triangles would give more than {} triangles",
                b.desc.entity.kind,
                prm.levels,
                mesh.tris.len(),
                MAX_TRIANGLES
            ),
        ));
    };
    let map = map_of(b, &prm);
    let sm = match subdivide(&mesh, &prm, map.as_ref()) {
        Ok(sm) => sm,
        Err(e) => {
            b.warn(&format!(
                "cannot subdivide: {e}; the mesh is kept as given (as LuxRender does)"
            ));
            return Ok(mesh);
        }
    };
    let what = format!("{} levels of loop subdivision", prm.levels);
    report(
        b,
        &what,
        (mesh.tris.len(), count),
        sm.bad_displacements,
        "vertices",
    );
    let out = to_arrays(&mesh, sm, flip);
    if out.p.iter().any(|p| !p.is_finite()) {
        return Err(b.err("subdivision or displacement moved a vertex out of range"));
    }
    Ok(out)
}

/// The name of the parameter that set the level count (for error locations).
fn levels_param(ps: &ParamSet) -> &'static str {
    if ps.contains("nsubdivlevels") {
        "nsubdivlevels"
    } else {
        "nlevels"
    }
}

/// The displacement texture a shape names, or `None` with a warning when it is unknown.
fn map_of(b: &Build, prm: &Params) -> Option<FloatTex> {
    let name = prm.map.as_ref()?;
    let t = b.ctx.displacement.get(name).cloned();
    if t.is_none() {
        b.warn(&format!(
            "unknown float texture \"{name}\": no displacement"
        ));
    }
    t
}

/// Logs a refinement (`what`, triangles before and after) and warns about the `bad` points
/// (named `points`) the displacement map left unmoved.
fn report(b: &Build, what: &str, (before, after): (usize, u64), bad: usize, points: &str) {
    tracing::info!(
        "{}: shape \"{}\": {what}: {before} -> {after} triangles",
        b.desc.entity.loc,
        b.desc.entity.kind,
    );
    if bad > 0 {
        b.warn(&format!(
            "the displacement map gave {bad} {points} a non-finite value: they were not moved"
        ));
    }
}

/// `subdivscheme "microdisplacement"` ([`super::microdisplace`]): `levels` segments per
/// edge.
fn microdisplaced(
    b: &Build,
    flip: bool,
    mesh: MeshArrays,
    prm: &Params,
) -> Result<MeshArrays, BuildError> {
    use super::microdisplace::{displace, micro_count, Micro};
    let ps = b.params();
    let Some(count) = micro_count(mesh.tris.len(), prm.levels, MAX_TRIANGLES) else {
        return Err(BuildError::new(
            &param_loc(ps, levels_param(ps), &b.desc.entity.loc),
            format!(
                "shape \"{}\": microdisplacement with {} segments per edge of {} triangles \
                 would give more than {} triangles (luxfarm builds the displaced surface \
                 as a mesh)",
                b.desc.entity.kind,
                prm.levels,
                mesh.tris.len(),
                MAX_TRIANGLES
            ),
        ));
    };
    let Some(map) = map_of(b, prm) else {
        return Ok(mesh);
    };
    let m = Micro {
        segments: prm.levels,
        scale: prm.scale,
        offset: prm.offset,
        smooth: prm.smooth,
    };
    let d = displace(&mesh, flip, &map, m);
    let what = format!("microdisplacement, {} segments per edge", prm.levels);
    report(b, &what, (mesh.tris.len(), count), d.bad, "grid points");
    if d.mesh.p.iter().any(|p| !p.is_finite()) {
        return Err(b.err("microdisplacement moved a vertex out of range"));
    }
    Ok(d.mesh)
}

/// The subdivided mesh and its normals (`None` for a flat-shaded result).
struct Subdivided {
    mesh: SubdivMesh,
    normals: Option<Vec<DVec3>>,
    bad_displacements: usize,
}

fn subdivide(
    mesh: &MeshArrays,
    prm: &Params,
    map: Option<&FloatTex>,
) -> Result<Subdivided, super::subdiv::TopologyError> {
    let p: Vec<DVec3> = mesh.p.iter().map(|v| v.as_dvec3()).collect();
    let weld_n: Option<Vec<DVec3>> = match (&mesh.n, prm.split) {
        (Some(n), true) => Some(n.iter().map(|v| v.as_dvec3()).collect()),
        _ => None,
    };
    let attr = (0..p.len())
        .map(|i| Attr {
            uv: mesh
                .uv
                .as_ref()
                .and_then(|uv| uv.get(i))
                .map_or(DVec2::ZERO, |t| t.as_dvec2()),
            col: mesh
                .cols
                .as_ref()
                .and_then(|c| c.get(i))
                .map_or(DVec3::ONE, |c| DVec3::from_array(c.map(f64::from))),
            alpha: mesh
                .alphas
                .as_ref()
                .and_then(|a| a.get(i))
                .map_or(1.0, |&a| a as f64),
        })
        .collect();
    let sm = SubdivMesh::new(&p, weld_n.as_deref(), attr, &mesh.tris)?;
    let (mut sm, topo) = sm.subdivide(Options {
        levels: prm.levels,
        sharp_boundary: prm.sharp,
    })?;
    let mut bad_displacements = 0;
    if let Some(map) = map {
        let normals = sm.normals(&topo);
        let eval = |p: DVec3, n: DVec3, uv: DVec2| evaluate(map, p, n, uv);
        bad_displacements = sm.displace(&topo, &normals, &eval, prm.scale, prm.offset);
    }
    let normals = prm.smooth.then(|| sm.normals(&topo));
    Ok(Subdivided {
        mesh: sm,
        normals,
        bad_displacements,
    })
}

/// The float texture at a vertex: its position, normal, a tangent frame around the normal
/// and the corner's uv (LuxRender's differential geometry for displacement).
fn evaluate(map: &FloatTex, p: DVec3, n: DVec3, uv: DVec2) -> f64 {
    let (dpdu, dpdv) = coordinate_system(n.as_vec3a());
    evaluate_in(map, p, n, uv, (dpdu.as_dvec3(), dpdv.as_dvec3()))
}

/// Back to f32 arrays, one vertex per attribute vertex; the input's optional channels stay
/// present or absent as they were.
fn to_arrays(input: &MeshArrays, s: Subdivided, flip: bool) -> MeshArrays {
    let m = &s.mesh;
    let owner = |a: usize| m.owner[a] as usize;
    let sign = if flip { -1.0 } else { 1.0 };
    MeshArrays {
        p: (0..m.attr.len())
            .map(|a| m.pos[owner(a)].as_vec3a())
            .collect(),
        n: s.normals.as_ref().map(|n| {
            (0..m.attr.len())
                .map(|a| (sign * n[owner(a)]).as_vec3a())
                .collect()
        }),
        uv: input
            .uv
            .as_ref()
            .map(|_| m.attr.iter().map(|a| a.uv.as_vec2()).collect()),
        cols: input
            .cols
            .as_ref()
            .map(|_| m.attr.iter().map(|a| a.col.as_vec3().to_array()).collect()),
        alphas: input
            .alphas
            .as_ref()
            .map(|_| m.attr.iter().map(|a| a.alpha as f32).collect()),
        tris: m.faces.clone(),
    }
}

/// The float textures the subdivided shapes that are built (world shapes, shapes of instanced
/// objects) displace by, built once by name. A name with no float texture is left out (the
/// shape warns and is not displaced, as LuxRender).
pub fn displacement_maps(
    desc: &SceneDescription,
    textures: &mut TextureSet,
) -> Result<BTreeMap<String, FloatTex>, BuildError> {
    let mut maps = BTreeMap::new();
    // Shapes of the world and of the objects that are instanced (the others are not built).
    let mut instanced: Vec<usize> = desc
        .instances
        .iter()
        .filter(|i| !i.portal)
        .map(|i| i.object)
        .collect();
    instanced.sort_unstable();
    instanced.dedup();
    let object_shapes = instanced
        .iter()
        .filter_map(|&i| desc.objects.get(i))
        .flat_map(|o| o.shapes.iter());
    let shapes: Vec<&ShapeDesc> = desc.shapes.iter().chain(object_shapes).collect();
    for s in shapes.into_iter().filter(|s| !s.portal) {
        let ps = &s.entity.params;
        let Some(name) = map_name(ps).filter(|_| levels_of(ps) > 0) else {
            continue;
        };
        if maps.contains_key(name) {
            continue;
        }
        let loc = param_loc(ps, "displacementmap", &s.entity.loc);
        match textures.named(TextureType::Float, name, &loc) {
            Ok(node) => {
                maps.insert(name.to_string(), FloatTex(node));
            }
            Err(TextureError::Missing { .. }) => {}
            Err(e) => return Err(e.into()),
        }
    }
    Ok(maps)
}
