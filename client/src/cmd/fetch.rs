//! `luxfarm fetch JOB [--format png|exr|flm] [--max-size N] [--tonemap NAME=VALUE ...]
//! [-o FILE]`: downloads an output of a job (a PNG optionally smaller or tonemapped otherwise
//! than the scene says).

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
    /// png: the longer side at most this many pixels.
    #[arg(long)]
    pub max_size: Option<u32>,
    /// png: tonemapping over the scene's, as NAME=VALUE (repeatable): kernel (reinhard,
    /// linear, contrast, maxwhite or autolinear) and the kernel's parameters
    /// (reinhard_prescale, reinhard_postscale, reinhard_burn, linear_sensitivity,
    /// linear_exposure, linear_fstop, linear_gamma, contrast_ywa, gamma).
    #[arg(long, value_parser = name_value)]
    pub tonemap: Vec<(String, String)>,
    /// Output file (default: JOB.FORMAT).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

fn name_value(s: &str) -> Result<(String, String), String> {
    match s.split_once('=') {
        Some((n, v)) if !n.trim().is_empty() => Ok((n.trim().to_string(), v.trim().to_string())),
        _ => Err(format!("expected NAME=VALUE, got {s:?}")),
    }
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let req = pb::FetchRequest {
        id: a.job.clone(),
        format: a.format.clone(),
        max_size: a.max_size.unwrap_or(0),
        tonemap: a.tonemap.iter().cloned().collect(),
    };
    let bytes = runtime()?.block_on(fetch(&a.remote, req))?;
    let out = a
        .output
        .unwrap_or_else(|| PathBuf::from(format!("{}.{}", a.job, a.format)));
    std::fs::write(&out, &bytes)?;
    eprintln!("wrote {} ({} bytes)", out.display(), bytes.len());
    Ok(ExitCode::SUCCESS)
}

/// Downloads one output of a job.
pub async fn fetch(remote: &Remote, req: pb::FetchRequest) -> anyhow::Result<Vec<u8>> {
    let mut c = remote.jobs()?;
    let mut s = c.fetch(req).await.map_err(status)?.into_inner();
    let mut out = Vec::new();
    while let Some(chunk) = s.next().await {
        out.extend_from_slice(&chunk.map_err(status)?.data);
    }
    Ok(out)
}
