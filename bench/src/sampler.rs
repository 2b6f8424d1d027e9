//! `luxfarm bench sampler`: throughput of the camera side of a sample on one thread: values
//! per second of each sampler, rays per second of a perspective camera with a thin lens, and
//! splats per second of the default (Mitchell) filter. Each measurement keeps a checksum of
//! its results so the work cannot be optimised away.

use glam::DMat4;
use luxfarm::camera::{Camera, FilmGeometry};
use luxfarm::filter::Filter;
use luxfarm::lxs::{CameraDesc, Entity, ParamValue, Xform};
use luxfarm::sampler::{Sampler, SamplerKind};
use std::process::ExitCode;
use std::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// Samples drawn from each sampler.
    #[arg(long, default_value_t = 1_000_000)]
    pub samples: u64,
    /// Dimensions drawn per sample after the camera's five (as 2D pairs).
    #[arg(long, default_value_t = 16)]
    pub dims: u32,
    /// Camera rays and filter splats.
    #[arg(long, default_value_t = 2_000_000)]
    pub rays: u64,
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    println!(
        "one thread; {} samples of 5 + {} dimensions, {} rays and splats; load average {}",
        a.samples,
        a.dims,
        a.rays,
        crate::support::loadavg()
    );
    let results = samplers(a.samples, a.dims)
        .into_iter()
        .chain(camera_and_filter(a.rays));
    for r in results {
        println!(
            "{:<34} {:>9.2} M/s   (checksum {:.6e})",
            r.name,
            r.per_second / 1e6,
            r.checksum
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// One measurement: what, how many per second, and a checksum that keeps the work alive.
#[derive(Clone, Debug)]
pub struct BenchResult {
    pub name: String,
    pub per_second: f64,
    pub checksum: f64,
}

fn timed(name: String, count: u64, work: impl FnOnce() -> f64) -> BenchResult {
    let t = Instant::now();
    let checksum = work();
    let secs = t.elapsed().as_secs_f64().max(1e-9);
    BenchResult {
        name,
        per_second: count as f64 / secs,
        checksum,
    }
}

/// Values per second of each sampler: `samples` samples over a 64-pixel row, each drawing
/// the camera dimensions and `dims` more as 2D pairs.
pub fn samplers(samples: u64, dims: u32) -> Vec<BenchResult> {
    [
        SamplerKind::Random,
        SamplerKind::LowDiscrepancy,
        SamplerKind::Sobol,
    ]
    .into_iter()
    .filter_map(|k| Sampler::new(k, 16).ok())
    .map(|s| {
        let values = samples * u64::from(5 + dims);
        timed(format!("sampler {:?} (values)", s.kind()), values, || {
            let mut acc = 0.0f64;
            for i in 0..samples {
                let mut st = s.start(1, 0, (i % 64) as u32, 0, i / 64);
                let cs = st.camera_sample();
                acc += f64::from(cs.p_film.x + cs.time);
                for _ in 0..dims / 2 {
                    let v = st.next_2d();
                    acc += f64::from(v.x + v.y);
                }
            }
            acc
        })
    })
    .collect()
}

/// Rays per second of a perspective camera with a thin lens, and splats per second of the
/// default (mitchell) filter.
pub fn camera_and_filter(n: u64) -> Vec<BenchResult> {
    let mut e = Entity {
        kind: "perspective".into(),
        ..Default::default()
    };
    e.params.add("lensradius", ParamValue::Float(vec![0.05]));
    e.params.add("focaldistance", ParamValue::Float(vec![3.0]));
    let desc = CameraDesc {
        entity: e,
        world_to_camera: Xform::fixed(DMat4::from_translation(glam::DVec3::new(0.0, 0.0, 4.0))),
        exterior: None,
    };
    let mut out = Vec::new();
    let Ok(cam) = Camera::build(&desc, &FilmGeometry::new(256, 256), &mut Vec::new()) else {
        return out;
    };
    let Ok(sampler) = Sampler::new(SamplerKind::Sobol, 16) else {
        return out;
    };
    out.push(timed("camera perspective+lens (rays)".into(), n, || {
        let mut acc = 0.0f64;
        for i in 0..n {
            let mut st = sampler.start(1, 0, (i % 256) as u32, ((i / 256) % 256) as u32, i);
            if let Some((r, _)) = cam.generate_ray(&st.camera_sample()) {
                acc += f64::from(r.d.x);
            }
        }
        acc
    }));
    if let Ok(f) = Filter::build(None, &mut Vec::new()) {
        out.push(timed("filter mitchell (splats)".into(), n, || {
            let mut acc = 0.0f64;
            for i in 0..n {
                let p = glam::Vec2::new((i % 251) as f32 * 1.013, (i % 241) as f32 * 0.987);
                f.splat(p, |x, _, w| acc += f64::from(w) + f64::from(x) * 1e-9);
            }
            acc
        }));
    }
    out
}
