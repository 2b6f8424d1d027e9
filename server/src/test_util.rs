//! Helpers of the master's unit tests: a master with a small job leased to one worker, and
//! deltas uploaded through the worker path (`Farm::upload`), as a worker's would be.

use crate::admission::SubmitOptions;
use crate::config::Config;
use crate::farm::{lock, Farm, JobRt};
use crate::scene;
use luxfarm_proto as pb;
use std::path::Path;
use std::sync::Arc;

/// An 8 x 6 scene with a camera, a light and a floor.
pub const SCENE: &str = "LookAt 0 -3 1 0 0 1 0 0 1\nCamera \"perspective\"\n\
    Film \"fleximage\" \"integer xresolution\" [8] \"integer yresolution\" [6]\n\
    WorldBegin\nAttributeBegin\nAreaLightSource \"area\" \"color L\" [4 4 4]\n\
    Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" \
    [-0.5 -0.5 1.99 0.5 -0.5 1.99 0.5 0.5 1.99 -0.5 0.5 1.99]\nAttributeEnd\n\
    Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" \
    [-1 -1 0 1 -1 0 1 1 0 -1 1 0]\nWorldEnd\n";

/// A master in `dir` (configured by `configure`; no tick running) with one job of [`SCENE`]
/// (halttime one hour) leased to one worker: the master, the job, the worker's id and the
/// lease's.
pub fn leased_job(
    dir: &Path,
    configure: impl FnOnce(&mut Config),
) -> (Arc<Farm>, Arc<JobRt>, String, String) {
    let mut cfg = Config::local(dir.to_path_buf());
    configure(&mut cfg);
    let farm = Farm::open(cfg).unwrap();
    let opts = SubmitOptions {
        halttime: Some(3600.0),
        ..SubmitOptions::default()
    };
    farm.submit(SCENE.as_bytes(), "t.lxs", &opts).unwrap();
    let reg = pb::RegisterRequest {
        name: "w".into(),
        threads: 1,
        protocol: pb::PROTOCOL_VERSION,
        ..Default::default()
    };
    let worker = farm.register(&reg).unwrap().worker_id;
    let a = farm.assign(&worker).unwrap().unwrap();
    let rt = lock(&farm.jobs).get(&a.job_id).cloned().unwrap();
    (farm, rt, worker, a.lease_id)
}

/// Uploads delta `seq` of the lease (lxd2): `spp` samples per pixel, one splat that moves
/// with `seq`; asserts it was merged.
pub fn upload(farm: &Farm, rt: &JobRt, worker: &str, lease: &str, seq: u64, spp: f64) {
    let mut d = scene::new_film(&rt.info);
    d.add_splat(0, seq as u32 % 8, 0, [1.0, 0.5, 0.25], 1.0, 1.0);
    d.add_sample_count(spp * rt.info.pixels as f64);
    let data = crate::codec::encode_delta(&d);
    let h = pb::UploadHeader {
        lease_id: lease.into(),
        seq,
        encoding: "lxd2".into(),
        size: data.len() as u64,
        ..Default::default()
    };
    assert_eq!(farm.upload(worker, &h, &data).unwrap().status, "merged");
}
