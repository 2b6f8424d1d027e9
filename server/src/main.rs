//! `luxfarm-server`: the master as its own binary (same as `luxfarm server`).

use clap::Parser;

#[derive(Parser)]
#[command(
    name = "luxfarm-server",
    version,
    about = "luxfarm master: jobs, workers, film merging"
)]
struct Cli {
    #[command(flatten)]
    cfg: luxfarm_server::Config,
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
    luxfarm_server::run(Cli::parse().cfg).await
}
