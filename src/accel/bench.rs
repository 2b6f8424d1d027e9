//! Ray-throughput benchmark of the BVH on incoherent rays (`luxfarm bench bvh`).
//!
//! Closest-hit rays start at random points inside the scene bounds with random directions;
//! any-hit rays join two random points inside the bounds (shadow-ray-like). Rays are split
//! evenly across `threads` OS threads. Also generates a synthetic scene (tessellated spheres
//! in a box) for when no scene file is given.

use super::bvh::{BuildQuality, BvhLayout, BvhOptions};
use super::{Geometry, GeometryBuilder};
use crate::geometry::Ray;
use crate::lxs::{Entity, Loc, ParamSet, ParamValue, SceneDescription, ShapeDesc, Xform};
use crate::plugin::BuildError;
use crate::shape::ShapeCtx;
use glam::{DMat4, Vec3A};
use std::time::Instant;

/// Deterministic SplitMix64 generator (benchmarks and tests only).
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

    pub fn in_box(&mut self, lo: Vec3A, hi: Vec3A) -> Vec3A {
        lo + (hi - lo) * Vec3A::new(self.f32(), self.f32(), self.f32())
    }

    pub fn direction(&mut self) -> Vec3A {
        let z = 1.0 - 2.0 * self.f32();
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = std::f32::consts::TAU * self.f32();
        Vec3A::new(r * phi.cos(), r * phi.sin(), z)
    }
}

/// `n` closest-hit rays and `n` any-hit segments inside the (slightly shrunk) bounds.
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

/// CPU time this thread has run, from Linux's `/proc/thread-self/schedstat` (None elsewhere).
fn thread_cpu_secs() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = s.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

/// Throughput of one run: wall-clock rate, and the rate per CPU-second actually received
/// times the thread count (what an otherwise idle machine would give; the build machine is
/// shared).
#[derive(Clone, Copy, Debug, Default)]
pub struct Throughput {
    pub wall_mrays: f64,
    pub cpu_mrays: f64,
    pub hits: usize,
}

/// Runs `f` over `rays` split across `threads` threads.
pub fn throughput(rays: &[Ray], threads: usize, f: impl Fn(&Ray) -> bool + Sync) -> Throughput {
    let threads = threads.max(1);
    let chunk = rays.len().div_ceil(threads).max(1);
    let start = Instant::now();
    let per_thread: Vec<(usize, f64)> = std::thread::scope(|s| {
        let handles: Vec<_> = rays
            .chunks(chunk)
            .map(|c| {
                s.spawn(|| {
                    let t0 = thread_cpu_secs();
                    let hits = c.iter().filter(|r| f(r)).count();
                    let cpu = match (t0, thread_cpu_secs()) {
                        (Some(a), Some(b)) => b - a,
                        _ => f64::NAN,
                    };
                    (hits, cpu)
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or((0, f64::NAN)))
            .collect()
    });
    let secs = start.elapsed().as_secs_f64().max(1e-9);
    let hits = per_thread.iter().map(|p| p.0).sum();
    let cpu: f64 = per_thread.iter().map(|p| p.1).sum();
    let n = rays.len() as f64;
    Throughput {
        wall_mrays: n / secs / 1e6,
        cpu_mrays: if cpu > 0.0 {
            n / cpu * threads as f64 / 1e6
        } else {
            f64::NAN
        },
        hits,
    }
}

/// Result of one configuration.
#[derive(Clone, Debug)]
pub struct BenchResult {
    pub options: BvhOptions,
    pub build_secs: f64,
    pub closest: Throughput,
    pub any: Throughput,
    pub rays: usize,
}

/// The obvhs configurations compared by [`bench()`].
pub fn candidate_options() -> Vec<BvhOptions> {
    let mut v = Vec::new();
    for layout in [BvhLayout::Cwbvh, BvhLayout::Bvh2, BvhLayout::Bvh8] {
        for quality in [BuildQuality::Fast, BuildQuality::Medium, BuildQuality::Slow] {
            let leaves: &[u32] = match layout {
                BvhLayout::Cwbvh => &[1, 3],
                BvhLayout::Bvh2 => &[1, 4, 8],
                BvhLayout::Bvh8 => &[1, 2, 4, 8],
            };
            for &max_prims_per_leaf in leaves {
                v.push(BvhOptions {
                    layout,
                    quality,
                    max_prims_per_leaf,
                });
            }
        }
    }
    v
}

/// Builds the geometry with each option set (`build`) and measures closest-hit and any-hit
/// throughput on the same `n` incoherent rays with `threads` threads.
pub fn bench(
    build: impl Fn(BvhOptions) -> Result<Geometry, BuildError>,
    options: &[BvhOptions],
    n: usize,
    threads: usize,
) -> Result<Vec<BenchResult>, BuildError> {
    let mut out = Vec::new();
    let mut rays = None;
    for &opts in options {
        let start = Instant::now();
        let g = build(opts)?;
        let build_secs = start.elapsed().as_secs_f64();
        let (closest, any) = rays.get_or_insert_with(|| incoherent_rays(&g, n, 7));
        // warm-up
        throughput(&closest[..closest.len().min(10_000)], threads, |r| {
            g.intersect(r).is_some()
        });
        let closest_t = throughput(closest, threads, |r| g.intersect(r).is_some());
        let any_t = throughput(any, threads, |r| g.intersect_p(r));
        out.push(BenchResult {
            options: opts,
            build_secs,
            closest: closest_t,
            any: any_t,
            rays: closest.len(),
        });
    }
    Ok(out)
}

/// Geometry of a parsed scene: world shapes (portals excluded), objects and instances.
pub fn scene_geometry(
    desc: &SceneDescription,
    ctx: &ShapeCtx,
    opts: BvhOptions,
) -> Result<Geometry, BuildError> {
    let mut b = GeometryBuilder::with_options(opts);
    for (i, s) in desc.shapes.iter().enumerate().filter(|(_, s)| !s.portal) {
        b.add_shape(s, i as u32, ctx)?;
    }
    let mut ids = Vec::new();
    for o in &desc.objects {
        let prims: Vec<u32> = (0..o.shapes.len() as u32).collect();
        ids.push(b.add_object(o, &prims, ctx)?);
    }
    for inst in desc.instances.iter().filter(|i| !i.portal) {
        if let Some(&id) = ids.get(inst.object) {
            b.add_instance(id, &inst.instance_to_world);
        }
    }
    Ok(b.build())
}

/// Geometry of a list of world shapes.
pub fn shapes_geometry(
    shapes: &[ShapeDesc],
    ctx: &ShapeCtx,
    opts: BvhOptions,
) -> Result<Geometry, BuildError> {
    let mut b = GeometryBuilder::with_options(opts);
    for (i, s) in shapes.iter().enumerate() {
        b.add_shape(s, i as u32, ctx)?;
    }
    Ok(b.build())
}

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
/// spheres tessellated with 48 segments and 24 rings, as in the file): used by the benchmark
/// until scenes can be parsed on this branch.
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
