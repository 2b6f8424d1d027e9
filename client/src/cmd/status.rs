//! `luxfarm status JOB [--json]`: one job's state and progress.

use super::farm_remote::{job_line, runtime, status, Remote};
use luxfarm_proto as pb;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    pub job: String,
    #[command(flatten)]
    pub remote: Remote,
    /// Print every field as JSON.
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let j = runtime()?.block_on(async {
        let mut c = a.remote.jobs()?;
        let r = c
            .get_job(pb::JobRef { id: a.job.clone() })
            .await
            .map_err(status)?;
        anyhow::Ok(r.into_inner())
    })?;
    if a.json {
        let v = serde_json::json!({
            "id": j.id, "name": j.name, "state": j.state, "reason": j.reason,
            "priority": j.priority, "width": j.width, "height": j.height,
            "samples": j.samples, "spp": j.spp, "haltspp": j.haltspp, "halttime": j.halttime,
            "haltthreshold": j.haltthreshold, "elapsed": j.elapsed,
            "samples_per_sec": j.samples_per_sec, "active_leases": j.active_leases,
            "merged_deltas": j.merged_deltas, "seed": j.seed, "convergence": j.convergence,
        });
        println!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        println!("{}", job_line(&j));
    }
    Ok(ExitCode::SUCCESS)
}
