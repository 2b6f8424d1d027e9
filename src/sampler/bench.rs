//! Throughput of the camera-side of a sample: sampler values, camera rays and filter splats
//! (for a `luxfarm bench` command; speed is measured here, never asserted in tests).

use super::{Sampler, SamplerKind};
use crate::camera::{Camera, FilmGeometry};
use crate::filter::Filter;
use crate::lxs::{CameraDesc, Entity, Xform};
use glam::DMat4;
use std::time::Instant;

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
    e.params
        .add("lensradius", crate::lxs::ParamValue::Float(vec![0.05]));
    e.params
        .add("focaldistance", crate::lxs::ParamValue::Float(vec![3.0]));
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
