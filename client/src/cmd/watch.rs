//! `luxfarm watch JOB`: a progress bar following a job until it ends (exit status 0 when done,
//! 1 when cancelled or failed).

use super::farm_remote::{is_final, runtime, status, Remote};
use indicatif::{ProgressBar, ProgressStyle};
use luxfarm_proto as pb;
use std::process::ExitCode;
use tokio_stream::StreamExt;

#[derive(clap::Args)]
pub struct Args {
    pub job: String,
    #[command(flatten)]
    pub remote: Remote,
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    watch_job(&runtime()?, &a.remote, &a.job)
}

/// Follows a job with a progress bar; the exit code tells how it ended.
pub fn watch_job(
    rt: &tokio::runtime::Runtime,
    remote: &Remote,
    id: &str,
) -> anyhow::Result<ExitCode> {
    let last = rt.block_on(follow(remote, id, |_| {}))?;
    Ok(if last.state == "done" {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

/// Streams a job's progress into a progress bar until it ends; `each` sees every update.
pub async fn follow(
    remote: &Remote,
    id: &str,
    mut each: impl FnMut(&pb::JobInfo),
) -> anyhow::Result<pb::JobInfo> {
    let mut c = remote.jobs()?;
    let mut stream = c
        .watch(pb::JobRef { id: id.into() })
        .await
        .map_err(status)?
        .into_inner();
    let bar = ProgressBar::new(1000);
    bar.set_style(
        ProgressStyle::with_template("{spinner} [{elapsed_precise}] {bar:40} {percent:>3}% {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut last = None;
    while let Some(info) = stream.next().await {
        let j = info.map_err(status)?;
        each(&j);
        bar.set_position((fraction(&j) * 1000.0) as u64);
        bar.set_message(format!(
            "{} {:.1} spp {:.0} samples/s {} workers",
            j.state, j.spp, j.samples_per_sec, j.active_leases
        ));
        let done = is_final(&j.state);
        last = Some(j);
        if done {
            break;
        }
    }
    bar.finish();
    let last = last.ok_or_else(|| anyhow::anyhow!("the master closed the watch"))?;
    if last.reason.is_empty() {
        eprintln!("{} {}", last.id, last.state);
    } else {
        eprintln!(
            "{} {}: {}",
            last.id,
            last.state,
            super::farm_remote::printable(&last.reason)
        );
    }
    Ok(last)
}

/// Progress toward the nearest halt rule, in [0, 1].
fn fraction(j: &pb::JobInfo) -> f64 {
    if is_final(&j.state) {
        return 1.0;
    }
    let by_spp = j.haltspp.map(|h| j.spp / h.max(1e-9));
    let by_time = j.halttime.map(|t| j.elapsed / t.max(1e-9));
    by_spp
        .into_iter()
        .chain(by_time)
        .fold(0.0f64, f64::max)
        .clamp(0.0, 1.0)
}
