//! Topology of a [`SubdivMesh`]: vertices welded by position (and normal), the neighbour
//! across each triangle edge, and the ordered fan of faces around each vertex, from which the
//! subdivision masks read a vertex's one-ring. Meshes LuxRender cannot subdivide (an edge
//! with three faces or neighbours wound against each other, a degenerate triangle, a vertex
//! whose faces form more than one fan) are refused here.

use super::{SubdivMesh, TopologyError};
use glam::DVec3;
use std::collections::HashMap;

/// No neighbour (a boundary edge).
const NONE: u32 = u32::MAX;

/// Neighbours and fans of one level of a mesh. A corner is `3 * face + k`.
#[derive(Clone, Debug)]
pub struct Topology {
    /// For each corner `c`, the corner of the neighbouring face whose edge is the edge from
    /// `c` to the next corner of its face (traversed the other way), or `NONE`.
    nbr: Vec<u32>,
    /// Fan of each topological vertex: `fan[fan_start[v]..fan_start[v + 1]]` are its corners,
    /// in order around it (each face after the one across its edge toward the next vertex).
    fan_start: Vec<u32>,
    fan: Vec<u32>,
    /// Whether the vertex's fan is open (the vertex lies on a boundary).
    boundary: Vec<bool>,
}

/// Gives each distinct position (and normal, when given) one topological vertex.
pub(super) fn weld(p: &[DVec3], n: Option<&[DVec3]>) -> (Vec<DVec3>, Vec<u32>) {
    let key = |i: usize| -> [u64; 6] {
        let q = p[i];
        let m = n.and_then(|n| n.get(i)).copied().unwrap_or(DVec3::ZERO);
        // +0.0 and -0.0 are one position, as C++'s == says.
        let bits = |x: f64| (x + 0.0).to_bits();
        [
            bits(q.x),
            bits(q.y),
            bits(q.z),
            bits(m.x),
            bits(m.y),
            bits(m.z),
        ]
    };
    let mut index: HashMap<[u64; 6], u32> = HashMap::with_capacity(p.len());
    let mut pos = Vec::new();
    let owner = (0..p.len())
        .map(|i| {
            *index.entry(key(i)).or_insert_with(|| {
                pos.push(p[i]);
                pos.len() as u32 - 1
            })
        })
        .collect();
    (pos, owner)
}

impl Topology {
    /// Neighbours and fans of `m`, or why it cannot be subdivided.
    pub fn new(m: &SubdivMesh) -> Result<Topology, TopologyError> {
        let nbr = neighbours(m)?;
        let nv = m.pos.len();
        // Corners of each vertex, bucketed.
        let mut count = vec![0u32; nv + 1];
        for f in 0..m.faces.len() {
            for k in 0..3 {
                count[m.topo(f, k) + 1] += 1;
            }
        }
        for v in 0..nv {
            count[v + 1] += count[v];
        }
        let mut first = vec![NONE; nv];
        for c in 0..3 * m.faces.len() {
            let v = m.topo(c / 3, c % 3);
            if first[v] == NONE {
                first[v] = c as u32;
            }
        }
        let mut t = Topology {
            nbr,
            fan_start: count,
            fan: Vec::with_capacity(3 * m.faces.len()),
            boundary: vec![false; nv],
        };
        for (v, &c0) in first.iter().enumerate() {
            let want = (t.fan_start[v + 1] - t.fan_start[v]) as usize;
            if want == 0 {
                continue;
            }
            let got = t.walk_fan(c0);
            if got != want {
                return Err(TopologyError::Vertex(v));
            }
            t.boundary[v] = t.nbr[prev_edge(t.fan[t.fan_start[v] as usize]) as usize] == NONE;
        }
        Ok(t)
    }

    /// Appends the fan through corner `c0` to `self.fan`; returns its length.
    fn walk_fan(&mut self, c0: u32) -> usize {
        let limit = self.nbr.len();
        // Back up to the first face of an open fan.
        let mut start = c0;
        for _ in 0..limit {
            match self.step_back(start) {
                Some(c) if c != c0 => start = c,
                _ => break,
            }
        }
        let mut c = start;
        let mut n = 0;
        loop {
            self.fan.push(c);
            n += 1;
            match self.step_forward(c) {
                Some(next) if next != start && n < limit => c = next,
                _ => break,
            }
        }
        n
    }

    /// The corner at the same vertex in the face across the edge toward the next vertex.
    fn step_forward(&self, c: u32) -> Option<u32> {
        let o = self.nbr[c as usize];
        (o != NONE).then(|| next_corner(o))
    }

    /// The corner at the same vertex in the face across the edge from the previous vertex.
    fn step_back(&self, c: u32) -> Option<u32> {
        let o = self.nbr[prev_edge(c) as usize];
        (o != NONE).then_some(o)
    }

    /// The corners around vertex `v`, in fan order.
    pub fn fan(&self, v: usize) -> &[u32] {
        let (a, b) = (self.fan_start[v] as usize, self.fan_start[v + 1] as usize);
        &self.fan[a..b]
    }

    pub fn is_boundary(&self, v: usize) -> bool {
        self.boundary[v]
    }

    /// The neighbouring corner across the edge starting at corner `c`.
    pub fn neighbour(&self, c: usize) -> Option<usize> {
        let o = self.nbr[c];
        (o != NONE).then_some(o as usize)
    }

    /// The one-ring of vertex `v` as corners (each naming the ring vertex in its face): for
    /// an interior vertex the next corner of each fan face; for a boundary vertex the previous
    /// corner of the first face, then the next corner of each face, so that the first and last
    /// entries are the two boundary neighbours.
    pub fn ring(&self, v: usize) -> Vec<u32> {
        let fan = self.fan(v);
        let mut ring = Vec::with_capacity(fan.len() + 1);
        if self.boundary[v] {
            if let Some(&c) = fan.first() {
                ring.push(prev_corner(c));
            }
        }
        ring.extend(fan.iter().map(|&c| next_corner(c)));
        ring
    }
}

/// The next corner of the same face.
pub fn next_corner(c: u32) -> u32 {
    c - c % 3 + (c % 3 + 1) % 3
}

/// The previous corner of the same face.
pub fn prev_corner(c: u32) -> u32 {
    c - c % 3 + (c % 3 + 2) % 3
}

/// The edge ending at corner `c` (it starts at the previous corner).
fn prev_edge(c: u32) -> u32 {
    prev_corner(c)
}

/// The neighbour of every corner's edge, refusing degenerate triangles, edges with more than
/// two faces and neighbours wound the other way.
fn neighbours(m: &SubdivMesh) -> Result<Vec<u32>, TopologyError> {
    let mut directed: HashMap<(u32, u32), u32> = HashMap::with_capacity(3 * m.faces.len());
    for f in 0..m.faces.len() {
        let t = [m.topo(f, 0), m.topo(f, 1), m.topo(f, 2)].map(|v| v as u32);
        if t[0] == t[1] || t[1] == t[2] || t[2] == t[0] {
            return Err(TopologyError::Degenerate(f));
        }
        for k in 0..3 {
            if directed
                .insert((t[k], t[(k + 1) % 3]), (3 * f + k) as u32)
                .is_some()
            {
                return Err(TopologyError::Edge(f));
            }
        }
    }
    let mut nbr = vec![NONE; 3 * m.faces.len()];
    for f in 0..m.faces.len() {
        for k in 0..3 {
            let (a, b) = (m.topo(f, k) as u32, m.topo(f, (k + 1) % 3) as u32);
            if let Some(&o) = directed.get(&(b, a)) {
                nbr[3 * f + k] = o;
            }
        }
    }
    Ok(nbr)
}
