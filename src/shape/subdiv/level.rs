//! One level of Loop subdivision: every triangle becomes four. Even vertices (the old ones)
//! move by Loop's vertex masks, odd vertices (one per edge) are placed by the edge mask, each
//! with LuxRender's boundary and seam rules; see [`super::limit::smooth_vertex`] for the
//! vertex masks shared with the limit push.

use super::limit::smooth_vertex;
use super::topology::{next_corner, prev_corner};
use super::{attr_sum, beta, Attr, SubdivMesh, Topology};
use glam::DVec3;

/// The mesh one level finer. Old topological and attribute vertices keep their indices; the
/// new ones follow them.
pub(super) fn refine(m: &SubdivMesh, topo: &Topology, sharp: bool) -> SubdivMesh {
    let mut out = SubdivMesh {
        pos: Vec::with_capacity(m.pos.len() + 3 * m.faces.len() / 2 + 8),
        attr: Vec::with_capacity(m.attr.len() + 2 * m.faces.len()),
        owner: Vec::with_capacity(m.attr.len() + 2 * m.faces.len()),
        faces: Vec::with_capacity(4 * m.faces.len()),
    };
    out.pos.extend_from_slice(&m.pos);
    out.attr.extend_from_slice(&m.attr);
    out.owner.extend_from_slice(&m.owner);
    for v in 0..m.pos.len() {
        let n = topo.ring(v).len();
        let w = if topo.is_boundary(v) {
            1.0 / 8.0
        } else {
            beta(n)
        };
        smooth_vertex(m, topo, v, w, sharp, &mut out);
    }
    let odd = odd_vertices(m, topo, &mut out);
    for (f, &[a0, a1, a2]) in m.faces.iter().enumerate() {
        let [m0, m1, m2] = [odd[3 * f], odd[3 * f + 1], odd[3 * f + 2]];
        out.faces.push([a0, m0, m2]);
        out.faces.push([m0, a1, m1]);
        out.faces.push([m2, m1, a2]);
        out.faces.push([m0, m1, m2]);
    }
    out
}

/// Creates the vertex of every edge; returns, per corner, the attribute vertex on the edge
/// that starts at that corner.
fn odd_vertices(m: &SubdivMesh, topo: &Topology, out: &mut SubdivMesh) -> Vec<u32> {
    let corner_attr = |c: usize| m.attr[m.faces[c / 3][c % 3] as usize];
    let corner_pos = |c: usize| m.pos[m.topo(c / 3, c % 3)];
    let mut odd_topo = vec![0u32; 3 * m.faces.len()];
    let mut odd_attr = vec![0u32; 3 * m.faces.len()];
    for c in 0..3 * m.faces.len() {
        let c1 = next_corner(c as u32) as usize;
        let c2 = prev_corner(c as u32) as usize;
        let own_mid = attr_sum(&[(0.5, corner_attr(c)), (0.5, corner_attr(c1))]);
        match topo.neighbour(c) {
            Some(o) if o < c => {
                // Second face of an interior edge: same position; its own midpoint attributes
                // when the two faces disagree about the edge's ends.
                odd_topo[c] = odd_topo[o];
                odd_attr[c] = if seam(&corner_attr, c, o) {
                    push_attr(out, own_mid, odd_topo[c])
                } else {
                    odd_attr[o]
                };
            }
            nbr => {
                let (p, a) = match nbr {
                    None => (0.5 * (corner_pos(c) + corner_pos(c1)), own_mid),
                    Some(o) => {
                        let o2 = prev_corner(o as u32) as usize;
                        let p = 3.0 / 8.0 * (corner_pos(c) + corner_pos(c1))
                            + 1.0 / 8.0 * (corner_pos(c2) + corner_pos(o2));
                        let a = if seam(&corner_attr, c, o) {
                            own_mid
                        } else {
                            attr_sum(&[
                                (3.0 / 8.0, corner_attr(c)),
                                (3.0 / 8.0, corner_attr(c1)),
                                (1.0 / 8.0, corner_attr(c2)),
                                (1.0 / 8.0, corner_attr(o2)),
                            ])
                        };
                        (p, a)
                    }
                };
                odd_topo[c] = push_pos(out, p);
                odd_attr[c] = push_attr(out, a, odd_topo[c]);
            }
        }
    }
    odd_attr
}

/// Whether corner `c`'s edge and its neighbour `o`'s carry different attributes at either
/// end (LuxRender compares uv, colour and alpha together here).
fn seam(corner_attr: &dyn Fn(usize) -> Attr, c: usize, o: usize) -> bool {
    let c1 = next_corner(c as u32) as usize;
    let o1 = next_corner(o as u32) as usize;
    // The neighbour runs the edge the other way: its corner o sits at c1, o1 at c.
    corner_attr(c) != corner_attr(o1) || corner_attr(c1) != corner_attr(o)
}

fn push_pos(out: &mut SubdivMesh, p: DVec3) -> u32 {
    out.pos.push(p);
    out.pos.len() as u32 - 1
}

fn push_attr(out: &mut SubdivMesh, a: Attr, owner: u32) -> u32 {
    out.attr.push(a);
    out.owner.push(owner);
    out.attr.len() as u32 - 1
}
