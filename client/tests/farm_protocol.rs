//! The worker protocol against a real master, driven by a protocol client in the test (no
//! rendering): a replayed (lease, seq) upload is ignored, an upload of the wrong resolution is
//! refused and leaves the job untouched, halting on haltspp tells the lease to stop, and the
//! merged film equals the sum of the acknowledged deltas; the jobs service's Fetch takes the
//! PNG size and tonemapping REST's image.png takes.

mod farm_common;

use farm_common::*;
use luxfarm::film::Film;
use luxfarm_proto as pb;
use luxfarm_proto::connect;
use luxfarm_wire::codec;

fn rt() -> tokio::runtime::Runtime {
    tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .unwrap()
}

async fn upload(
    c: &mut pb::worker_client::WorkerClient<connect::AuthChannel>,
    worker: &str,
    lease: &str,
    seq: u64,
    film: &Film,
) -> Result<pb::UploadAck, tonic::Status> {
    let bytes = codec::encode(film);
    let chunks = vec![
        pb::UploadChunk {
            part: Some(pb::upload_chunk::Part::Header(pb::UploadHeader {
                worker_id: worker.into(),
                lease_id: lease.into(),
                seq,
                encoding: "lxd1".into(),
                last: false,
                size: bytes.len() as u64,
                master_instance: String::new(),
                sampling_map_version: None,
            })),
        },
        pb::UploadChunk {
            part: Some(pb::upload_chunk::Part::Data(bytes)),
        },
    ];
    c.upload_delta(tokio_stream::iter(chunks))
        .await
        .map(|r| r.into_inner())
}

/// Registers a one-thread worker and takes its first assignment; returns a client carrying
/// the worker's credential.
async fn register_and_lease(
    url: &str,
) -> (
    pb::worker_client::WorkerClient<connect::AuthChannel>,
    pb::RegisterReply,
    pb::Assignment,
) {
    let reg = connect::worker_client(connect::channel(url, None, None).unwrap())
        .register(pb::RegisterRequest {
            name: "t".into(),
            threads: 1,
            worker_id: String::new(),
            protocol: pb::PROTOCOL_VERSION,
            build: pb::BUILD.into(),
            worker_token: String::new(),
            ..Default::default()
        })
        .await
        .unwrap()
        .into_inner();
    let mut c =
        connect::worker_client(connect::channel(url, Some(&reg.worker_token), None).unwrap());
    let a = c
        .next_assignment(pb::NextRequest {
            worker_id: reg.worker_id.clone(),
        })
        .await
        .unwrap()
        .into_inner()
        .assignment
        .expect("an assignment");
    (c, reg, a)
}

fn delta(w: u32, h: u32, value: f32, spp: f64) -> Film {
    let mut f = Film::new(w, h, vec!["default".into()]);
    for y in 0..h {
        for x in 0..w {
            f.add_splat(0, x, y, [value, value * 2.0, value * 0.5], 1.0, 1.0);
        }
    }
    f.add_sample_count(spp * (w * h) as f64);
    f
}

#[test]
fn replay_ignored_wrong_resolution_refused_and_halt_stops() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &[]);
    let scene = std::fs::read(small_scene(dir.path(), "p", (8, 6), "")).unwrap();
    // The frame option travels from the submission to the worker's assignment.
    let (st, job) = post_job(&s, scene, "?filename=p.lxs&haltspp=3&frame=12");
    assert_eq!(st, 201, "{job}");
    assert_eq!(job["frame"], 12);
    let id = job["id"].as_str().unwrap().to_string();
    let url = s.url();
    rt().block_on(async move {
        let (mut c, reg, a) = register_and_lease(&url).await;
        assert_eq!(a.job_id, id);
        assert_eq!((a.width, a.height), (8, 6));
        assert_eq!(a.frame, Some(12));
        let w = &reg.worker_id;
        let d1 = delta(8, 6, 0.25, 1.0);
        let ack = upload(&mut c, w, &a.lease_id, 1, &d1).await.unwrap();
        assert_eq!(ack.status, "merged");
        assert!(!ack.stop);
        // the same (lease, seq) again: ignored
        let ack = upload(&mut c, w, &a.lease_id, 1, &d1).await.unwrap();
        assert_eq!(ack.status, "duplicate");
        // wrong resolution: refused, job untouched
        let err = upload(&mut c, w, &a.lease_id, 2, &delta(16, 6, 1.0, 1.0))
            .await
            .unwrap_err();
        assert_eq!(err.code(), tonic::Code::InvalidArgument, "{err:?}");
        let v = tokio::task::block_in_place(|| get_json(&format!("{}/api/v1/jobs/{id}", s.url())));
        assert_eq!(v["samples"], 48.0, "{v}");
        assert_eq!(v["merged_deltas"], 1);
        assert_eq!(v["state"], "rendering");
        // haltspp counts against the sample extent's pixels (LuxRender's samplePerPass: 8 × 6
        // widened to 9 × 7 by the 0.5-wide box filter), so 3 spp are 189 samples: 144 more
        // reach them, the lease is told to stop
        let d2 = delta(8, 6, 0.5, 3.0);
        let ack = upload(&mut c, w, &a.lease_id, 2, &d2).await.unwrap();
        assert_eq!(ack.status, "merged");
        assert!(ack.stop, "haltspp reached: the worker must stop");
        let hb = c
            .heartbeat(pb::HeartbeatRequest {
                worker_id: w.clone(),
                lease_id: a.lease_id.clone(),
                samples: 0.0,
                pass_samples: 0.0,
            })
            .await
            .unwrap()
            .into_inner();
        assert!(hb.stop);
        // the last delta (empty) ends the lease; the job completes
        let empty = Film::new(8, 6, vec!["default".into()]);
        let mut last = pb::UploadHeader {
            worker_id: w.clone(),
            lease_id: a.lease_id.clone(),
            seq: 3,
            encoding: "lxd1".into(),
            last: true,
            size: codec::encode(&empty).len() as u64,
            master_instance: String::new(),
            sampling_map_version: None,
        };
        let chunks = vec![
            pb::UploadChunk {
                part: Some(pb::upload_chunk::Part::Header(last.clone())),
            },
            pb::UploadChunk {
                part: Some(pb::upload_chunk::Part::Data(codec::encode(&empty))),
            },
        ];
        c.upload_delta(tokio_stream::iter(chunks)).await.unwrap();
        let v = tokio::task::block_in_place(|| wait_job(&s, &id, 30, |v| v["state"] == "done"));
        assert_eq!(v["state"], "done", "{v}");
        assert_eq!(v["samples"], 48.0 * 4.0);
        // after the end, a late upload is refused as a conflict
        last.seq = 4;
        let chunks = vec![
            pb::UploadChunk {
                part: Some(pb::upload_chunk::Part::Header(last)),
            },
            pb::UploadChunk {
                part: Some(pb::upload_chunk::Part::Data(codec::encode(&d1))),
            },
        ];
        let err = c
            .upload_delta(tokio_stream::iter(chunks))
            .await
            .unwrap_err();
        assert_eq!(err.code(), tonic::Code::FailedPrecondition);
        // the final checkpoint is the exact sum of the merged deltas
        let ckpt = files_under(&s.data.join("jobs").join(&id))
            .into_iter()
            .find(|p| p.extension().is_some_and(|e| e == "lxd"))
            .expect("a checkpoint");
        let merged = codec::decode(&std::fs::read(ckpt).unwrap()).unwrap();
        let mut expect = d1.clone();
        expect.merge(&d2).unwrap();
        expect.merge(&empty).unwrap();
        assert_eq!(merged, expect);
        // outputs are served
        tokio::task::block_in_place(|| {
            let png = http()
                .get(format!("{}/api/v1/jobs/{id}/image.png", s.url()))
                .send()
                .unwrap();
            assert_eq!(png.status().as_u16(), 200);
            let etag = png.headers()["etag"].to_str().unwrap().to_string();
            assert!(png.bytes().unwrap().starts_with(b"\x89PNG"));
            let again = http()
                .get(format!("{}/api/v1/jobs/{id}/image.png", s.url()))
                .header("if-none-match", etag)
                .send()
                .unwrap();
            assert_eq!(again.status().as_u16(), 304);
            let flm = http()
                .get(format!("{}/api/v1/jobs/{id}/film.flm", s.url()))
                .send()
                .unwrap();
            assert_eq!(flm.status().as_u16(), 200);
            let (film, _) = luxfarm::film::flm::read_flm(&flm.bytes().unwrap()[..]).unwrap();
            assert_eq!(film.total_samples(), 48.0 * 4.0);
        });
    });
}

/// PNG width and height from its IHDR chunk.
fn png_size(png: &[u8]) -> (u32, u32) {
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n", "not a PNG");
    let be = |i: usize| u32::from_be_bytes(png[i..i + 4].try_into().unwrap());
    (be(16), be(20))
}

/// gRPC Fetch takes image.png's size and tonemapping: the same bytes as the REST query with
/// the same parameters, and the same errors for unknown or misplaced parameters.
#[test]
fn fetch_takes_the_size_and_tonemapping_of_image_png() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &[]);
    let scene = std::fs::read(small_scene(dir.path(), "f", (8, 6), "")).unwrap();
    let (st, job) = post_job(&s, scene, "?filename=f.lxs&haltspp=100");
    assert_eq!(st, 201, "{job}");
    let id = job["id"].as_str().unwrap().to_string();
    let (url, api) = (s.url(), s.api(&format!("/jobs/{id}/image.png")));
    let rest = |query: &str| -> Vec<u8> {
        let r = http().get(format!("{api}{query}")).send().expect("GET");
        assert_eq!(r.status().as_u16(), 200, "{query}");
        r.bytes().unwrap().to_vec()
    };
    rt().block_on(async move {
        let (mut w, reg, a) = register_and_lease(&url).await;
        let d = delta(8, 6, 0.25, 1.0);
        let ack = upload(&mut w, &reg.worker_id, &a.lease_id, 1, &d)
            .await
            .unwrap();
        assert_eq!(ack.status, "merged");

        let jobs = connect::jobs_client(connect::channel(&url, None, None).unwrap());
        let fetch = |max_size: u32, format: &str, tm: &[(&str, &str)]| {
            let req = pb::FetchRequest {
                id: id.clone(),
                format: format.into(),
                max_size,
                tonemap: tm
                    .iter()
                    .map(|(k, v)| (k.to_string(), v.to_string()))
                    .collect(),
            };
            let mut jobs = jobs.clone();
            async move {
                let mut s = jobs.fetch(req).await?.into_inner();
                let mut out = Vec::new();
                while let Some(c) = tokio_stream::StreamExt::next(&mut s).await {
                    out.extend_from_slice(&c?.data);
                }
                Ok::<_, tonic::Status>(out)
            }
        };
        let plain = fetch(0, "png", &[]).await.unwrap();
        assert_eq!(png_size(&plain), (8, 6));
        let q = "?kernel=linear&linear_exposure=8&gamma=1.8";
        let tm = [
            ("kernel", "linear"),
            ("linear_exposure", "8"),
            ("gamma", "1.8"),
        ];
        let toned = fetch(0, "png", &tm).await.unwrap();
        assert_ne!(toned, plain, "the tonemapping must change the image");
        let small = fetch(4, "png", &[]).await.unwrap();
        assert_eq!(png_size(&small), (4, 3));
        tokio::task::block_in_place(|| {
            assert_eq!(plain, rest(""));
            assert_eq!(toned, rest(q));
            assert_eq!(small, rest("?max_size=4"));
        });
        for (size, format, tm) in [
            (0, "png", vec![("bogus", "1")]),
            (0, "png", vec![("kernel", "linear"), ("reinhard_burn", "2")]),
            (0, "png", vec![("linear_exposure", "-1")]),
            (0, "exr", vec![("kernel", "linear")]),
            (4, "flm", vec![]),
        ] {
            let err = fetch(size, format, &tm).await.unwrap_err();
            assert_eq!(
                err.code(),
                tonic::Code::InvalidArgument,
                "{format} {tm:?}: {err:?}"
            );
        }
    });
}

/// A worker of another protocol version is refused at registration with both versions named;
/// a lease is bound to the worker holding it: another registered worker (its own credential),
/// even knowing the worker and lease ids, can neither upload into it nor fail it.
#[test]
fn protocol_versions_and_leases_bound_to_their_worker() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &[]);
    let scene = std::fs::read(small_scene(dir.path(), "b", (8, 6), "")).unwrap();
    let (st, job) = post_job(&s, scene, "?filename=b.lxs&haltspp=3");
    assert_eq!(st, 201, "{job}");
    let id = job["id"].as_str().unwrap().to_string();
    let url = s.url();
    let api = s.api(&format!("/jobs/{id}"));
    rt().block_on(async move {
        // another protocol version
        let e = connect::worker_client(connect::channel(&url, None, None).unwrap())
            .register(pb::RegisterRequest {
                name: "old".into(),
                threads: 1,
                worker_id: String::new(),
                protocol: pb::PROTOCOL_VERSION + 1,
                build: "9.9.9".into(),
                worker_token: String::new(),
                ..Default::default()
            })
            .await
            .expect_err("another protocol version is refused");
        assert_eq!(e.code(), tonic::Code::FailedPrecondition, "{e:?}");
        let m = e.message();
        assert!(
            m.contains(&(pb::PROTOCOL_VERSION + 1).to_string())
                && m.contains(&pb::PROTOCOL_VERSION.to_string())
                && m.contains("9.9.9"),
            "{m}"
        );
        // the victim holds the lease; the intruder registers on its own
        let (_victim, vreg, a) = register_and_lease(&url).await;
        let ireg = connect::worker_client(connect::channel(&url, None, None).unwrap())
            .register(pb::RegisterRequest {
                name: "intruder".into(),
                threads: 1,
                worker_id: String::new(),
                protocol: pb::PROTOCOL_VERSION,
                build: pb::BUILD.into(),
                worker_token: String::new(),
                ..Default::default()
            })
            .await
            .unwrap()
            .into_inner();
        assert_ne!(ireg.worker_token, vreg.worker_token);
        let mut intruder =
            connect::worker_client(connect::channel(&url, Some(&ireg.worker_token), None).unwrap());
        // the victim's ids in the intruder's calls
        let e = upload(
            &mut intruder,
            &vreg.worker_id,
            &a.lease_id,
            1,
            &delta(8, 6, 1.0, 48.0),
        )
        .await
        .expect_err("an upload into another worker's lease is refused");
        assert_eq!(e.code(), tonic::Code::PermissionDenied, "{e:?}");
        let e = intruder
            .report_failure(pb::FailureReport {
                worker_id: vreg.worker_id.clone(),
                lease_id: a.lease_id.clone(),
                reason: "forged".into(),
            })
            .await
            .expect_err("a failure report for another worker's lease is refused");
        assert_eq!(e.code(), tonic::Code::PermissionDenied, "{e:?}");
        // the job is untouched
        let v = tokio::task::spawn_blocking(move || get_json(&api))
            .await
            .unwrap();
        assert_eq!(v["state"], "rendering", "{v}");
        assert_eq!(v["samples"].as_f64().unwrap_or(0.0), 0.0, "{v}");
    });
}
