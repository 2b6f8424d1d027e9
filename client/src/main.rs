//! `luxfarm`: the command-line tool. Each subcommand lives in its own file under `cmd/`, but
//! `bench`, whose benchmarks live in the `luxfarm-bench` crate.

use clap::{Parser, Subcommand};
use std::process::ExitCode;

mod cmd;
mod exit;
mod isa;

#[derive(Parser)]
#[command(
    name = "luxfarm",
    version,
    about = "A network render farm for LuxRender scenes"
)]
struct Cli {
    /// Log filter (e.g. "info", "luxfarm=debug"); also read from RUST_LOG.
    #[arg(long, global = true, default_value = "warn")]
    log: String,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Parse a scene and print a summary, or its SceneDescription as JSON.
    Parse(cmd::parse::Args),
    /// Render a scene locally on all cores and write the outputs its Film asks for.
    Render(cmd::render::Args),
    /// Compare two images (RMSE, relative MSE, mean ratio; the second is the reference).
    CompareImage(cmd::compare_image::Args),
    /// FLM film tools: info, merge, compare, tonemap.
    Flm(cmd::flm::Args),
    /// Run TestSuite-style regression tests (.cfg files): render, compare with the reference
    /// films as luxcomp does, print a pass/fail table.
    Regress(cmd::regress::Args),
    /// Speed against accuracy: render under several configurations, measure the error
    /// against a reference over time, write a CSV, an HTML report and figures.
    Study(cmd::study::Args),
    /// Submit a scene (bundled with what it references) to a master.
    Submit(cmd::submit::Args),
    /// List the master's jobs.
    Jobs(cmd::jobs::Args),
    /// Show one job.
    Status(cmd::status::Args),
    /// Follow a job with a progress bar until it ends.
    Watch(cmd::watch::Args),
    /// Download a job's PNG, EXR or FLM.
    Fetch(cmd::fetch::Args),
    /// Cancel a job.
    Cancel(cmd::cancel::Args),
    /// List the master's workers.
    Workers(cmd::workers::Args),
    /// Manage the master's user tokens (admin): add, list, revoke.
    Token(cmd::token::Args),
    /// Make a private CA and the master's TLS certificate (DIR/ca.crt, DIR/master.crt, keys).
    Certs(cmd::certs::Args),
    /// Run a master (gRPC, REST and the dashboard on one address).
    Server(cmd::server::Args),
    /// Run a worker for a master.
    Worker(cmd::worker::Args),
    /// Benchmarks (not tests).
    #[command(subcommand)]
    Bench(luxfarm_bench::Command),
}

fn main() -> ExitCode {
    isa::check_start();
    isa::dispatch();
    let cli = Cli::parse();
    init_logging(&cli.log);
    let result = match cli.command {
        Command::Parse(a) => cmd::parse::run(a),
        Command::Render(a) => cmd::render::run(a),
        Command::CompareImage(a) => cmd::compare_image::run(a),
        Command::Flm(a) => cmd::flm::run(a),
        Command::Regress(a) => cmd::regress::run(a),
        Command::Study(a) => cmd::study::run(a),
        Command::Submit(a) => cmd::submit::run(a),
        Command::Jobs(a) => cmd::jobs::run(a),
        Command::Status(a) => cmd::status::run(a),
        Command::Watch(a) => cmd::watch::run(a),
        Command::Fetch(a) => cmd::fetch::run(a),
        Command::Cancel(a) => cmd::cancel::run(a),
        Command::Workers(a) => cmd::workers::run(a),
        Command::Token(a) => cmd::token::run(a),
        Command::Certs(a) => cmd::certs::run(a),
        Command::Server(a) => cmd::server::run(a),
        Command::Worker(a) => cmd::worker::run(a),
        Command::Bench(b) => luxfarm_bench::run(b),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(exit::code(&e))
        }
    }
}

fn init_logging(default: &str) {
    let filter = tracing_subscriber::EnvFilter::try_from_default_env()
        .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new(default));
    tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        .init();
}
