//! `luxfarm bench bvh`: ray throughput of the BVH on incoherent rays (closest hit and any
//! hit), for every obvhs configuration or the default one.
//!
//! The geometry (a scene file, or [`synthetic`] shapes) is built once per configuration and
//! the same rays are cast through each ([`measure`]); one row per configuration is printed.

pub mod measure;
pub mod synthetic;

use anyhow::Context;
use luxfarm::accel::bvh::BvhOptions;
use luxfarm::lxs::{parse_file, ParseOptions};
use luxfarm::shape::ShapeCtx;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Scene to load (default: ../shared/scenes/cornell/cornell-mesh.lxs).
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Use a synthetic scene of K³ tessellated spheres (64 segments) in a box instead.
    #[arg(long, value_name = "K", conflicts_with = "scene")]
    pub spheres: Option<usize>,
    /// Use the Cornell geometry generated in code instead of loading a scene.
    #[arg(long, conflicts_with_all = ["scene", "spheres"])]
    pub builtin: bool,
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

/// The shared Cornell mesh scene.
fn default_scene() -> PathBuf {
    crate::support::shared_dir().join("scenes/cornell/cornell-mesh.lxs")
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let options = if args.all {
        BvhOptions::candidates()
    } else {
        vec![BvhOptions::default()]
    };
    let results = if let Some(k) = args.spheres {
        let shapes = synthetic::sphere_field(k, 64);
        header(&format!("{k}³ tessellated spheres"), &args);
        let ctx = ShapeCtx::default();
        measure::bench(
            |o| measure::shapes_geometry(&shapes, &ctx, o),
            &options,
            args.rays,
            args.threads,
        )
    } else if args.builtin {
        let shapes = synthetic::cornell_like();
        header("Cornell geometry (generated)", &args);
        let ctx = ShapeCtx::default();
        measure::bench(
            |o| measure::shapes_geometry(&shapes, &ctx, o),
            &options,
            args.rays,
            args.threads,
        )
    } else {
        let path = args.scene.clone().unwrap_or_else(default_scene);
        let desc = parse_file(&path, &ParseOptions::default())
            .with_context(|| format!("parsing {}", path.display()))?;
        let ctx = ShapeCtx {
            files: path.parent().map(PathBuf::from).unwrap_or_default().into(),
            ..ShapeCtx::default()
        };
        header(&path.display().to_string(), &args);
        measure::bench(
            |o| measure::scene_geometry(&desc, &ctx, o),
            &options,
            args.rays,
            args.threads,
        )
    }
    .context("building the benchmark geometry")?;
    println!(
        "{:<24} {:>9} {:>22} {:>22} {:>9}",
        "configuration", "build ms", "closest Mray/s", "any-hit Mray/s", "hit rate"
    );
    for r in &results {
        print_row(r);
    }
    if let Some(best) = results
        .iter()
        .max_by(|a, b| a.closest.cpu_mrays.total_cmp(&b.closest.cpu_mrays))
    {
        println!("fastest closest-hit: {}", best.options);
    }
    Ok(ExitCode::SUCCESS)
}

fn header(name: &str, args: &Args) {
    println!(
        "{name}: {} rays of each kind, {} threads",
        args.rays, args.threads
    );
    println!("Mray/s: wall clock | per CPU-second received x threads (the machine may be shared)");
}

fn print_row(r: &measure::BenchResult) {
    println!(
        "{:<24} {:>9.1} {:>10.2} | {:>9.2} {:>10.2} | {:>9.2} {:>8.1}%",
        r.options.to_string(),
        r.build_secs * 1e3,
        r.closest.wall_mrays,
        r.closest.cpu_mrays,
        r.any.wall_mrays,
        r.any.cpu_mrays,
        100.0 * r.closest.hits as f64 / r.rays.max(1) as f64
    );
}
