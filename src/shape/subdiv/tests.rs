//! Loop subdivision: closed meshes stay closed, vertices land on Loop's limit positions and
//! converge, attributes and normals interpolate, seams and boundaries follow LuxRender's rules,
//! displacement moves along the normals.

use super::*;
use std::collections::HashMap;

fn mesh(p: &[[f64; 3]], tris: &[[u32; 3]]) -> SubdivMesh {
    let p: Vec<DVec3> = p.iter().map(|v| DVec3::from_array(*v)).collect();
    SubdivMesh::new(&p, None, vec![Attr::default(); p.len()], tris).unwrap()
}

/// A unit cube centred on the origin, outward (counter-clockwise) triangles.
fn cube() -> SubdivMesh {
    let p: Vec<[f64; 3]> = (0..8)
        .map(|i| {
            [
                (i & 1) as f64 - 0.5,
                ((i >> 1) & 1) as f64 - 0.5,
                ((i >> 2) & 1) as f64 - 0.5,
            ]
        })
        .collect();
    let quads = [
        [0, 2, 3, 1], // z-
        [4, 5, 7, 6], // z+
        [0, 1, 5, 4], // y-
        [2, 6, 7, 3], // y+
        [0, 4, 6, 2], // x-
        [1, 3, 7, 5], // x+
    ];
    let tris: Vec<[u32; 3]> = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    mesh(&p, &tris)
}

fn tetrahedron() -> SubdivMesh {
    mesh(
        &[
            [1.0, 1.0, 1.0],
            [1.0, -1.0, -1.0],
            [-1.0, 1.0, -1.0],
            [-1.0, -1.0, 1.0],
        ],
        &[[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]],
    )
}

fn icosahedron() -> SubdivMesh {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut p = vec![
        [-1.0, g, 0.0],
        [1.0, g, 0.0],
        [-1.0, -g, 0.0],
        [1.0, -g, 0.0],
        [0.0, -1.0, g],
        [0.0, 1.0, g],
        [0.0, -1.0, -g],
        [0.0, 1.0, -g],
        [g, 0.0, -1.0],
        [g, 0.0, 1.0],
        [-g, 0.0, -1.0],
        [-g, 0.0, 1.0],
    ];
    for v in &mut p {
        let l = DVec3::from_array(*v).length();
        *v = v.map(|c| c / l);
    }
    let tris = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    mesh(&p, &tris)
}

fn run(m: &SubdivMesh, levels: u32, sharp: bool) -> (SubdivMesh, Topology) {
    m.clone()
        .subdivide(Options {
            levels,
            sharp_boundary: sharp,
        })
        .unwrap()
}

fn corner_pos(m: &SubdivMesh, f: usize, k: usize) -> DVec3 {
    m.pos[m.topo(f, k)]
}

/// Every edge, keyed by its two positions, is used once in each direction.
fn assert_watertight(m: &SubdivMesh) {
    let key = |p: DVec3| p.to_array().map(f64::to_bits);
    let mut directed: HashMap<_, usize> = HashMap::new();
    for f in 0..m.faces.len() {
        for k in 0..3 {
            let e = (key(corner_pos(m, f, k)), key(corner_pos(m, f, (k + 1) % 3)));
            *directed.entry(e).or_default() += 1;
        }
    }
    for (&(a, b), &n) in &directed {
        assert_eq!(n, 1, "an edge is used twice in one direction");
        assert_eq!(directed.get(&(b, a)), Some(&1), "an open edge");
    }
}

#[test]
fn closed_meshes_stay_closed_and_watertight() {
    for (name, m) in [("cube", cube()), ("tetrahedron", tetrahedron())] {
        for levels in 1..=3 {
            let (out, topo) = run(&m, levels, false);
            assert_eq!(
                out.faces.len(),
                m.faces.len() * 4usize.pow(levels),
                "{name}"
            );
            assert!((0..out.pos.len()).all(|v| !topo.is_boundary(v)), "{name}");
            assert_watertight(&out);
            // Euler characteristic of a sphere.
            let edges = out.faces.len() * 3 / 2;
            assert_eq!(
                out.pos.len() + out.faces.len() - edges,
                2,
                "{name} L{levels}"
            );
        }
    }
}

/// Loop's limit position of vertex `v` of the cage: (1 - nγ) v + γ Σ ring.
fn limit_of(m: &SubdivMesh, v: usize) -> DVec3 {
    let topo = Topology::new(m).unwrap();
    let ring = topo.ring(v);
    let g = limit_gamma(ring.len());
    let sum: DVec3 = ring
        .iter()
        .map(|&c| corner_pos(m, c as usize / 3, c as usize % 3))
        .sum();
    (1.0 - ring.len() as f64 * g) * m.pos[v] + g * sum
}

#[test]
fn cage_vertices_land_on_loops_limit_position_at_every_level() {
    for m in [cube(), tetrahedron(), icosahedron()] {
        for levels in 0..=4 {
            let (out, _) = run(&m, levels, false);
            for v in 0..m.pos.len() {
                let want = limit_of(&m, v);
                assert!(
                    out.pos[v].distance(want) < 1e-12,
                    "level {levels} vertex {v}: {} vs {want}",
                    out.pos[v]
                );
            }
        }
    }
}

fn point_triangle_distance(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let n = (b - a).cross(c - a);
    let inside = [(a, b), (b, c), (c, a)]
        .iter()
        .all(|(u, w)| (*w - *u).cross(p - *u).dot(n) >= 0.0);
    if inside && n.length() > 0.0 {
        return ((p - a).dot(n) / n.length()).abs();
    }
    [(a, b), (b, c), (c, a)]
        .iter()
        .map(|(u, w)| {
            let d = *w - *u;
            let t = ((p - *u).dot(d) / d.length_squared()).clamp(0.0, 1.0);
            p.distance(*u + t * d)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Largest distance from the vertices of `fine` to the triangles of `coarse`.
fn deviation(coarse: &SubdivMesh, fine: &SubdivMesh) -> f64 {
    fine.pos
        .iter()
        .map(|&p| {
            (0..coarse.faces.len())
                .map(|f| {
                    let [a, b, c] = [0, 1, 2].map(|k| corner_pos(coarse, f, k));
                    point_triangle_distance(p, a, b, c)
                })
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

#[test]
fn a_subdivided_cube_converges_toward_its_limit_surface() {
    // The limit surface's points at level L+1 lie ever closer to the level-L triangles; the
    // gap shrinks about fourfold per level (second-order convergence of a smooth surface).
    let levels: Vec<SubdivMesh> = (0..=4).map(|l| run(&cube(), l, false).0).collect();
    let dev: Vec<f64> = levels.windows(2).map(|w| deviation(&w[0], &w[1])).collect();
    eprintln!("deviation per level: {dev:?}");
    for w in dev.windows(2) {
        assert!(w[1] < 0.5 * w[0], "{dev:?}");
    }
    assert!(dev[3] < 5e-3, "{dev:?}");
    // Every refinement keeps the old vertices where they were (they are already on the limit).
    for w in levels.windows(2) {
        for v in 0..w[0].pos.len() {
            assert!(w[0].pos[v].distance(w[1].pos[v]) < 1e-12);
        }
    }
}

#[test]
fn a_subdivided_icosahedron_is_round() {
    // Radial spread of surface points about the centre: the flat-faced cage swings from its
    // face centres (0.79) to its vertices (1); after three levels of Loop what is left is
    // mostly the limit surface's own departure from a sphere (a few percent).
    let spread = |m: &SubdivMesh| {
        let mut r: Vec<f64> = Vec::new();
        for f in 0..m.faces.len() {
            let [a, b, c] = [0, 1, 2].map(|k| corner_pos(m, f, k));
            r.extend([a.length(), ((a + b + c) / 3.0).length()]);
        }
        let max = r.iter().copied().fold(0.0, f64::max);
        let min = r.iter().copied().fold(f64::INFINITY, f64::min);
        (max - min) / max
    };
    let cage = spread(&icosahedron());
    let fine = spread(&run(&icosahedron(), 3, false).0);
    eprintln!("radial spread: cage {cage:.4}, 3 levels {fine:.4}");
    assert!(cage > 0.2);
    assert!(fine < 0.05 && fine < cage / 5.0, "{fine}");
}

/// A planar n×n grid on [0,1]² with uv = (x, y).
fn grid(n: usize) -> SubdivMesh {
    let mut p = Vec::new();
    let mut attr = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
            p.push(DVec3::new(x, y, 0.0));
            attr.push(Attr {
                uv: DVec2::new(x, y),
                col: DVec3::new(x, 1.0 - y, 0.5),
                alpha: 1.0,
            });
        }
    }
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut tris = Vec::new();
    for j in 0..n {
        for i in 0..n {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    SubdivMesh::new(&p, None, attr, &tris).unwrap()
}

#[test]
fn uv_and_colours_follow_the_surface_and_a_plane_keeps_its_normal() {
    // Loop's masks reproduce affine functions: on a plane whose uv and colours are affine in
    // the position they stay so, and every normal is the plane's.
    let (out, topo) = run(&grid(3), 3, false);
    for (a, at) in out.attr.iter().enumerate() {
        let p = out.pos[out.owner[a] as usize];
        assert!(p.z.abs() < 1e-12);
        assert!(at.uv.distance(p.truncate()) < 1e-12, "{} at {p}", at.uv);
        assert!(at.col.distance(DVec3::new(p.x, 1.0 - p.y, 0.5)) < 1e-12);
    }
    for n in out.normals(&topo) {
        assert!(n.distance(DVec3::Z) < 1e-9, "{n}");
    }
}

#[test]
fn the_boundary_shrinks_unless_it_is_sharp() {
    let (soft, _) = run(&grid(2), 2, false);
    let (sharp, _) = run(&grid(2), 2, true);
    // The cage's corner (0,0): pulled inward by the boundary rule, kept when sharp.
    assert!(soft.pos[0].length() > 1e-3, "{}", soft.pos[0]);
    assert_eq!(sharp.pos[0], DVec3::ZERO);
    // A sharp boundary stays on the cage's square.
    let topo = Topology::new(&sharp).unwrap();
    for v in (0..sharp.pos.len()).filter(|&v| topo.is_boundary(v)) {
        let p = sharp.pos[v];
        let on_edge = [p.x, p.y, 1.0 - p.x, 1.0 - p.y]
            .iter()
            .any(|c| c.abs() < 1e-12);
        assert!(on_edge, "{p}");
    }
}

/// A cube whose six faces each have their own four vertices and uv in [0,1]² (uv seams on
/// every edge).
fn cube_with_seams() -> SubdivMesh {
    let c = cube();
    let mut p = Vec::new();
    let mut attr = Vec::new();
    let mut tris = Vec::new();
    for q in 0..6 {
        let (f0, f1) = (2 * q, 2 * q + 1);
        let corners = [
            c.faces[f0][0],
            c.faces[f0][1],
            c.faces[f0][2],
            c.faces[f1][2],
        ];
        let base = p.len() as u32;
        for (i, &v) in corners.iter().enumerate() {
            p.push(c.pos[c.owner[v as usize] as usize]);
            let uv = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]][i];
            attr.push(Attr {
                uv: DVec2::from_array(uv),
                ..Attr::default()
            });
        }
        tris.push([base, base + 1, base + 2]);
        tris.push([base, base + 2, base + 3]);
    }
    SubdivMesh::new(&p, None, attr, &tris).unwrap()
}

#[test]
fn uv_seams_keep_each_side_and_the_surface_closed() {
    let seamed = cube_with_seams();
    assert_eq!(seamed.pos.len(), 8, "welded by position");
    let (out, _) = run(&seamed, 2, false);
    let (plain, _) = run(&cube(), 2, false);
    assert_watertight(&out);
    // Positions do not depend on the uv layout.
    let mut a: Vec<[u64; 3]> = out
        .pos
        .iter()
        .map(|p| p.to_array().map(f64::to_bits))
        .collect();
    let mut b: Vec<[u64; 3]> = plain
        .pos
        .iter()
        .map(|p| p.to_array().map(f64::to_bits))
        .collect();
    a.sort_unstable();
    b.sort_unstable();
    assert_eq!(a, b);
    // Each face keeps its own square of uv; the cube's corners keep (0,0), (1,0), ...
    for at in &out.attr {
        assert!(at.uv.cmpge(DVec2::ZERO).all() && at.uv.cmple(DVec2::ONE).all());
    }
    for (a, at) in seamed.attr.iter().enumerate() {
        assert_eq!(out.attr[a].uv, at.uv, "a seam corner keeps its uv");
    }
}

#[test]
fn normals_point_out_of_a_closed_mesh() {
    let (out, topo) = run(&icosahedron(), 2, false);
    let n = out.normals(&topo);
    for (v, nv) in n.iter().enumerate() {
        assert!((nv.length() - 1.0).abs() < 1e-9);
        assert!(
            nv.dot(out.pos[v].normalize()) > 0.98,
            "{nv} at {}",
            out.pos[v]
        );
    }
}

#[test]
fn constant_displacement_moves_every_vertex_along_its_normal() {
    let (base, topo) = run(&cube(), 2, false);
    let normals = base.normals(&topo);
    let mut moved = base.clone();
    let bad = moved.displace(&topo, &normals, &|_, _, _| 0.5, 0.2, 0.03);
    assert_eq!(bad, 0);
    assert_eq!(normals.len(), base.pos.len());
    for ((p, n), q) in base.pos.iter().zip(&normals).zip(&moved.pos) {
        let want = *p + *n * (0.5 * 0.2 + 0.03);
        assert!(q.distance(want) < 1e-12);
    }
    // A map that varies with uv is averaged over the corners around a vertex.
    let (seamed, topo) = run(&cube_with_seams(), 1, false);
    let normals = seamed.normals(&topo);
    let mut m = seamed.clone();
    m.displace(&topo, &normals, &|_, _, uv| uv.x, 1.0, 0.0);
    let corner = m.owner[0] as usize;
    let fan = topo.fan(corner);
    let avg: f64 = fan
        .iter()
        .map(|&c| {
            seamed.attr[seamed.faces[c as usize / 3][c as usize % 3] as usize]
                .uv
                .x
        })
        .sum::<f64>()
        / fan.len() as f64;
    let d = m.pos[corner] - seamed.pos[corner];
    assert!((d.dot(normals[corner]) - avg).abs() < 1e-12);
}

#[test]
fn meshes_loop_subdivision_cannot_handle_are_refused() {
    let p = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ];
    // Two triangles wound against each other across their shared edge.
    let m = mesh(&p, &[[0, 1, 2], [1, 2, 3]]);
    assert_eq!(Topology::new(&m).unwrap_err(), TopologyError::Edge(1));
    // A triangle with two corners at one position.
    let m = mesh(&[[0.0; 3], [0.0; 3], [1.0, 0.0, 0.0]], &[[0, 1, 2]]);
    assert_eq!(Topology::new(&m).unwrap_err(), TopologyError::Degenerate(0));
    // Two fans meeting at one vertex (a bow tie).
    let m = mesh(
        &[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [-1.0, 0.0, 0.0],
            [-1.0, -1.0, 0.0],
        ],
        &[[0, 1, 2], [0, 3, 4]],
    );
    assert_eq!(Topology::new(&m).unwrap_err(), TopologyError::Vertex(0));
    let p: Vec<DVec3> = p.iter().map(|v| DVec3::from_array(*v)).collect();
    assert!(SubdivMesh::new(&p, None, vec![Attr::default(); 4], &[[0, 1, 9]]).is_err());
}

#[test]
fn normal_split_opens_the_mesh_along_normal_breaks() {
    // The two triangles of a quad, with different normals at the shared vertices.
    let p: Vec<DVec3> = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ]
    .iter()
    .map(|v| DVec3::from_array(*v))
    .collect();
    let n: Vec<DVec3> = [DVec3::Z, DVec3::Z, DVec3::Z, DVec3::X, DVec3::X, DVec3::X].to_vec();
    let tris = [[0, 1, 2], [3, 4, 5]];
    let joined = SubdivMesh::new(&p, None, vec![Attr::default(); 6], &tris).unwrap();
    let split = SubdivMesh::new(&p, Some(&n), vec![Attr::default(); 6], &tris).unwrap();
    assert_eq!(joined.pos.len(), 4);
    assert_eq!(split.pos.len(), 6);
    let t = Topology::new(&split).unwrap();
    assert!((0..6).all(|c| t.neighbour(c).is_none()));
}
