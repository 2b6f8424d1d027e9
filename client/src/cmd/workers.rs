//! `luxfarm workers`: the workers the master knows.

use super::farm_remote::{runtime, status, Remote};
use luxfarm_proto as pb;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub remote: Remote,
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let ws = runtime()?.block_on(async {
        let mut c = a.remote.jobs()?;
        let r = c
            .list_workers(pb::ListWorkersRequest {})
            .await
            .map_err(status)?;
        anyhow::Ok(r.into_inner().workers)
    })?;
    for w in &ws {
        let job = if w.job_id.is_empty() { "-" } else { &w.job_id };
        println!(
            "{:<18} {:<24} {:>3} threads  {:<9} job {job}  {:.0} samples  {:.0} samples/s",
            w.id,
            super::farm_remote::printable(&w.name),
            w.threads,
            w.state,
            w.samples,
            w.samples_per_sec
        );
    }
    Ok(ExitCode::SUCCESS)
}
