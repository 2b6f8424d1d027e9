//! `luxfarm submit SCENE [--haltspp N] [--halttime S] [--haltthreshold T] [--seed S]
//! [--priority P] [--watch]`: bundles the scene with every file it references and queues a job.

use super::farm_remote::{job_line, runtime, status, Remote};
use luxfarm_proto as pb;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// The scene (.lxs, bundled with what it references) or a ready .zip/.tar bundle.
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
    /// The .lxs inside a .zip/.tar holding several.
    #[arg(long)]
    pub scene_in_bundle: Option<String>,
    /// The animation frame to render (animated scene formats).
    #[arg(long, allow_negative_numbers = true)]
    pub frame: Option<i64>,
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
    let job = rt.block_on(async {
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
        submit(&a.remote, header, upload.bytes).await
    })?;
    println!("{}", job.id);
    eprintln!("{}", job_line(&job));
    if a.watch {
        return super::watch::watch_job(&rt, &a.remote, &job.id);
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
