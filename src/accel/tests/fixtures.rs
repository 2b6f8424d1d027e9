//! Fixtures of the accelerator tests: a deterministic random generator, incoherent rays inside
//! a geometry's bounds, and the Cornell box geometry (`cornell/cornell-mesh.lxs`) built in
//! code, so that the tests need no scene file.

use crate::accel::Geometry;
use crate::geometry::Ray;
use crate::lxs::{ParamValue, ShapeDesc};
use crate::shape::test_util::shape;
use glam::{DMat4, Vec3A};

/// Deterministic SplitMix64 generator.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in the box [lo, hi).
    pub fn in_box(&mut self, lo: Vec3A, hi: Vec3A) -> Vec3A {
        lo + (hi - lo) * Vec3A::new(self.f32(), self.f32(), self.f32())
    }

    /// Uniform on the unit sphere.
    pub fn direction(&mut self) -> Vec3A {
        let z = 1.0 - 2.0 * self.f32();
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = std::f32::consts::TAU * self.f32();
        Vec3A::new(r * phi.cos(), r * phi.sin(), z)
    }
}

/// `n` closest-hit rays (random origins and directions) and `n` any-hit segments (between
/// two random points) inside the slightly shrunk bounds of `g`.
pub fn incoherent_rays(g: &Geometry, n: usize, seed: u64) -> (Vec<Ray>, Vec<Ray>) {
    let (lo, hi) = g.bounds();
    let margin = (hi - lo) * 0.01;
    let (lo, hi) = (lo + margin, hi - margin);
    let mut rng = Rng::new(seed);
    let closest = (0..n)
        .map(|_| Ray::new(rng.in_box(lo, hi), rng.direction()))
        .collect();
    let any = (0..n)
        .map(|_| {
            let a = rng.in_box(lo, hi);
            let b = rng.in_box(lo, hi);
            Ray {
                o: a,
                d: b - a,
                t_max: 1.0,
                time: 0.0,
            }
        })
        .collect();
    (closest, any)
}

/// A trianglemesh of points `p` and triangle indices `idx`.
fn mesh(p: Vec<[f32; 3]>, idx: Vec<i32>) -> ShapeDesc {
    let params = vec![
        ("P", ParamValue::Point(p)),
        ("indices", ParamValue::Integer(idx)),
    ];
    shape("trianglemesh", params, DMat4::IDENTITY, false)
}

/// A UV sphere with `seg` segments around and `seg/2` rings.
fn uv_sphere(c: [f32; 3], r: f32, seg: usize) -> ShapeDesc {
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
            let (c2, d) = (a + seg as i32, b + seg as i32);
            idx.extend([a, c2, d, a, d, b]);
        }
    }
    mesh(p, idx)
}

/// The geometry of `cornell/cornell-mesh.lxs`: floor, ceiling and back wall, the two side
/// walls, the lamp, and the two spheres tessellated with 48 segments and 24 rings.
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
    let wall = |x: f32| vec![[x, -1.0, 0.0], [x, 1.0, 0.0], [x, 1.0, 2.0], [x, -1.0, 2.0]];
    let lamp = vec![
        [-0.25, -0.25, 1.99],
        [0.25, -0.25, 1.99],
        [0.25, 0.25, 1.99],
        [-0.25, 0.25, 1.99],
    ];
    vec![
        mesh(box_p, box_i),
        mesh(wall(-1.0), vec![0, 1, 2, 0, 2, 3]),
        mesh(wall(1.0), vec![0, 2, 1, 0, 3, 2]),
        mesh(lamp, vec![0, 2, 1, 0, 3, 2]),
        uv_sphere([-0.4, 0.3, 0.4], 0.4, 48),
        uv_sphere([0.45, -0.3, 0.35], 0.35, 48),
    ]
}
