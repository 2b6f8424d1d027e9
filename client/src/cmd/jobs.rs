//! `luxfarm jobs`: lists the master's jobs in scheduling order.

use super::farm_remote::{job_line, runtime, status, Remote};
use luxfarm_proto as pb;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub remote: Remote,
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let jobs = runtime()?.block_on(async {
        let mut c = a.remote.jobs()?;
        let r = c.list_jobs(pb::ListJobsRequest {}).await.map_err(status)?;
        anyhow::Ok(r.into_inner().jobs)
    })?;
    for j in &jobs {
        println!("{}", job_line(j));
    }
    Ok(ExitCode::SUCCESS)
}
