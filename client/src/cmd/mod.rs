//! One module per subcommand.

pub mod bench_bvh;
pub mod bench_parse;
pub mod bench_flm;
pub mod flm;
pub mod parse;

/// `luxfarm bench ...`: benchmarks (not tests).
#[derive(clap::Subcommand)]
pub enum BenchCommand {
    /// FLM decode + merge and encode throughput of a 1080p delta.
    Flm(bench_flm::Args),
}
pub mod compare_image;
pub mod parse;
pub mod render;
