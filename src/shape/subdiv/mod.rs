//! Loop subdivision of a triangle mesh with LuxRender 1.x's rules (its `loopsubdiv.cpp`):
//! Loop's even/odd masks, the boundary rules (or a sharp boundary that keeps the cage's
//! boundary), uv/colour/alpha seams that are kept rather than smoothed, the final push of
//! every vertex onto the limit surface, limit-surface normals and the displacement of each
//! vertex along its normal.
//!
//! ```text
//! vertices + triangles --SubdivMesh::new (topology.rs: weld by position, check manifold)
//!   --refine (level.rs) x levels--> finer SubdivMesh
//!   --to_limit (limit.rs)--> vertices on the limit surface
//!   --normals / displace (limit.rs)--> positions, normals per vertex
//! ```
//!
//! The mesh keeps two kinds of vertex: a *topological* vertex is a position (LuxRender joins
//! the faces of a mesh by vertex position, and with `dmnormalsplit` by position and normal),
//! and an *attribute* vertex (a corner's uv, colour and alpha) belongs to one topological
//! vertex. Faces name attribute vertices, so a uv seam keeps its two sides' coordinates
//! while the surface stays closed. Everything is computed in f64.

mod level;
mod limit;
mod topology;

use glam::{DVec2, DVec3};
pub use topology::Topology;

/// What a corner carries besides its position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Attr {
    pub uv: DVec2,
    pub col: DVec3,
    pub alpha: f64,
}

impl Default for Attr {
    /// LuxRender's values for a mesh without uv, colours or alphas.
    fn default() -> Attr {
        Attr {
            uv: DVec2::ZERO,
            col: DVec3::ONE,
            alpha: 1.0,
        }
    }
}

/// Which attribute channels are smoothed (a channel with a seam at a vertex is kept).
#[derive(Clone, Copy, Debug, Default)]
struct Split {
    uv: bool,
    col: bool,
    alpha: bool,
}

impl Split {
    /// Marks the channels in which `a` and `b` differ.
    fn note(&mut self, a: &Attr, b: &Attr) {
        self.uv |= a.uv != b.uv;
        self.col |= a.col != b.col;
        self.alpha |= a.alpha != b.alpha;
    }

    /// `own` with its unsplit channels replaced by `smooth`.
    fn pick(&self, own: Attr, smooth: Attr) -> Attr {
        Attr {
            uv: if self.uv { own.uv } else { smooth.uv },
            col: if self.col { own.col } else { smooth.col },
            alpha: if self.alpha { own.alpha } else { smooth.alpha },
        }
    }
}

/// A weighted sum of attributes.
fn attr_sum(terms: &[(f64, Attr)]) -> Attr {
    let mut out = Attr {
        uv: DVec2::ZERO,
        col: DVec3::ZERO,
        alpha: 0.0,
    };
    for (w, a) in terms {
        out.uv += *w * a.uv;
        out.col += *w * a.col;
        out.alpha += *w * a.alpha;
    }
    out
}

/// A mesh during subdivision.
#[derive(Clone, Debug)]
pub struct SubdivMesh {
    /// Position of each topological vertex.
    pub pos: Vec<DVec3>,
    /// Attributes of each attribute vertex.
    pub attr: Vec<Attr>,
    /// The topological vertex of each attribute vertex.
    pub owner: Vec<u32>,
    /// Triangles as attribute vertex indices, counter-clockwise.
    pub faces: Vec<[u32; 3]>,
}

/// Why a mesh cannot be subdivided (LuxRender then keeps the cage).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TopologyError {
    #[error("triangle {0} has two corners at the same position")]
    Degenerate(usize),
    #[error("the edge of triangle {0} is shared by more than two triangles, or its neighbour is wound the other way")]
    Edge(usize),
    #[error("vertex {0} joins faces that do not form one fan (non-manifold vertex)")]
    Vertex(usize),
    #[error("vertex index {0} out of range")]
    Index(usize),
}

/// How to subdivide.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    pub levels: u32,
    /// Keep the cage's boundary (`dmsharpboundary`).
    pub sharp_boundary: bool,
}

/// Loop's even-vertex weight β for a vertex of `valence` (Warren's choice, as LuxRender).
pub fn beta(valence: usize) -> f64 {
    if valence == 3 {
        3.0 / 16.0
    } else {
        3.0 / (8.0 * valence as f64)
    }
}

/// The weight of each neighbour in the limit position of an interior vertex of `valence`.
pub fn limit_gamma(valence: usize) -> f64 {
    1.0 / (valence as f64 + 3.0 / (8.0 * beta(valence)))
}

impl SubdivMesh {
    /// Builds the mesh from vertices and triangles; `weld_n` (the vertex normals, given for
    /// `dmnormalsplit`) keeps vertices at one position apart when their normals differ.
    pub fn new(
        p: &[DVec3],
        weld_n: Option<&[DVec3]>,
        attr: Vec<Attr>,
        tris: &[[u32; 3]],
    ) -> Result<SubdivMesh, TopologyError> {
        let (pos, owner) = topology::weld(p, weld_n);
        for t in tris {
            for &i in t {
                if i as usize >= owner.len() {
                    return Err(TopologyError::Index(i as usize));
                }
            }
        }
        Ok(SubdivMesh {
            pos,
            attr,
            owner,
            faces: tris.to_vec(),
        })
    }

    /// The topological vertex of corner `k` of face `f`.
    pub fn topo(&self, f: usize, k: usize) -> usize {
        self.owner[self.faces[f][k] as usize] as usize
    }

    /// Runs `opts.levels` levels of subdivision and pushes the vertices to the limit surface.
    pub fn subdivide(mut self, opts: Options) -> Result<(SubdivMesh, Topology), TopologyError> {
        let mut topo = Topology::new(&self)?;
        for _ in 0..opts.levels {
            self = level::refine(&self, &topo, opts.sharp_boundary);
            topo = Topology::new(&self)?;
        }
        limit::to_limit(&mut self, &topo, opts.sharp_boundary);
        Ok((self, topo))
    }

    /// Unit normal of each topological vertex from the limit tangents, turned to the side the
    /// counter-clockwise faces around it face.
    pub fn normals(&self, topo: &Topology) -> Vec<DVec3> {
        limit::normals(self, topo)
    }

    /// Moves each topological vertex along `normals` by `scale * value + offset`, `value`
    /// being `map(p, n, uv)` averaged over the faces around the vertex (each with its own
    /// corner's uv), as LuxRender's displacement does. Returns how many vertices got a
    /// non-finite value (they stay in place).
    pub fn displace(
        &mut self,
        topo: &Topology,
        normals: &[DVec3],
        map: &dyn Fn(DVec3, DVec3, DVec2) -> f64,
        scale: f64,
        offset: f64,
    ) -> usize {
        limit::displace(self, topo, normals, map, scale, offset)
    }
}

#[cfg(test)]
mod tests;
