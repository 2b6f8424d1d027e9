//! `luxfarm-worker`: a slave node as its own binary (same as `luxfarm worker`).

use clap::Parser;

#[derive(Parser)]
#[command(
    name = "luxfarm-worker",
    version,
    about = "luxfarm worker: renders leases for a master"
)]
struct Cli {
    #[command(flatten)]
    cfg: luxfarm_worker::Config,
}

#[tokio::main]
async fn main() -> anyhow::Result<()> {
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info")),
        )
        .with_writer(std::io::stderr)
        .init();
    luxfarm_worker::run(Cli::parse().cfg).await
}
