//! The measurement of `luxfarm bench bvh`: builds the geometry with each BVH configuration
//! and casts the same incoherent rays through each.
//!
//! Closest-hit rays start at random points inside the scene bounds with random directions;
//! any-hit rays join two random points inside the bounds (shadow-ray-like). Rays are split
//! evenly across `threads` OS threads; each thread's CPU time is read from Linux's schedstat,
//! so a shared machine's rate per CPU-second received can be told from the wall-clock rate.

use glam::Vec3A;
use luxfarm::accel::bvh::BvhOptions;
use luxfarm::accel::{Geometry, GeometryBuilder};
use luxfarm::geometry::Ray;
use luxfarm::lxs::{SceneDescription, ShapeDesc};
use luxfarm::plugin::BuildError;
use luxfarm::shape::ShapeCtx;
use std::time::Instant;

/// Deterministic SplitMix64 generator of the rays.
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
