//! `luxfarm submit SCENE [--haltspp N] [--halttime S] [--haltthreshold T] [--seed S]
//! [--priority P] [--frame N | --frames A-B[:step]] [--watch]`: bundles the scene with every file
//! it references and queues a job, or one job per frame of an animated scene (LightWave).
//!
//! With `--frames`, the bundle is made once and sent with each job (the master stores it once,
//! by content); job `i` renders frame `i` and is named `NAME_0012` (NAME: `--name`, else the
//! scene's file stem), and the importer names the outputs after the frame too
//! (`scene_0012.png`), so an animation spreads over the farm's workers as separate jobs.

use super::farm_remote::{job_line, runtime, status, Remote};
use super::frames::{frame_name, FrameRange};
use luxfarm_proto as pb;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// The scene (.lxs or .lws, bundled with what it references) or a ready .zip/.tar bundle.
    pub scene: PathBuf,
    #[command(flatten)]
    pub remote: Remote,
    /// Job name (default: the scene's file stem).
    #[arg(long)]
    pub name: Option<String>,
    #[arg(long)]
    pub haltspp: Option<f64>,
    #[arg(long)]
    pub halttime: Option<f64>,
    #[arg(long)]
    pub haltthreshold: Option<f64>,
    #[arg(long)]
    pub seed: Option<u64>,
    /// Higher runs first.
    #[arg(long)]
    pub priority: Option<i32>,
    /// The scene inside a .zip/.tar holding several.
    #[arg(long)]
    pub scene_in_bundle: Option<String>,
    /// The animation frame to render (animated scene formats).
    #[arg(long, allow_negative_numbers = true, conflicts_with = "frames")]
    pub frame: Option<i64>,
    /// Submit one job per frame: `A-B` or `A-B:step` (inclusive), e.g. `1-120` or `0-96:4`.
    #[arg(long, allow_hyphen_values = true)]
    pub frames: Option<FrameRange>,
    /// Follow the job until it ends (as `luxfarm watch`).
    #[arg(long)]
    pub watch: bool,
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let upload = luxfarm_wire::bundle::prepare(&a.scene)?;
    tracing::info!(
        files = upload.files.len(),
        bytes = upload.bytes.len(),
        "bundle ready"
    );
    let rt = runtime()?;
    let header = pb::SubmitHeader {
        file_name: upload.file_name.clone(),
        name: a.name.clone().unwrap_or_default(),
        haltspp: a.haltspp,
        halttime: a.halttime,
        haltthreshold: a.haltthreshold,
        seed: a.seed,
        priority: a.priority,
        scene: a.scene_in_bundle.clone().unwrap_or_default(),
        frame: a.frame,
    };
    let Some(range) = a.frames else {
        let job = rt.block_on(submit(&a.remote, header, upload.bytes))?;
        println!("{}", job.id);
        eprintln!("{}", job_line(&job));
        if a.watch {
            return super::watch::watch_job(&rt, &a.remote, &job.id);
        }
        return Ok(ExitCode::SUCCESS);
    };
    let base = a.name.clone().unwrap_or_else(|| {
        a.scene
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("scene")
            .to_string()
    });
    let mut ids = Vec::new();
    for frame in range.frames() {
        let h = pb::SubmitHeader {
            name: frame_name(&base, frame),
            frame: Some(frame),
            ..header.clone()
        };
        let job = rt.block_on(submit(&a.remote, h, upload.bytes.clone()))?;
        println!("{}", job.id);
        eprintln!("frame {frame}: {}", job_line(&job));
        ids.push(job.id);
    }
    if a.watch {
        let mut code = ExitCode::SUCCESS;
        for id in &ids {
            if super::watch::watch_job(&rt, &a.remote, id)? != ExitCode::SUCCESS {
                code = ExitCode::from(1);
            }
        }
        return Ok(code);
    }
    Ok(ExitCode::SUCCESS)
}

/// Streams a bundle to the master and returns the queued job.
pub async fn submit(
    remote: &Remote,
    header: pb::SubmitHeader,
    bytes: Vec<u8>,
) -> anyhow::Result<pb::JobInfo> {
    let mut chunks = vec![pb::SubmitChunk {
        part: Some(pb::submit_chunk::Part::Header(header)),
    }];
    for c in bytes.chunks(pb::CHUNK_BYTES) {
        chunks.push(pb::SubmitChunk {
            part: Some(pb::submit_chunk::Part::Data(c.to_vec())),
        });
    }
    let mut client = remote.jobs()?;
    let job = client
        .submit(tokio_stream::iter(chunks))
        .await
        .map_err(status)?
        .into_inner();
    Ok(job)
}
