//! `luxfarm parse SCENE.lxs [--json]` (the parser lands with the foundation issue).

use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// The .lxs scene file.
    pub scene: PathBuf,
    /// Print the whole SceneDescription as JSON instead of a summary.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    eprintln!(
        "error: {}: the .lxs parser is not built yet",
        args.scene.display()
    );
    Ok(ExitCode::from(2))
}
