//! `luxfarm bench flm`: FLM throughput (not a test). Decodes and merges a 1920x1080
//! single-group FLM delta from memory into an accumulated film, and encodes one, reporting
//! milliseconds and MB/s of decompressed data per gzip level.

use crate::support::best;
use luxfarm::film::{flm, Film, FilmParams, FlmDelta};
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[arg(long, default_value_t = 1920)]
    pub width: u32,
    #[arg(long, default_value_t = 1080)]
    pub height: u32,
    /// Repetitions per measurement (the best time is reported).
    #[arg(long, default_value_t = 5)]
    pub runs: u32,
    /// gzip levels to measure.
    #[arg(long, value_delimiter = ',', default_value = "0,1,4")]
    pub levels: Vec<u32>,
}

/// A film that looks like a render delta: smooth image plus per-pixel noise.
fn delta_film(w: u32, h: u32) -> Film {
    let mut f = Film::new(w, h, vec!["default".into()]);
    let mut s: u32 = 0x1234_5678;
    for y in 0..h {
        for x in 0..w {
            for _ in 0..4 {
                s ^= s << 13;
                s ^= s >> 17;
                s ^= s << 5;
                let n = (s >> 8) as f32 / (1u32 << 24) as f32;
                let base = 0.2 + 0.6 * (x as f32 / w as f32);
                let v = base * (0.5 + n);
                f.add_splat(0, x, y, [v * 0.9, v, v * 1.1], 1.0, 0.25 + 0.5 * n);
            }
        }
    }
    f.add_sample_count(f64::from(w) * f64::from(h) * 4.0);
    f
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let film = delta_film(a.width, a.height);
    let params = FilmParams::with_resolution(a.width, a.height);
    let raw_mb = film.pixel_count() as f64 * 20.0 / 1e6;
    println!(
        "FLM delta {}x{}, 1 group: {:.1} MB decompressed, {} threads",
        a.width,
        a.height,
        raw_mb,
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );
    let mut acc = Film::new(a.width, a.height, vec!["default".into()]);
    let mut delta = FlmDelta::default();
    for &level in &a.levels {
        let (enc_s, bytes) = best(a.runs, || {
            let mut v = Vec::with_capacity(film.pixel_count() * 20);
            flm::write_flm_level(&film, &params, &mut v, level).map(|_| v)
        });
        let bytes = bytes?;
        let (dec_s, r) = best(a.runs, || delta.decode(&bytes[..]).map(|_| ()));
        r?;
        let (add_s, r) = best(a.runs, || acc.add_delta(&delta));
        r?;
        let (merge_s, r) = best(a.runs, || {
            delta.decode(&bytes[..])?;
            acc.add_delta(&delta)
        });
        r?;
        let (oneshot_s, r) = best(a.runs, || flm::merge_flm(&mut acc, &bytes[..]).map(|_| ()));
        r?;
        let (slice_s, r) = best(a.runs, || delta.decode_slice(&bytes).map(|_| ()));
        r?;
        let (slice_merge_s, r) = best(a.runs, || {
            delta.decode_slice(&bytes)?;
            acc.add_delta(&delta)
        });
        r?;
        println!(
            "gzip level {level}: {:.1} MB compressed ({:.0}%)",
            bytes.len() as f64 / 1e6,
            100.0 * bytes.len() as f64 / (raw_mb * 1e6)
        );
        println!(
            "  encode        {:7.1} ms  {:7.1} MB/s",
            enc_s * 1e3,
            raw_mb / enc_s
        );
        println!(
            "  decode (zlib-rs stream) {:7.1} ms  {:7.1} MB/s",
            dec_s * 1e3,
            raw_mb / dec_s
        );
        println!("  add           {:7.1} ms", add_s * 1e3);
        println!(
            "  decode+merge  (stream)  {:7.1} ms  {:7.1} MB/s  (reused delta buffer)",
            merge_s * 1e3,
            raw_mb / merge_s
        );
        println!(
            "  merge_flm     {:7.1} ms  {:7.1} MB/s  (fresh buffer each time)",
            oneshot_s * 1e3,
            raw_mb / oneshot_s
        );
        println!(
            "  libdeflate decode       {:7.1} ms  {:7.1} MB/s",
            slice_s * 1e3,
            raw_mb / slice_s
        );
        println!(
            "  libdeflate decode+merge {:7.1} ms  {:7.1} MB/s  (reused delta buffer)",
            slice_merge_s * 1e3,
            raw_mb / slice_merge_s
        );
    }
    Ok(ExitCode::SUCCESS)
}
