//! `luxfarm fetch JOB [--format png|exr|flm] [-o FILE]`: downloads an output of a job.

use super::farm_remote::{runtime, status, Remote};
use luxfarm_proto as pb;
use std::path::PathBuf;
use std::process::ExitCode;
use tokio_stream::StreamExt;

#[derive(clap::Args)]
pub struct Args {
    pub job: String,
    #[command(flatten)]
    pub remote: Remote,
    /// png (tonemapped), exr (linear) or flm (the merged film).
    #[arg(long, default_value = "png", value_parser = ["png", "exr", "flm"])]
    pub format: String,
    /// Output file (default: JOB.FORMAT).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let bytes = runtime()?.block_on(fetch(&a.remote, &a.job, &a.format))?;
    let out = a
        .output
        .unwrap_or_else(|| PathBuf::from(format!("{}.{}", a.job, a.format)));
    std::fs::write(&out, &bytes)?;
    eprintln!("wrote {} ({} bytes)", out.display(), bytes.len());
    Ok(ExitCode::SUCCESS)
}

/// Downloads one output of a job.
pub async fn fetch(remote: &Remote, id: &str, format: &str) -> anyhow::Result<Vec<u8>> {
    let mut c = remote.jobs()?;
    let req = pb::FetchRequest {
        id: id.into(),
        format: format.into(),
    };
    let mut s = c.fetch(req).await.map_err(status)?.into_inner();
    let mut out = Vec::new();
    while let Some(chunk) = s.next().await {
        out.extend_from_slice(&chunk.map_err(status)?.data);
    }
    Ok(out)
}
