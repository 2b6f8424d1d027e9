//! `luxfarm bench bvh`: ray throughput of the BVH on incoherent rays (closest hit and any
//! hit), for every obvhs configuration or the default one.

use anyhow::Context;
use luxfarm::accel::bench::{self, BenchResult};
use luxfarm::accel::bvh::BvhOptions;
use luxfarm::shape::ShapeCtx;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// A scene to load (needs the .lxs parser; the built-in Cornell geometry otherwise).
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Use a synthetic scene of K³ tessellated spheres (64 segments) in a box instead.
    #[arg(long, value_name = "K")]
    pub spheres: Option<usize>,
    /// Number of rays of each kind.
    #[arg(long, default_value_t = 2_000_000)]
    pub rays: usize,
    /// Threads casting rays.
    #[arg(long, default_value_t = 2)]
    pub threads: usize,
    /// Compare all obvhs configurations (layout, build quality, leaf size).
    #[arg(long)]
    pub all: bool,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let (name, shapes) = match (&args.scene, args.spheres) {
        (Some(path), _) => anyhow::bail!(
            "{}: loading scenes needs the .lxs parser, which is not on this branch yet; \
             run without --scene for the built-in Cornell geometry",
            path.display()
        ),
        (None, Some(k)) => (format!("{k}³ spheres"), bench::sphere_field(k, 64)),
        (None, None) => ("cornell-mesh geometry".to_string(), bench::cornell_like()),
    };
    let options = if args.all {
        bench::candidate_options()
    } else {
        vec![BvhOptions::default()]
    };
    println!(
        "{name}: {} rays of each kind, {} threads",
        args.rays, args.threads
    );
    let results = bench::bench(
        &shapes,
        &ShapeCtx::default(),
        &options,
        args.rays,
        args.threads,
    )
    .context("building the benchmark geometry")?;
    println!(
        "{:<24} {:>9} {:>14} {:>12} {:>10}",
        "configuration", "build ms", "closest Mray/s", "any Mray/s", "hit rate"
    );
    for r in &results {
        print_row(r);
    }
    if let Some(best) = results
        .iter()
        .max_by(|a, b| a.closest_mrays.total_cmp(&b.closest_mrays))
    {
        println!("fastest closest-hit: {}", best.options);
    }
    Ok(ExitCode::SUCCESS)
}

fn print_row(r: &BenchResult) {
    println!(
        "{:<24} {:>9.1} {:>14.2} {:>12.2} {:>9.1}%",
        r.options.to_string(),
        r.build_secs * 1e3,
        r.closest_mrays,
        r.any_mrays,
        100.0 * r.closest_hits as f64 / r.rays.max(1) as f64
    );
}
