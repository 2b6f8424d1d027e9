//! `luxfarm bench transport`: the film delta encodings compared on a real rendered delta (not a
//! test). Renders the shared Cornell scene at the chosen resolution for a few passes with the
//! render core (box filter as in the scene, and optionally a Mitchell variant, whose negative
//! lobes and fractional weights are harder to compress), then measures encode time, decode
//! time, bytes and exactness of: `lxd1` (raw f64), FLM (f32 + gzip, LuxRender's own; lossy
//! for f64 sums) and `lxd2` (planes + byte shuffle + lz4 or zstd; lossless).

use crate::support::{best, parse_res};
use luxfarm::film::{flm, Film, FilmParams};
use luxfarm::lxs::{self, ParseOptions};
use luxfarm::render::{Session, SessionOptions};
use luxfarm_wire::codec::{self, lxd2, Compressor};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// Film resolution WIDTHxHEIGHT.
    #[arg(long, default_value = "1920x1080")]
    pub res: String,
    /// Passes (samples per pixel) rendered into the delta.
    #[arg(long, default_value_t = 2)]
    pub spp: u32,
    /// Pixel filters to render with: box (the scene's) and/or mitchell.
    #[arg(long, value_delimiter = ',', default_value = "box,mitchell")]
    pub filters: Vec<String>,
    /// Repetitions per measurement (the best time is reported).
    #[arg(long, default_value_t = 3)]
    pub runs: u32,
    /// The Cornell scene to render (default: the shared one).
    #[arg(long)]
    pub scene: Option<PathBuf>,
}

/// Renders the scene at `res` with `filter` for `spp` passes; returns the delta film.
fn render_delta(scene: &Path, res: (u32, u32), filter: &str, spp: u32) -> anyhow::Result<Film> {
    let text = std::fs::read_to_string(scene)?;
    let mut out = String::new();
    for line in text.lines() {
        // The Film statement's first line holds the resolution; its other parameters follow.
        let line = if line.starts_with("Film ") {
            format!(
                "Film \"fleximage\" \"integer xresolution\" [{}] \"integer yresolution\" [{}]",
                res.0, res.1
            )
        } else if line.starts_with("PixelFilter ") && filter == "mitchell" {
            "PixelFilter \"mitchell\"".to_string()
        } else {
            line.to_string()
        };
        out.push_str(&line);
        out.push('\n');
    }
    let dir = tempfile::tempdir()?;
    let path = dir.path().join("bench.lxs");
    std::fs::write(&path, out)?;
    let desc =
        lxs::parse_file(&path, &ParseOptions::default()).map_err(|e| anyhow::anyhow!("{e}"))?;
    let opts = SessionOptions {
        threads: 0,
        seed: 1,
        stream: 0,
    };
    let mut session = Session::new(&desc, dir.path(), opts)?;
    for _ in 0..spp {
        session.render_pass();
    }
    Ok(session.take_film())
}

/// Largest relative difference of the sums (0 when bit-identical).
fn max_rel_error(a: &Film, b: &Film) -> f64 {
    let mut worst = 0.0f64;
    for g in 0..a.groups().len() {
        let (Some(x), Some(y)) = (a.buffer(g, 0), b.buffer(g, 0)) else {
            continue;
        };
        for (p, q) in x.iter().zip(y) {
            let scale = p.abs().max(1e-300);
            worst = worst.max((p - q).abs() / scale);
        }
    }
    worst
}

/// One measured encoding.
struct Row {
    name: String,
    bytes: usize,
    encode_s: f64,
    decode_s: f64,
    exact: bool,
    rel_err: f64,
}

fn measure(
    name: &str,
    film: &Film,
    runs: u32,
    enc: impl Fn(&Film) -> anyhow::Result<Vec<u8>>,
    dec: impl Fn(&[u8]) -> anyhow::Result<Film>,
) -> anyhow::Result<Row> {
    let (encode_s, bytes) = best(runs, || enc(film));
    let bytes = bytes?;
    let (decode_s, back) = best(runs, || dec(&bytes));
    let back = back?;
    Ok(Row {
        name: name.to_string(),
        bytes: bytes.len(),
        encode_s,
        decode_s,
        exact: &back == film,
        rel_err: max_rel_error(film, &back),
    })
}

fn rows_for(film: &Film, runs: u32) -> anyhow::Result<Vec<Row>> {
    let params = FilmParams::with_resolution(film.width(), film.height());
    let dec = |b: &[u8]| codec::decode(b).map_err(anyhow::Error::from);
    let mut rows = vec![measure(
        "lxd1 (raw f64)",
        film,
        runs,
        |f| Ok(codec::encode(f)),
        dec,
    )?];
    for level in [1u32, 6] {
        let enc = |f: &Film| -> anyhow::Result<Vec<u8>> {
            let mut v = Vec::new();
            flm::write_flm_level(f, &params, &mut v, level)?;
            Ok(v)
        };
        let flm_dec = |b: &[u8]| -> anyhow::Result<Film> { Ok(flm::read_flm(b)?.0) };
        rows.push(measure(
            &format!("FLM gzip {level} (f32)"),
            film,
            runs,
            enc,
            flm_dec,
        )?);
    }
    let comps = [
        ("lxd2 lz4", Compressor::Lz4),
        ("lxd2 zstd -1", Compressor::Zstd(-1)),
        ("lxd2 zstd 1", Compressor::Zstd(1)),
        ("lxd2 zstd 3", Compressor::Zstd(3)),
    ];
    for (name, comp) in comps {
        rows.push(measure(
            name,
            film,
            runs,
            |f| Ok(lxd2::encode(f, comp)),
            dec,
        )?);
    }
    Ok(rows)
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let res = parse_res(&a.res)?;
    let scene = a
        .scene
        .clone()
        .unwrap_or_else(|| crate::support::shared_dir().join("scenes/cornell/cornell.lxs"));
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    println!(
        "transport encodings of a rendered {}x{} delta, {} spp, {threads} threads",
        res.0, res.1, a.spp
    );
    for filter in &a.filters {
        let t = Instant::now();
        let film = render_delta(&scene, res, filter, a.spp)?;
        println!(
            "\n{filter} filter (rendered in {:.1} s; upload default: {}):",
            t.elapsed().as_secs_f64(),
            codec::DELTA_ENCODING
        );
        println!(
            "  {:<20} {:>9} {:>6} {:>10} {:>10}  exact",
            "encoding", "MB", "ratio", "encode ms", "decode ms"
        );
        let raw = (film.pixel_count() * 40) as f64;
        for r in rows_for(&film, a.runs)? {
            let exact = if r.exact {
                "yes".to_string()
            } else {
                format!("NO (max rel err {:.1e})", r.rel_err)
            };
            println!(
                "  {:<20} {:>9.2} {:>5.0}% {:>10.1} {:>10.1}  {exact}",
                r.name,
                r.bytes as f64 / 1e6,
                100.0 * r.bytes as f64 / raw,
                r.encode_s * 1e3,
                r.decode_s * 1e3
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}
