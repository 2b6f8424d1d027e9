//! `luxfarm server ...`: runs the master (same options as `luxfarm-server`).

use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub cfg: luxfarm_server::Config,
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    super::farm_remote::runtime()?.block_on(luxfarm_server::run(a.cfg))?;
    Ok(ExitCode::SUCCESS)
}
