//! Synthetic geometry for `luxfarm bench bvh` when no scene file is used: tessellated spheres
//! in a box (`--spheres K`), and the Cornell box of `cornell/cornell-mesh.lxs` built in code
//! (`--builtin`).

use glam::DMat4;
use luxfarm::lxs::{Entity, Loc, ParamSet, ParamValue, ShapeDesc, Xform};

/// A synthetic scene: a closed box (12 triangles) holding `k`³ UV spheres of `seg` segments.
pub fn sphere_field(k: usize, seg: usize) -> Vec<ShapeDesc> {
    let mut shapes = vec![box_mesh()];
    let step = 2.0 / k as f32;
    for i in 0..k {
        for j in 0..k {
            for l in 0..k {
                let c = [
                    -1.0 + step * (i as f32 + 0.5),
                    -1.0 + step * (j as f32 + 0.5),
                    -1.0 + step * (l as f32 + 0.5),
                ];
                shapes.push(uv_sphere(c, step * 0.35, seg));
            }
        }
    }
    shapes
}

fn mesh_desc(p: Vec<[f32; 3]>, idx: Vec<i32>) -> ShapeDesc {
    let mut ps = ParamSet::new();
    ps.add("P", ParamValue::Point(p));
    ps.add("indices", ParamValue::Integer(idx));
    ShapeDesc {
        entity: Entity {
            kind: "trianglemesh".into(),
            params: ps,
            loc: Loc {
                file: "<generated>".into(),
                line: 1,
                col: 1,
            },
        },
        object_to_world: Xform::fixed(DMat4::IDENTITY),
        material: None,
        area_light: None,
        reverse_orientation: false,
        interior: None,
        exterior: None,
        portal: false,
        portal_light: None,
    }
}

/// The [-1.2, 1.2]³ box as 12 inward-facing triangles.
pub fn box_mesh() -> ShapeDesc {
    let s = 1.2;
    let p: Vec<[f32; 3]> = (0..8)
        .map(|i| {
            [
                if i & 1 == 0 { -s } else { s },
                if i & 2 == 0 { -s } else { s },
                if i & 4 == 0 { -s } else { s },
            ]
        })
        .collect();
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let idx = quads
        .iter()
        .flat_map(|q| [q[0], q[1], q[2], q[0], q[2], q[3]])
        .collect();
    mesh_desc(p, idx)
}

/// A UV sphere with `seg` segments around and `seg/2` rings.
pub fn uv_sphere(c: [f32; 3], r: f32, seg: usize) -> ShapeDesc {
    let rings = (seg / 2).max(2);
    let mut p = Vec::new();
    for i in 0..=rings {
        let theta = std::f32::consts::PI * i as f32 / rings as f32;
        for j in 0..seg {
            let phi = std::f32::consts::TAU * j as f32 / seg as f32;
            p.push([
                c[0] + r * theta.sin() * phi.cos(),
                c[1] + r * theta.sin() * phi.sin(),
                c[2] + r * theta.cos(),
            ]);
        }
    }
    let mut idx = Vec::new();
    for i in 0..rings {
        for j in 0..seg {
            let a = (i * seg + j) as i32;
            let b = (i * seg + (j + 1) % seg) as i32;
            let c2 = a + seg as i32;
            let d = b + seg as i32;
            idx.extend([a, c2, d, a, d, b]);
        }
    }
    mesh_desc(p, idx)
}

/// The geometry of `cornell/cornell-mesh.lxs` rebuilt in code (walls, lamp and the two
/// spheres tessellated with 48 segments and 24 rings, as in the file).
pub fn cornell_like() -> Vec<ShapeDesc> {
    let box_p = vec![
        [-1.0, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
        [-1.0, -1.0, 2.0],
        [1.0, -1.0, 2.0],
        [1.0, 1.0, 2.0],
        [-1.0, 1.0, 2.0],
        [-1.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
        [1.0, 1.0, 2.0],
        [-1.0, 1.0, 2.0],
    ];
    let box_i = vec![0, 1, 2, 0, 2, 3, 4, 6, 5, 4, 7, 6, 8, 9, 10, 8, 10, 11];
    let left = vec![
        [-1.0, -1.0, 0.0],
        [-1.0, 1.0, 0.0],
        [-1.0, 1.0, 2.0],
        [-1.0, -1.0, 2.0],
    ];
    let right = vec![
        [1.0, -1.0, 0.0],
        [1.0, 1.0, 0.0],
        [1.0, 1.0, 2.0],
        [1.0, -1.0, 2.0],
    ];
    let lamp = vec![
        [-0.25, -0.25, 1.99],
        [0.25, -0.25, 1.99],
        [0.25, 0.25, 1.99],
        [-0.25, 0.25, 1.99],
    ];
    vec![
        mesh_desc(box_p, box_i),
        mesh_desc(left, vec![0, 1, 2, 0, 2, 3]),
        mesh_desc(right, vec![0, 2, 1, 0, 3, 2]),
        mesh_desc(lamp, vec![0, 2, 1, 0, 3, 2]),
        uv_sphere([-0.4, 0.3, 0.4], 0.4, 48),
        uv_sphere([0.45, -0.3, 0.35], 0.35, 48),
    ]
}
