//! `luxfarm bench parse [--size-mb N]`: generates a large mesh scene (as exporters write them:
//! trianglemesh shapes with long index, point, normal and uv arrays) in a temporary
//! directory, parses it, and reports throughput and peak memory against the bytes of the
//! parsed numbers stored as f32/u32.

use anyhow::Context;
use luxfarm::lxs::{self, ParamValue, ParseOptions, SceneDescription};
use std::io::{BufWriter, Write};
use std::path::Path;
use std::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// Size of the generated scene in megabytes (at least 200 for the reported target).
    #[arg(long, default_value_t = 256)]
    pub size_mb: u64,
    /// Keep the generated file in this directory (created when missing) instead of a
    /// temporary one.
    #[arg(long)]
    pub dir: Option<std::path::PathBuf>,
}

/// Vertices per generated mesh.
const VERTS: usize = 50_000;

/// A small deterministic generator of coordinates.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn write_array(
    w: &mut impl Write,
    decl: &str,
    n: usize,
    mut f: impl FnMut(&mut dyn Write, usize) -> std::io::Result<()>,
) -> std::io::Result<()> {
    write!(w, "  \"{decl}\" [")?;
    for i in 0..n {
        if i % 12 == 0 {
            w.write_all(b"\n    ")?;
        }
        f(w, i)?;
    }
    w.write_all(b"\n  ]\n")
}

fn write_mesh(w: &mut impl Write, rng: &mut Lcg) -> std::io::Result<()> {
    writeln!(
        w,
        "AttributeBegin\nNamedMaterial \"grey\"\nShape \"trianglemesh\""
    )?;
    let tris = VERTS * 2;
    write_array(w, "integer indices", tris * 3, |w, _| {
        write!(w, "{} ", (rng.next() * VERTS as f64) as u32)
    })?;
    write_array(w, "point P", VERTS * 3, |w, _| {
        write!(w, "{:.6} ", rng.next() * 20.0 - 10.0)
    })?;
    write_array(w, "normal N", VERTS * 3, |w, _| {
        write!(w, "{:.6} ", rng.next() * 2.0 - 1.0)
    })?;
    write_array(w, "float uv", VERTS * 2, |w, _| {
        write!(w, "{:.6} ", rng.next())
    })?;
    writeln!(w, "AttributeEnd")
}

/// Writes the scene; returns its size in bytes.
fn generate(path: &Path, size_mb: u64) -> anyhow::Result<u64> {
    let f = std::fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
    let mut w = BufWriter::with_capacity(1 << 20, f);
    writeln!(
        w,
        "LookAt 0 -30 5 0 0 0 0 0 1\nCamera \"perspective\" \"float fov\" [40]\n\
         Film \"fleximage\" \"integer xresolution\" [640] \"integer yresolution\" [480]\n\
         WorldBegin\nMakeNamedMaterial \"grey\" \"string type\" [\"matte\"] \"color Kd\" [0.5 0.5 0.5]"
    )?;
    let mut rng = Lcg(42);
    let target = size_mb * 1_000_000;
    let mut written = 0;
    while written < target {
        write_mesh(&mut w, &mut rng)?;
        w.flush()?;
        written = w.get_ref().metadata()?.len();
    }
    writeln!(w, "WorldEnd")?;
    w.flush()?;
    Ok(w.get_ref().metadata()?.len())
}

/// Bytes of all numeric parameter values stored as 4-byte numbers.
fn number_bytes(d: &SceneDescription) -> u64 {
    let shapes = d
        .shapes
        .iter()
        .chain(d.objects.iter().flat_map(|o| o.shapes.iter()));
    let mut n: u64 = 0;
    for s in shapes {
        for p in &s.entity.params.params {
            n += match &p.value {
                ParamValue::Integer(v) => 4 * v.len() as u64,
                ParamValue::Float(v) => 4 * v.len() as u64,
                ParamValue::Point(v)
                | ParamValue::Vector(v)
                | ParamValue::Normal(v)
                | ParamValue::Color(v) => 12 * v.len() as u64,
                _ => 0,
            };
        }
    }
    n
}

/// A field of /proc/self/status in kB (VmHWM, VmRSS).
fn status_kb(field: &str) -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with(field))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// CPU time this process has run, in seconds (/proc/self/schedstat, Linux).
fn cpu_seconds() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/schedstat").ok()?;
    let ns: u64 = s.split_whitespace().next()?.parse().ok()?;
    Some(ns as f64 * 1e-9)
}

pub fn run(args: Args) -> anyhow::Result<std::process::ExitCode> {
    let tmp;
    let dir = match &args.dir {
        Some(d) => {
            std::fs::create_dir_all(d).with_context(|| format!("creating {}", d.display()))?;
            d.clone()
        }
        None => {
            tmp = tempfile::tempdir()?;
            tmp.path().to_path_buf()
        }
    };
    let path = dir.join("bench-mesh.lxs");
    let t0 = Instant::now();
    let size = generate(&path, args.size_mb)?;
    eprintln!(
        "generated {} ({:.1} MB) in {:.1} s",
        path.display(),
        size as f64 / 1e6,
        t0.elapsed().as_secs_f64()
    );
    // Reset the peak-RSS counter so it measures the parse only (Linux).
    let _ = std::fs::write("/proc/self/clear_refs", "5");
    let before = status_kb("VmHWM:").unwrap_or(0);
    let cpu0 = cpu_seconds();
    let t = Instant::now();
    let desc =
        lxs::parse_file(&path, &ParseOptions::default()).map_err(|e| anyhow::anyhow!("{e}"))?;
    let secs = t.elapsed().as_secs_f64();
    let cpu = cpu0.zip(cpu_seconds()).map(|(a, b)| b - a);
    let peak_kb = status_kb("VmHWM:").unwrap_or(0);
    let numbers = number_bytes(&desc);
    let peak = peak_kb * 1024;
    println!("file:           {:.1} MB", size as f64 / 1e6);
    println!("parse time:     {secs:.3} s");
    println!(
        "throughput:     {:.1} MB/s (wall clock)",
        size as f64 / 1e6 / secs
    );
    if let Some(cpu) = cpu {
        println!(
            "cpu time:       {cpu:.3} s, {:.1} MB/s per CPU second (the machine is shared)",
            size as f64 / 1e6 / cpu
        );
    }
    println!("shapes:         {}", desc.shapes.len());
    println!(
        "number bytes:   {:.1} MB (parsed values as f32/u32)",
        numbers as f64 / 1e6
    );
    println!(
        "peak RSS:       {:.1} MB (VmHWM; {:.1} MB before parsing)",
        peak as f64 / 1e6,
        (before * 1024) as f64 / 1e6
    );
    println!(
        "peak / numbers: {:.2}x",
        peak as f64 / numbers.max(1) as f64
    );
    drop(desc);
    Ok(std::process::ExitCode::SUCCESS)
}
