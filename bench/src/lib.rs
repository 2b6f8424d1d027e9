//! luxfarm's benchmarks, apart from the product code: the bodies of the `luxfarm bench ...`
//! subcommands. The `luxfarm` command parses `bench` into a [`Command`] and hands it to
//! [`run`]; each benchmark prints its report on standard output and returns the exit code.
//! Speed is measured here and reported, never asserted in tests.
//!
//! - [`bvh`]: ray throughput of the BVH on incoherent rays, per obvhs configuration.
//! - [`cornell`]: the Cornell scene against LuxCore, speed and RMSE.
//! - [`efficiency`]: light transport at equal wall time (path, bidirectional, each sampler,
//!   LuxCore's PATHCPU and BIDIRCPU) on the Cornell scene and a caustic variant.
//! - [`parse`]: parse speed and peak memory on a generated mesh scene.
//! - [`flm`]: FLM decode, merge and encode throughput.
//! - [`master`]: master capacity under simulated workers over gRPC.
//! - [`transport`]: the film delta encodings on a rendered delta.
//! - [`sampler`]: sampler values, camera rays and filter splats per second.
//! - [`unused`]: a scene with a thousand unused textures, materials and objects builds
//!   what the same scene without them builds, in the same time and memory.
//! - [`luxcore_textures`]: every texture class shared with LuxCore, per pixel against it.
//! - [`image_metrics`]: image error metrics, shared with `luxfarm compare-image`;
//!   [`support`]: helpers the benchmarks share.
//!
//! Like the command modules of a binary, the benchmarks return `anyhow` errors: this crate is
//! the body of a subcommand, not an API to build on.

pub mod bvh;
pub mod cornell;
pub mod efficiency;
pub mod flm;
pub mod image_metrics;
pub mod luxcore_textures;
pub mod master;
pub mod parse;
pub mod sampler;
pub mod support;
pub mod transport;
pub mod unused;

use std::process::ExitCode;

/// The benchmarks of `luxfarm bench`.
#[derive(clap::Subcommand)]
pub enum Command {
    /// Ray throughput of the BVH on incoherent rays (closest hit and any hit).
    Bvh(bvh::Args),
    /// Issue 3's Cornell benchmark side by side with LuxCore: samples/s and RMSE against the
    /// 2048-spp reference.
    Cornell(cornell::Args),
    /// Light transport at equal wall time: RMSE against a long reference of path,
    /// bidirectional and each sampler, beside LuxCore's PATHCPU and BIDIRCPU.
    Efficiency(efficiency::Args),
    /// Parse speed and peak memory on a generated mesh scene.
    Parse(parse::Args),
    /// FLM decode + merge and encode throughput of a 1080p delta.
    Flm(flm::Args),
    /// Master capacity: N simulated workers uploading full-frame deltas over gRPC.
    Master(master::Args),
    /// Film delta encodings (lxd1, FLM, lxd2) on a rendered delta: bytes, encode, decode.
    Transport(transport::Args),
    /// Sampler values, camera rays and filter splats per second (one thread).
    Sampler(sampler::Args),
    /// Build time and memory of a scene with N unused textures, materials and objects
    /// against the same scene without them (nothing unused is built).
    Unused(unused::Args),
    /// Issue 15: every texture class shared with LuxCore on a flat surface, per pixel.
    LuxcoreTextures(luxcore_textures::Args),
}

/// Runs one benchmark.
pub fn run(command: Command) -> anyhow::Result<ExitCode> {
    match command {
        Command::Bvh(a) => bvh::run(a),
        Command::Cornell(a) => cornell::run(a),
        Command::Efficiency(a) => efficiency::run(a),
        Command::Parse(a) => parse::run(a),
        Command::Flm(a) => flm::run(a),
        Command::Master(a) => master::run(a),
        Command::Transport(a) => transport::run(a),
        Command::Sampler(a) => sampler::run(a),
        Command::Unused(a) => unused::run(a),
        Command::LuxcoreTextures(a) => luxcore_textures::run(a),
    }
}
