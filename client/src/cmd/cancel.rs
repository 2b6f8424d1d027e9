//! `luxfarm cancel JOB`: cancels a queued or rendering job.

use super::farm_remote::{job_line, runtime, status, Remote};
use luxfarm_proto as pb;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    pub job: String,
    #[command(flatten)]
    pub remote: Remote,
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let j = runtime()?.block_on(async {
        let mut c = a.remote.jobs()?;
        let r = c
            .cancel_job(pb::JobRef { id: a.job.clone() })
            .await
            .map_err(status)?;
        anyhow::Ok(r.into_inner())
    })?;
    println!("{}", job_line(&j));
    Ok(ExitCode::SUCCESS)
}
