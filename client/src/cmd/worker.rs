//! `luxfarm worker --master URL ...`: runs a worker (same options as `luxfarm-worker`).

use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub cfg: luxfarm_worker::Config,
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    super::farm_remote::runtime()?.block_on(luxfarm_worker::run(a.cfg))?;
    Ok(ExitCode::SUCCESS)
}
