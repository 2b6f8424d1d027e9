//! Triangle meshes as every mesh-like shape produces them (trianglemesh, mesh, plymesh,
//! stlmesh, heightfield): vertices transformed into the target space at build time, optional
//! per-vertex normals, uv, colours and alphas (what `hitpointcolor`/`hitpointalpha` read,
//! interpolated like LuxRender's `GetShadingInformation`), quads split along their shorter
//! diagonal as LuxRender does. A mesh that asks for subdivision is subdivided (and displaced)
//! in the target space by [`super::loopsubdiv`] before its face normals are computed.

use super::loopsubdiv::apply as apply_subdivision;
use super::mesh_arrays::{MeshArrays, DEFAULT_UV};
use super::{Build, BuildError};
use crate::geometry::frame::{coordinate_system, LocalGeometry};
use crate::geometry::transform::{error_floor, gamma, to_f32, to_f64};
use crate::geometry::HitData;
use glam::{Vec2, Vec3A};

/// Vertex and face data as read from parameters or a file (object space).
#[derive(Clone, Debug, Default)]
pub struct MeshData {
    pub p: Vec<[f32; 3]>,
    pub n: Option<Vec<[f32; 3]>>,
    pub uv: Option<Vec<[f32; 2]>>,
    /// Per-vertex colour (LuxRender's `float C`, three per vertex; PLY red/green/blue).
    pub cols: Option<Vec<[f32; 3]>>,
    /// Per-vertex alpha (LuxRender's `float A`; PLY alpha).
    pub alphas: Option<Vec<f32>>,
    pub tris: Vec<[i64; 3]>,
    pub quads: Vec<[i64; 4]>,
}

/// A point on a triangle: position, error bound, oriented geometric normal, shading normal.
#[derive(Clone, Copy, Debug)]
pub struct MeshPoint {
    pub p: Vec3A,
    pub p_error: Vec3A,
    pub n: Vec3A,
    pub ns: Option<Vec3A>,
}

/// A triangle mesh in its target space.
#[derive(Clone, Debug)]
pub struct TriangleMesh {
    pub p: Vec<Vec3A>,
    /// Unit vertex normals in the target space (negated under ReverseOrientation, as
    /// LuxRender does); the geometric normal is turned to agree with them.
    pub n: Option<Vec<Vec3A>>,
    pub uv: Option<Vec<Vec2>>,
    /// Per-vertex colours and alphas, when the mesh has them.
    pub cols: Option<Vec<[f32; 3]>>,
    pub alphas: Option<Vec<f32>>,
    pub tris: Vec<[u32; 3]>,
    /// Unit geometric normal of each triangle, `flip` applied (before turning it toward the
    /// shading normal). Kept rather than recomputed: its square root and division sat on
    /// every hit's critical path (16 bytes per triangle).
    pub face_n: Vec<Vec3A>,
    /// Geometric normal flipped: ReverseOrientation XOR the transform swaps handedness.
    pub flip: bool,
}

impl TriangleMesh {
    /// Validates `data` and transforms it into the target space of `b`.
    pub(crate) fn build(b: &Build, data: MeshData) -> Result<TriangleMesh, BuildError> {
        let nv = data.p.len();
        if nv == 0 {
            return Err(b.err("the mesh has no vertices (\"P\")"));
        }
        if let Some(bad) = data.p.iter().find(|p| !p.iter().all(|c| c.is_finite())) {
            return Err(b.err(format!("vertex {bad:?} is not finite")));
        }
        let check = |i: i64| -> Result<u32, BuildError> {
            if i < 0 || i as usize >= nv {
                Err(b.err(format!(
                    "vertex index {i} out of range ({nv} \"P\" values were given)"
                )))
            } else {
                Ok(i as u32)
            }
        };
        let mut tris = Vec::with_capacity(data.tris.len() + 2 * data.quads.len());
        for t in &data.tris {
            tris.push([check(t[0])?, check(t[1])?, check(t[2])?]);
        }
        let p: Vec<Vec3A> = data
            .p
            .iter()
            .map(|v| to_f32(b.to_space.point(to_f64(Vec3A::from_array(*v)))))
            .collect();
        let uv: Option<Vec<Vec2>> = match data.uv {
            Some(uv) if uv.len() == nv => Some(uv.iter().map(|t| Vec2::from_array(*t)).collect()),
            Some(uv) => {
                b.warn(&format!(
                    "{} uv pairs for {nv} vertices: ignoring uv",
                    uv.len()
                ));
                None
            }
            None => None,
        };
        for q in &data.quads {
            let q = [check(q[0])?, check(q[1])?, check(q[2])?, check(q[3])?];
            tris.extend(split_quad(&p, uv.as_deref(), q));
        }
        if tris.is_empty() {
            return Err(b.err("the mesh has no triangles or quads"));
        }
        let n = match data.n {
            Some(n) if n.len() == nv => Some(transform_normals(b, &n)),
            Some(n) => {
                b.warn(&format!(
                    "{} normals for {nv} vertices: ignoring \"N\"",
                    n.len()
                ));
                None
            }
            None => None,
        };
        let cols = per_vertex(b, data.cols, nv, "colours (\"C\")");
        let alphas = per_vertex(b, data.alphas, nv, "alphas (\"A\")");
        let flip = b.reverse() ^ b.to_space.swaps_handedness();
        let MeshArrays {
            p,
            n,
            uv,
            cols,
            alphas,
            tris,
        } = apply_subdivision(
            b,
            flip,
            MeshArrays {
                p,
                n,
                uv,
                cols,
                alphas,
                tris,
            },
        )?;
        let face_n = tris.iter().map(|t| face_normal(&p, *t, flip)).collect();
        Ok(TriangleMesh {
            p,
            n,
            uv,
            cols,
            alphas,
            tris,
            face_n,
            flip,
        })
    }

    #[inline(always)]
    pub fn vertices(&self, i: usize) -> [Vec3A; 3] {
        let [a, b, c] = self.tris[i];
        [self.p[a as usize], self.p[b as usize], self.p[c as usize]]
    }

    pub fn area(&self, i: usize) -> f64 {
        let [p0, p1, p2] = self.vertices(i).map(to_f64);
        0.5 * (p1 - p0).cross(p2 - p0).length()
    }

    /// Point, its error bound, oriented geometric normal and shading normal at barycentric
    /// coordinates `b` of triangle `i` (what light sampling needs of a point).
    pub fn surface(&self, i: usize, b: [f32; 3]) -> MeshPoint {
        self.surface_of(i, self.vertices(i), b)
    }

    /// [`Self::surface`] with triangle `i`'s vertices given (a BVH packet that was just
    /// tested holds them: reading them there spares two dependent loads from the mesh).
    #[inline(always)]
    pub fn surface_of(&self, i: usize, v: [Vec3A; 3], b: [f32; 3]) -> MeshPoint {
        debug_assert_eq!(v, self.vertices(i), "triangle {i}: not the mesh's vertices");
        let [p0, p1, p2] = v;
        let p = b[0] * p0 + b[1] * p1 + b[2] * p2;
        let p_abs_sum = (b[0] * p0).abs() + (b[1] * p1).abs() + (b[2] * p2).abs();
        let p_error = error_floor(p, gamma(7) * p_abs_sum);
        let mut n = self.face_n[i];
        let ns = self.n.as_ref().and_then(|vn| {
            let idx = self.tris[i];
            let s = b[0] * vn[idx[0] as usize]
                + b[1] * vn[idx[1] as usize]
                + b[2] * vn[idx[2] as usize];
            let s = s.normalize_or_zero();
            (s != Vec3A::ZERO).then_some(s)
        });
        if let Some(ns) = ns {
            if n.dot(ns) < 0.0 {
                n = -n;
            }
        }
        MeshPoint { p, p_error, n, ns }
    }

    /// Local geometry at barycentric coordinates `b` of triangle `i`.
    pub fn geometry(&self, i: usize, b: [f32; 3]) -> LocalGeometry {
        self.geometry_of(i, self.vertices(i), b)
    }

    /// [`Self::geometry`] with triangle `i`'s vertices given (see [`Self::surface_of`]).
    #[inline(always)]
    pub fn geometry_of(&self, i: usize, v: [Vec3A; 3], b: [f32; 3]) -> LocalGeometry {
        let MeshPoint { p, p_error, n, ns } = self.surface_of(i, v, b);
        let [p0, p1, p2] = v;
        let uv = self.vertex_uv(i);
        let (dp02, dp12) = (p0 - p2, p1 - p2);
        let (duv02, duv12) = (uv[0] - uv[2], uv[1] - uv[2]);
        let det = duv02.x * duv12.y - duv02.y * duv12.x;
        let (mut dpdu, mut dpdv) = (Vec3A::ZERO, Vec3A::ZERO);
        if det.abs() > 1e-12 {
            let inv = 1.0 / det;
            dpdu = (duv12.y * dp02 - duv02.y * dp12) * inv;
            dpdv = (duv02.x * dp12 - duv12.x * dp02) * inv;
        }
        if dpdu.cross(dpdv).length_squared().is_nan() || dpdu.cross(dpdv).length_squared() <= 0.0 {
            (dpdu, dpdv) = coordinate_system(n);
        }
        LocalGeometry {
            p,
            p_error,
            n,
            ns,
            uv: b[0] * uv[0] + b[1] * uv[1] + b[2] * uv[2],
            dpdu,
            dpdv,
            hit: self.hit_data(i, b),
        }
    }

    /// Interpolated vertex colour and alpha (white and 1 without them) and the face index.
    fn hit_data(&self, i: usize, b: [f32; 3]) -> HitData {
        let idx = self.tris[i].map(|k| k as usize);
        let mut hit = HitData {
            face: i as u32,
            ..HitData::default()
        };
        if let Some(c) = &self.cols {
            for (ch, out) in hit.color.iter_mut().enumerate() {
                *out = b[0] * c[idx[0]][ch] + b[1] * c[idx[1]][ch] + b[2] * c[idx[2]][ch];
            }
        }
        if let Some(a) = &self.alphas {
            hit.alpha = b[0] * a[idx[0]] + b[1] * a[idx[1]] + b[2] * a[idx[2]];
        }
        hit
    }

    /// The uv of triangle `i`'s vertices ([`DEFAULT_UV`] without "uv").
    fn vertex_uv(&self, i: usize) -> [Vec2; 3] {
        match &self.uv {
            Some(uv) => self.tris[i].map(|k| uv[k as usize]),
            None => DEFAULT_UV,
        }
    }

    /// A point of triangle `i`, uniform by area, and its uv (for textured emission).
    pub fn sample(&self, i: usize, u: Vec2) -> (MeshPoint, Vec2) {
        let su0 = u.x.sqrt();
        let b0 = 1.0 - su0;
        let b1 = u.y * su0;
        let b = [b0, b1, (1.0 - b0 - b1).max(0.0)];
        let uv = self.vertex_uv(i);
        (
            self.surface(i, b),
            b[0] * uv[0] + b[1] * uv[1] + b[2] * uv[2],
        )
    }
}

/// Unit geometric normal of triangle `t` (any unit vector perpendicular to an edge when the
/// triangle is degenerate), negated when `flip`.
fn face_normal(p: &[Vec3A], t: [u32; 3], flip: bool) -> Vec3A {
    let [p0, p1, p2] = t.map(|k| p[k as usize]);
    let mut n = (p0 - p2).cross(p1 - p2).normalize_or_zero();
    if n == Vec3A::ZERO {
        n = (p1 - p0).any_orthonormal_vector();
    }
    if flip {
        -n
    } else {
        n
    }
}

/// Per-vertex data kept when there is one value per vertex; otherwise dropped with a warning.
fn per_vertex<T>(b: &Build, data: Option<Vec<T>>, nv: usize, what: &str) -> Option<Vec<T>> {
    match data {
        Some(v) if v.len() == nv => Some(v),
        Some(v) => {
            b.warn(&format!(
                "{} vertex {what} for {nv} vertices: ignoring them",
                v.len()
            ));
            None
        }
        None => None,
    }
}

fn transform_normals(b: &Build, n: &[[f32; 3]]) -> Vec<Vec3A> {
    n.iter()
        .map(|v| {
            let w = to_f32(b.to_space.normal(to_f64(Vec3A::from_array(*v)))).normalize_or_zero();
            if b.reverse() {
                -w
            } else {
                w
            }
        })
        .collect()
}

/// Splits a quad along its shorter diagonal (by uv distance on a tie), as LuxRender's mesh.
fn split_quad(p: &[Vec3A], uv: Option<&[Vec2]>, q: [u32; 4]) -> [[u32; 3]; 2] {
    let at = |i: usize| p[q[i] as usize];
    let d02 = at(0).distance_squared(at(2));
    let d13 = at(1).distance_squared(at(3));
    let mut first = d02 < d13;
    if d02 == d13 {
        if let Some(uv) = uv {
            let t = |i: usize| uv[q[i] as usize];
            first = t(0).distance_squared(t(2)) < t(1).distance_squared(t(3));
        }
    }
    if first {
        [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
    } else {
        [[q[1], q[2], q[3]], [q[1], q[3], q[0]]]
    }
}

#[cfg(test)]
mod tests {
    use crate::geometry::Transform;
    use crate::shape::test_util::{floats, ints, points, shape};
    use crate::shape::{Shape, ShapeCtx};
    use glam::{DMat4, Vec2};

    fn triangle(extra: Vec<(&str, crate::lxs::ParamValue)>) -> super::TriangleMesh {
        let mut params = vec![
            (
                "P",
                points(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]),
            ),
            ("indices", ints(&[0, 1, 2])),
        ];
        params.extend(extra);
        let desc = shape("trianglemesh", params, DMat4::IDENTITY, false);
        match Shape::build(&desc, &Transform::IDENTITY, &ShapeCtx::default()) {
            Ok(Shape::Mesh(m)) => m,
            _ => panic!("a mesh"),
        }
    }

    /// LuxRender 1.x gives every corner of a mesh without uv the uv (0.5, 0.5); given uvs
    /// are interpolated.
    #[test]
    fn a_mesh_without_uv_is_at_the_centre_of_uv_space() {
        let m = triangle(Vec::new());
        for b in [[1.0, 0.0, 0.0], [0.2, 0.3, 0.5], [0.0, 0.0, 1.0]] {
            assert_eq!(m.geometry(0, b).uv, Vec2::new(0.5, 0.5));
        }
        let g = triangle(vec![("uv", floats(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0]))])
            .geometry(0, [0.2, 0.3, 0.5]);
        assert!((g.uv - Vec2::new(0.3, 0.5)).length() < 1e-6, "{}", g.uv);
        // Without uv the tangents come from the normal: a frame around +z.
        let g = m.geometry(0, [0.2, 0.3, 0.5]);
        assert!(g.dpdu.cross(g.dpdv).normalize().z.abs() > 0.999);
    }
}
