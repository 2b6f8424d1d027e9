//! Running one configuration of a study, and making the reference when none is given.
//!
//! A local run builds a render session from the configured scene, renders passes until its
//! share of the budget is spent, and measures the film at checkpoints: after the first pass,
//! then whenever the render time has grown by [`CHECKPOINT_GROWTH`]. Only the time spent in
//! passes counts (scene building and the measurements themselves are left out), so the
//! checkpoints are comparable across configurations. The film is never halted by the scene's
//! haltspp/halttime/haltthreshold: the study's budget alone decides.
//!
//! A farm run renders the scene file as written on a local farm (`farm_render`) with
//! halttime = its share of the budget and measures the FLM the master wrote, once.
//!
//! The reference, when not given, is a long local render of the scene as written with a seed
//! no configuration uses, cached as `reference.flm` in the output folder beside
//! `reference.json` (the scene's path, size and modification time, the seconds rendered);
//! a later study of the same, unchanged scene reuses it when it rendered at least as long.

use super::measure::{Error, Reference};
use anyhow::Context;
use luxfarm::film::{read_flm_file, write_flm_file, FilmParams};
use luxfarm::lxs::SceneDescription;
use luxfarm::render::{Session, SessionOptions};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Factor between the render times of successive checkpoints.
pub const CHECKPOINT_GROWTH: f64 = 1.4;
/// Seed of the reference render (no configuration renders with it).
const REFERENCE_SEED: u64 = 0x5eed_7e7e_0000_0001;

/// One measurement of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Checkpoint {
    /// Render seconds so far.
    pub seconds: f64,
    pub samples: f64,
    pub spp: f64,
    pub error: Option<Error>,
}

/// How local runs sample.
#[derive(Clone, Copy, Debug)]
pub struct LocalOptions {
    pub threads: usize,
    pub seed: u64,
    pub budget: f64,
}

/// Renders `desc` for `o.budget` seconds of passes, measuring at checkpoints.
pub fn run_local(
    desc: &SceneDescription,
    base_dir: &Path,
    o: LocalOptions,
    reference: &Reference,
) -> anyhow::Result<Vec<Checkpoint>> {
    let opts = SessionOptions {
        threads: o.threads,
        seed: o.seed,
        stream: 0,
    };
    let mut session = Session::new(desc, base_dir, opts)?;
    let tonemap = session.film_params().tonemap.clone();
    let (mut secs, mut samples, mut next) = (0.0f64, 0.0f64, 0.0f64);
    let mut out = Vec::new();
    while secs < o.budget {
        let start = Instant::now();
        let stats = session.render_pass();
        secs += start.elapsed().as_secs_f64();
        samples += stats.samples as f64;
        if stats.samples == 0 {
            anyhow::bail!("a pass rendered no samples (an empty film?)");
        }
        if secs >= next || secs >= o.budget {
            let film = session.film();
            out.push(Checkpoint {
                seconds: secs,
                samples,
                spp: film.spp(),
                error: Some(reference.error(film, &tonemap)?),
            });
            next = secs * CHECKPOINT_GROWTH;
        }
    }
    Ok(out)
}

/// Renders the scene file on a local farm of `workers` for `budget` seconds and measures its
/// FLM (error None when the scene's Film writes no FLM).
pub fn run_farm(
    scene: &Path,
    workers: usize,
    budget: f64,
    seed: u64,
    out_base: PathBuf,
    reference: &Reference,
    tonemap: &luxfarm::tonemap::TonemapParams,
) -> anyhow::Result<Checkpoint> {
    let o = crate::cmd::farm_render::render_job(crate::cmd::farm_render::Options {
        scene: scene.to_path_buf(),
        workers,
        threads: None,
        // The master's largest haltspp: the budget decides, not the scene's haltspp.
        haltspp: Some(1_000_000.0),
        halttime: Some(budget),
        haltthreshold: None,
        seed: Some(seed),
        output: Some(out_base),
        upload_interval: 1.0,
        frame: None,
    })?;
    if o.samples <= 0.0 {
        anyhow::bail!(
            "the farm merged no samples in {budget:.1} s (its workers did not finish a pass and \
             upload it within the share of the budget)"
        );
    }
    let flm = o
        .written
        .iter()
        .find(|p| p.extension().is_some_and(|e| e == "flm"));
    let error = match flm {
        Some(p) => {
            let (film, _) = read_flm_file(p).with_context(|| format!("reading {}", p.display()))?;
            Some(reference.error(&film, tonemap)?)
        }
        None => None,
    };
    Ok(Checkpoint {
        seconds: o.elapsed,
        samples: o.samples,
        spp: o.spp,
        error,
    })
}

/// What identifies a cached reference.
fn cache_key(scene: &Path) -> anyhow::Result<serde_json::Value> {
    let meta = std::fs::metadata(scene).with_context(|| format!("{}", scene.display()))?;
    let mtime = meta
        .modified()
        .ok()
        .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
        // Whole nanoseconds: an integer survives the JSON round trip exactly (a float read
        // back by serde_json may differ in its last bit, and the cache would never match).
        .map_or(0, |d| u64::try_from(d.as_nanos()).unwrap_or(u64::MAX));
    let path = std::fs::canonicalize(scene).unwrap_or_else(|_| scene.to_path_buf());
    Ok(json!({
        "scene": path.to_string_lossy(),
        "bytes": meta.len(),
        "modified": mtime,
    }))
}

/// The cached reference in `dir`, when it is of this scene and rendered at least `seconds`.
fn cached(dir: &Path, key: &serde_json::Value, seconds: f64) -> Option<PathBuf> {
    let text = std::fs::read_to_string(dir.join("reference.json")).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    let rendered = v.get("seconds")?.as_f64()?;
    let flm = dir.join("reference.flm");
    (v.get("key")? == key && rendered >= seconds && flm.is_file()).then_some(flm)
}

/// The reference FLM of the study: the cached one, or a new render of `seconds`.
pub fn make_reference(
    scene: &Path,
    desc: &SceneDescription,
    base_dir: &Path,
    threads: usize,
    seconds: f64,
    dir: &Path,
) -> anyhow::Result<PathBuf> {
    let key = cache_key(scene)?;
    if let Some(p) = cached(dir, &key, seconds) {
        eprintln!("study: reusing the cached reference {}", p.display());
        return Ok(p);
    }
    eprintln!("study: rendering the reference for {seconds:.0} s");
    let opts = SessionOptions {
        threads,
        seed: REFERENCE_SEED,
        stream: 0,
    };
    let mut session = Session::new(desc, base_dir, opts)?;
    let start = Instant::now();
    while start.elapsed().as_secs_f64() < seconds {
        if session.render_pass().samples == 0 {
            anyhow::bail!("the reference pass rendered no samples (an empty film?)");
        }
    }
    let rendered = start.elapsed().as_secs_f64();
    let flm = dir.join("reference.flm");
    let params: &FilmParams = session.film_params();
    write_flm_file(&flm, session.film(), params)
        .with_context(|| format!("writing {}", flm.display()))?;
    let meta = json!({ "key": key, "seconds": rendered, "spp": session.film().spp() });
    std::fs::write(dir.join("reference.json"), format!("{meta:#}\n"))?;
    Ok(flm)
}
