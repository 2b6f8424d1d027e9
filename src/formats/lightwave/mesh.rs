//! Turning the polygons of one surface on one layer into a triangle mesh in luxfarm space:
//! triangulation, smoothing, custom normals and texture coordinates.
//!
//! ```text
//! Layer + polygon list + Surface + UvSource
//!   --per polygon: Newell normal, corner normals (custom NORM map, or smoothing within the
//!     surface's angle), corner uv (TXUV map, or a projection)--> corners
//!   --corners deduplicated by (point, normal, uv)--> vertices; n-gons --triangulate--> triangles
//!   --swap Y/Z, reverse winding--> MeshData (P, N, uv, indices)
//! ```
//!
//! LightWave polygons list their corners clockwise seen from the front; the plain cross
//! product of their edges (as numbers) points out of the front. Smoothing averages the unit
//! normals of the polygons around a point whose angle with the corner's polygon is within the
//! surface's smoothing angle (0: faceted). A mesh whose corners all keep their polygon's own
//! normal gets no `N` (the renderer uses the geometric normals).

use super::coords::point_to_lux;
use super::model::{Layer, TexBlock, VertexMap};
use super::projection::{fix_seam, project};
use super::triangulate::{newell_normal, triangulate};
use glam::{DVec2, DVec3};
use std::collections::HashMap;

/// Where a surface's texture coordinates come from.
#[derive(Clone, Copy, Debug)]
pub enum UvSource<'a> {
    None,
    /// A TXUV vertex map (v up, as LightWave stores it).
    Map(&'a VertexMap),
    /// A projection of a texture layer.
    Projected(&'a TexBlock),
}

/// A triangle mesh ready for a `trianglemesh` shape (luxfarm space).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    pub p: Vec<[f32; 3]>,
    pub n: Option<Vec<[f32; 3]>>,
    pub uv: Option<Vec<f32>>,
    pub indices: Vec<i32>,
    /// Polygons with fewer than 3 corners (points and lines), not rendered.
    pub skipped: usize,
}

/// Quantised key of a corner's attributes.
type CornerKey = (u32, [u64; 3], [u64; 2]);

/// Builds the mesh of polygons `polys` (indices into `layer.polygons`).
pub fn build(
    layer: &Layer,
    polys: &[usize],
    smoothing: f32,
    normal_map: Option<&VertexMap>,
    uv: UvSource,
) -> MeshData {
    let point = |i: u32| -> DVec3 {
        let p = layer.points.get(i as usize).copied().unwrap_or([0.0; 3]);
        DVec3::from(p.map(f64::from))
    };
    // Unit normals of the group's polygons, and the polygons around each point.
    let normals: HashMap<usize, DVec3> = polys
        .iter()
        .map(|&pi| {
            let pts: Vec<DVec3> = layer.polygon_points(pi).iter().map(|&v| point(v)).collect();
            (pi, newell_normal(&pts).normalize_or_zero())
        })
        .collect();
    let cos_limit = f64::from(smoothing).cos();
    let smooth = smoothing > 0.0;
    let mut around: HashMap<u32, Vec<usize>> = HashMap::new();
    if smooth {
        for &pi in polys {
            for &v in layer.polygon_points(pi) {
                around.entry(v).or_default().push(pi);
            }
        }
    }
    let mut out = MeshData::default();
    let mut n_out: Vec<[f32; 3]> = Vec::new();
    let mut uv_out: Vec<f32> = Vec::new();
    let mut any_custom_normal = false;
    let mut seen: HashMap<CornerKey, i32> = HashMap::new();
    for &pi in polys {
        let corners = layer.polygon_points(pi);
        if corners.len() < 3 {
            out.skipped += 1;
            continue;
        }
        let pn = normals.get(&pi).copied().unwrap_or(DVec3::ZERO);
        let pts: Vec<DVec3> = corners.iter().map(|&v| point(v)).collect();
        let mut uvs: Vec<Option<DVec2>> = corners
            .iter()
            .zip(&pts)
            .map(|(&v, &p)| corner_uv(uv, v, pi, p, pn))
            .collect();
        if let UvSource::Projected(b) = uv {
            if matches!(
                b.projection,
                super::model::Projection::Cylindrical | super::model::Projection::Spherical
            ) {
                let mut flat: Vec<DVec2> = uvs.iter().map(|u| u.unwrap_or(DVec2::ZERO)).collect();
                fix_seam(&mut flat, f64::from(b.wrap_amount.0.max(1e-6)));
                uvs = flat.into_iter().map(Some).collect();
            }
        }
        let mut ids = Vec::with_capacity(corners.len());
        for (k, &v) in corners.iter().enumerate() {
            let custom = normal_map.and_then(|m| m.at(v, pi as u32));
            let n = match custom {
                Some(c) => {
                    any_custom_normal = true;
                    DVec3::from(c.map(f64::from)).normalize_or_zero()
                }
                None if smooth => smoothed(&around, &normals, v, pn, cos_limit),
                None => pn,
            };
            let t = uvs[k].unwrap_or(DVec2::ZERO);
            // Faceted corners need no normal: they do not split points.
            let keyed_n = if smooth || normal_map.is_some() {
                n
            } else {
                DVec3::ZERO
            };
            let key: CornerKey = (
                v,
                keyed_n.to_array().map(|c| (c as f32).to_bits() as u64),
                [(t.x as f32).to_bits() as u64, (t.y as f32).to_bits() as u64],
            );
            let id = *seen.entry(key).or_insert_with(|| {
                out.p.push(point_to_lux(
                    layer.points.get(v as usize).copied().unwrap_or([0.0; 3]),
                ));
                n_out.push(point_to_lux(n.as_vec3().to_array()));
                uv_out.extend_from_slice(&[t.x as f32, t.y as f32]);
                (out.p.len() - 1) as i32
            });
            ids.push(id);
        }
        for [a, b, c] in triangulate(&pts) {
            // reversed: the Y/Z swap mirrors the geometry
            out.indices.extend_from_slice(&[ids[a], ids[c], ids[b]]);
        }
    }
    if smooth || any_custom_normal {
        out.n = Some(n_out);
    }
    if !matches!(uv, UvSource::None) {
        out.uv = Some(uv_out);
    }
    out
}

/// A corner's image coordinates (t down from the top row).
fn corner_uv(uv: UvSource, v: u32, poly: usize, p: DVec3, n: DVec3) -> Option<DVec2> {
    match uv {
        UvSource::None => None,
        UvSource::Map(m) => m
            .at(v, poly as u32)
            .map(|c| DVec2::new(f64::from(c[0]), 1.0 - f64::from(c[1]))),
        UvSource::Projected(b) => project(b, p, n),
    }
}

/// The smoothed normal at point `v` of a polygon with normal `pn`.
fn smoothed(
    around: &HashMap<u32, Vec<usize>>,
    normals: &HashMap<usize, DVec3>,
    v: u32,
    pn: DVec3,
    cos_limit: f64,
) -> DVec3 {
    let mut sum = DVec3::ZERO;
    for q in around.get(&v).into_iter().flatten() {
        let qn = normals.get(q).copied().unwrap_or(DVec3::ZERO);
        if qn.dot(pn) >= cos_limit - 1e-9 {
            sum += qn;
        }
    }
    let n = sum.normalize_or_zero();
    if n == DVec3::ZERO {
        pn
    } else {
        n
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::lightwave::model::{PolyKind, Polygon};

    /// Two faces of a unit cube's corner, sharing an edge: the floor (y = 0, front down) and
    /// the side x = 0 (front towards -x), listed clockwise seen from the front.
    fn corner() -> Layer {
        let pts = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 0.0, 1.0],
            [0.0, 0.0, 1.0],
            [0.0, 1.0, 0.0],
            [0.0, 1.0, 1.0],
        ];
        let indices = vec![0, 1, 2, 3, 0, 3, 5, 4];
        let polygons = vec![
            Polygon {
                start: 0,
                count: 4,
                kind: PolyKind::Face,
                surface_tag: Some(0),
            },
            Polygon {
                start: 4,
                count: 4,
                kind: PolyKind::Face,
                surface_tag: Some(0),
            },
        ];
        Layer {
            points: pts,
            indices,
            polygons,
            ..Layer::default()
        }
    }

    fn tri_normal(m: &MeshData, t: usize) -> DVec3 {
        let p = |i: i32| DVec3::from(m.p[i as usize].map(f64::from));
        let (a, b, c) = (
            p(m.indices[3 * t]),
            p(m.indices[3 * t + 1]),
            p(m.indices[3 * t + 2]),
        );
        (b - a).cross(c - a).normalize()
    }

    #[test]
    fn faceted_mesh_faces_out_after_conversion() {
        let l = corner();
        let m = build(&l, &[0, 1], 0.0, None, UvSource::None);
        assert_eq!(m.indices.len(), 12);
        assert!(m.n.is_none() && m.uv.is_none());
        // floor faces LightWave -y, which is luxfarm -z
        assert!((tri_normal(&m, 0) - DVec3::new(0.0, 0.0, -1.0)).length() < 1e-9);
        // the side faces -x in both
        assert!((tri_normal(&m, 2) - DVec3::new(-1.0, 0.0, 0.0)).length() < 1e-9);
        assert_eq!(m.p.len(), 6, "shared corners are shared vertices");
    }

    #[test]
    fn smoothing_within_the_angle_merges_normals() {
        let l = corner();
        let sharp = build(&l, &[0, 1], 80f32.to_radians(), None, UvSource::None);
        // 90 degrees apart: not smoothed; shared points split by normal
        assert_eq!(sharp.p.len(), 8);
        let soft = build(&l, &[0, 1], 91f32.to_radians(), None, UvSource::None);
        assert_eq!(soft.p.len(), 6);
        let n = soft.n.unwrap();
        // point 0 is shared: its normal is halfway between -z and -x (luxfarm)
        let k = soft.p.iter().position(|p| *p == [0.0, 0.0, 0.0]).unwrap();
        let d = DVec3::from(n[k].map(f64::from));
        assert!(
            (d - DVec3::new(-1.0, 0.0, -1.0).normalize()).length() < 1e-6,
            "{d}"
        );
    }

    #[test]
    fn uv_maps_flip_v_and_split_vertices() {
        let l = corner();
        let mut map = VertexMap::default();
        for i in 0..6u32 {
            map.values.insert(i, [0.25 * i as f32, 0.25, 0.0]);
        }
        map.per_poly.insert((0, 1), [0.9, 0.75, 0.0]);
        let m = build(&l, &[0, 1], 0.0, None, UvSource::Map(&map));
        let uv = m.uv.unwrap();
        assert_eq!(uv.len(), 2 * m.p.len());
        assert_eq!(m.p.len(), 7, "point 0 has two uvs");
        assert!(uv.chunks(2).any(|c| c == [0.9, 0.25]));
        assert!(uv.chunks(2).any(|c| c == [0.0, 0.75]));
    }

    #[test]
    fn short_polygons_are_counted_not_rendered() {
        let mut l = corner();
        l.indices.extend_from_slice(&[0, 1]);
        l.polygons.push(Polygon {
            start: 8,
            count: 2,
            kind: PolyKind::Face,
            surface_tag: Some(0),
        });
        let m = build(&l, &[0, 1, 2], 0.0, None, UvSource::None);
        assert_eq!(m.skipped, 1);
    }
}
