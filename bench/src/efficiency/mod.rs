//! `luxfarm bench efficiency`: light transport at equal wall time. Each contestant (luxfarm's
//! integrators and samplers, LuxCore's PATHCPU and BIDIRCPU) renders the same scene for the
//! same wall-clock budget, one after the other in one run, and is measured by RMSE against a
//! long reference render.
//!
//! Two scenes, both built from `../shared/bench/cornell_scene.py`'s Cornell benchmark scene:
//! - `cornell`: the benchmark scene itself (`cornell-mesh.lxs`);
//! - `caustic`: the same box with its ceiling lamp shrunk to a 0.1 × 0.1 square of 25 times
//!   the radiance (the same power): the glass sphere throws a caustic onto the floor, and every
//!   diffuse surface sees the lamp through the glass. A path tracer finds those paths only by
//!   hitting the small lamp after a specular bounce; light tracing finds them directly;
//! - `caustic-small`: the same with a 0.04 × 0.04 lamp of 156.25 times the radiance;
//! - `caustic-covered`: the `caustic` lamp under a glass slab ([`COVER_Z`], half-side 0.3), so
//!   all of its light reaches the room through glass (a small light seen through glass, as a
//!   lamp behind a window pane): shadow rays find the lamp only past the slab's rim, at grazing
//!   angles that carry under 1 % of its power.
//!
//! **Depth** is in path segments (`--maxdepth`, default 16, where the Cornell box's light has
//! fallen below 10⁻⁴ so every integrator converges to one image): luxfarm's path `maxdepth`
//! D − 1, bidirectional `eyedepth` = `lightdepth` = D + 1 (vertices, camera and light
//! included), LuxCore's `path.pathdepth.total` D and `path.maxdepth` = `light.maxdepth` D.
//! Russian roulette is off everywhere.
//!
//! **The reference** of each scene is two independent halves rendered by LuxCore's BIDIRCPU
//! (`--reference-seconds` each, kept in `--reference-dir` and reused). Their mean is the
//! reference; half their squared difference estimates its own noise, which is subtracted from
//! each contestant's mean squared error: the "RMSE" column is the contestant's own error, the
//! raw one is printed beside it. Pixels whose reference luminance exceeds `--exclude-above`
//! (the lamp seen directly, where pixel-area sampling noise is the same for every integrator)
//! are left out, as is the mean ratio's.
//!
//! **Sampling** is uniform over the pixels for every contestant unless it says otherwise:
//! `:noiseaware` (luxfarm's noise-aware sampling) or `:adaptive` (LuxCore's adaptive
//! sampling, which its PATHCPU RANDOM and SOBOL samplers do by default; the script turns it off
//! otherwise, so that like is compared with like).
//!
//! Pixel conventions: LuxCore's rows sit one row lower than LuxRender's, so luxfarm's images
//! are compared one row up (as in `bench cornell`).

mod luxcore;
mod ours;
mod reference;

use crate::cornell::Run;
use anyhow::bail;
use luxcore::LuxCore;
use ours::Ours;
use reference::Reference;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// The shared material (default: ../shared beside the repository, else /work/shared).
    #[arg(long)]
    pub shared: Option<PathBuf>,
    /// Scenes to run, comma-separated (cornell, caustic, caustic-small, caustic-covered).
    #[arg(long, default_value = "caustic,cornell", value_delimiter = ',')]
    pub scenes: Vec<String>,
    /// Image width and height in pixels.
    #[arg(long, default_value_t = 128)]
    pub res: u32,
    /// Path depth in segments (see the module documentation).
    #[arg(long, default_value_t = 16)]
    pub maxdepth: u32,
    /// Wall seconds each contestant renders.
    #[arg(long, default_value_t = 30.0)]
    pub budget: f64,
    /// Rounds of all contestants (alternating); rates are medians, RMSE the root of the mean
    /// squared error over the rounds (beside it the median round's RMSE).
    #[arg(long, default_value_t = 1)]
    pub runs: usize,
    /// luxfarm's contestants as integrator:sampler[:noiseaware], comma-separated.
    #[arg(
        long,
        default_value = "path:random,path:sobol,path:sobol:noiseaware,path:metropolis,bidirectional:random,bidirectional:sobol,bidirectional:metropolis,bidirectional:erpt",
        value_delimiter = ','
    )]
    pub luxfarm: Vec<String>,
    /// LuxCore's contestants as ENGINE:SAMPLER[:adaptive], comma-separated ("" or none: leave
    /// LuxCore out). Without `:adaptive` LuxCore's adaptive sampling is off, as luxfarm's
    /// samplers without `noiseaware`.
    #[arg(
        long,
        default_value = "PATHCPU:RANDOM,PATHCPU:SOBOL,PATHCPU:SOBOL:adaptive,BIDIRCPU:RANDOM,BIDIRCPU:SOBOL,BIDIRCPU:METROPOLIS",
        value_delimiter = ','
    )]
    pub luxcore: Vec<String>,
    /// Render threads for all (0: all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Where the references are kept (default: target/bench-efficiency in the repository).
    #[arg(long)]
    pub reference_dir: Option<PathBuf>,
    /// Wall seconds of each of a reference's two halves, when they must be rendered.
    #[arg(long, default_value_t = 600.0)]
    pub reference_seconds: f64,
    /// Leave out pixels whose reference luminance exceeds this (the lamp seen directly).
    #[arg(long, default_value_t = 5.0)]
    pub exclude_above: f64,
    /// Python interpreter with pyluxcore.
    #[arg(long, default_value = "python3")]
    pub python: String,
    /// Write every run's linear RGB image here as PFM (`SCENE-CONTESTANT-ROUND.pfm`, rows
    /// top to bottom as rendered), to look at where a run's error lies.
    #[arg(long)]
    pub save_images: Option<PathBuf>,
}

/// Which scene: the benchmark scene, or its small-lamp caustic variant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Variant {
    Cornell,
    /// Lamp half-side and radiance factor, and the half-side of the glass slab under the
    /// lamp (0: none).
    Caustic {
        half: f64,
        scale: f64,
        cover: f64,
    },
}

/// The heights of the bottom and top faces of the `caustic-covered` glass slab (the lamp is
/// at 1.99, the ceiling at 2).
pub const COVER_Z: (f64, f64) = (1.95, 1.975);

/// The glass slab of half-side `c`: a closed box, its triangles wound so that every normal
/// points out, as (vertices, triangle indices).
pub fn cover_mesh(c: f64) -> ([[f64; 3]; 8], [[u32; 3]; 12]) {
    let (z0, z1) = COVER_Z;
    let p = [
        [-c, -c, z0],
        [c, -c, z0],
        [c, c, z0],
        [-c, c, z0],
        [-c, -c, z1],
        [c, -c, z1],
        [c, c, z1],
        [-c, c, z1],
    ];
    let tris = [
        [0, 2, 1],
        [0, 3, 2],
        [4, 5, 6],
        [4, 6, 7],
        [0, 1, 5],
        [0, 5, 4],
        [3, 7, 6],
        [3, 6, 2],
        [0, 4, 7],
        [0, 7, 3],
        [1, 2, 6],
        [1, 6, 5],
    ];
    (p, tris)
}

/// The caustic variant: a 0.1 × 0.1 lamp (the benchmark's is 0.5 × 0.5) of 25 times the
/// radiance.
const CAUSTIC: Variant = Variant::Caustic {
    half: 0.05,
    scale: 25.0,
    cover: 0.0,
};

/// The caustic lamp under a glass slab of half-side 0.3.
const CAUSTIC_COVERED: Variant = Variant::Caustic {
    half: 0.05,
    scale: 25.0,
    cover: 0.3,
};

/// The harder caustic variant: a 0.04 × 0.04 lamp of 156.25 times the radiance.
const CAUSTIC_SMALL: Variant = Variant::Caustic {
    half: 0.02,
    scale: 156.25,
    cover: 0.0,
};

impl Variant {
    fn parse(s: &str) -> anyhow::Result<Variant> {
        match s {
            "cornell" => Ok(Variant::Cornell),
            "caustic" => Ok(CAUSTIC),
            "caustic-small" => Ok(CAUSTIC_SMALL),
            "caustic-covered" => Ok(CAUSTIC_COVERED),
            other => bail!("scene {other:?}: cornell, caustic, caustic-small or caustic-covered"),
        }
    }

    fn name(self) -> &'static str {
        match self {
            Variant::Cornell => "cornell",
            Variant::Caustic { cover, .. } if cover > 0.0 => "caustic-covered",
            Variant::Caustic { half, .. } if half < 0.05 => "caustic-small",
            Variant::Caustic { .. } => "caustic",
        }
    }
}

/// Who renders.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Renderer {
    Luxfarm,
    LuxCore,
}

/// One contestant: a renderer with an integrator (engine) and a sampler, sampling every
/// pixel alike unless `adaptive`: luxfarm's `noiseaware` sampling (`:noiseaware`), LuxCore's
/// adaptive sampling (`:adaptive`, its PATHCPU samplers' default).
#[derive(Clone, Debug)]
pub struct Contestant {
    pub renderer: Renderer,
    pub integrator: String,
    pub sampler: String,
    pub adaptive: bool,
}

impl Contestant {
    fn parse(renderer: Renderer, s: &str) -> anyhow::Result<Contestant> {
        let mut parts = s.split(':').map(str::trim);
        let (Some(i), Some(smp)) = (parts.next(), parts.next()) else {
            bail!("contestant {s:?} is not INTEGRATOR:SAMPLER[:OPTION]");
        };
        let wanted = match renderer {
            Renderer::Luxfarm => "noiseaware",
            Renderer::LuxCore => "adaptive",
        };
        let adaptive = match parts.next() {
            None => false,
            Some(o) if o == wanted => true,
            Some(o) => bail!("contestant {s:?}: option {o:?} (only {wanted:?} here)"),
        };
        if parts.next().is_some() {
            bail!("contestant {s:?} is not INTEGRATOR:SAMPLER[:OPTION]");
        }
        if adaptive && renderer == Renderer::LuxCore && smp.eq_ignore_ascii_case("METROPOLIS") {
            bail!("contestant {s:?}: LuxCore's METROPOLIS sampler is not adaptive");
        }
        Ok(Contestant {
            renderer,
            integrator: i.to_string(),
            sampler: smp.to_string(),
            adaptive,
        })
    }

    fn label(&self) -> String {
        let (who, option) = match self.renderer {
            Renderer::Luxfarm => ("luxfarm", "+noiseaware"),
            Renderer::LuxCore => ("LuxCore", "+adaptive"),
        };
        let option = if self.adaptive { option } else { "" };
        format!("{who} {}+{}{option}", self.integrator, self.sampler)
    }

    /// Rows this renderer's images sit below LuxCore's (the reference's).
    fn row_shift(&self) -> i64 {
        match self.renderer {
            Renderer::Luxfarm => 1,
            Renderer::LuxCore => 0,
        }
    }
}

/// A contestant's medians over the runs.
struct Summary {
    who: Contestant,
    rate: f64,
    cpu_rate: f64,
    spp: f64,
    seconds: f64,
    rmse: f64,
    /// The median run's RMSE: the typical render, where `rmse` is the expected one.
    median_rmse: f64,
    raw_rmse: f64,
    mean_ratio: f64,
}

/// The RMSE over several runs: the root of their mean squared error. Errors of caustic
/// scenes are heavy-tailed (a rare path of huge value), so a median of a few runs would
/// mostly miss the fireflies every renderer pays for in expectation.
fn root_mean_square(v: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x * x, n + 1));
    if n == 0 {
        f64::NAN
    } else {
        (sum / n as f64).sqrt()
    }
}

/// Writes a square `res` × `res` RGB image as a little-endian PFM (PFM stores rows bottom
/// first, so they are written in reverse).
fn write_pfm(path: &std::path::Path, res: u32, rgb: &[[f32; 3]]) -> anyhow::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let mut out = format!("PF\n{res} {res}\n-1.0\n").into_bytes();
    let width = res as usize;
    for row in rgb.chunks(width.max(1)).rev() {
        for px in row {
            for c in px {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    std::fs::write(path, out)?;
    Ok(())
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

fn contestants(a: &Args, lc: &LuxCore) -> anyhow::Result<Vec<Contestant>> {
    let mut v = Vec::new();
    for s in a.luxfarm.iter().filter(|s| !s.is_empty()) {
        v.push(Contestant::parse(Renderer::Luxfarm, s)?);
    }
    let wanted: Vec<&String> = a
        .luxcore
        .iter()
        .filter(|s| !s.is_empty() && !s.eq_ignore_ascii_case("none"))
        .collect();
    if !wanted.is_empty() && !lc.available() {
        println!("LuxCore: pyluxcore not found, left out");
        return Ok(v);
    }
    for s in wanted {
        v.push(Contestant::parse(Renderer::LuxCore, s)?);
    }
    Ok(v)
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let shared = a.shared.clone().unwrap_or_else(crate::support::shared_dir);
    let repo = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    let ref_dir = a
        .reference_dir
        .clone()
        .unwrap_or_else(|| repo.join("target/bench-efficiency"));
    std::fs::create_dir_all(&ref_dir)?;
    let depth = a.maxdepth.clamp(2, 63);
    let lc = LuxCore {
        python: a.python.clone(),
        script: repo.join("scripts/luxcore_efficiency.py"),
        shared: shared.clone(),
        threads: a.threads,
        depth,
        res: a.res,
    };
    let who = contestants(&a, &lc)?;
    let tmp = tempfile::tempdir()?;
    println!("machine: {} (before)", crate::support::machine());
    println!(
        "{}x{} pixels, at most {depth} path segments, Russian roulette off, {} s per render",
        a.res, a.res, a.budget
    );
    let mut out = String::new();
    for scene in &a.scenes {
        let variant = Variant::parse(scene)?;
        let reference = Reference::load_or_render(&lc, variant, &ref_dir, a.reference_seconds)?;
        let mask = reference.mask(a.exclude_above);
        println!(
            "{}: reference {} (its own RMSE {:.5}); {} of {} pixels above luminance {} left out",
            variant.name(),
            reference.describe(),
            reference.own_rmse(&mask),
            mask.iter().filter(|m| !**m).count(),
            mask.len(),
            a.exclude_above
        );
        let ours = Ours::new(
            &shared.join("scenes/cornell/cornell-mesh.lxs"),
            variant,
            a.res,
            depth,
            a.threads,
        )?;
        let mut runs: Vec<Vec<Run>> = who.iter().map(|_| Vec::new()).collect();
        for i in 0..a.runs.max(1) {
            for (k, c) in who.iter().enumerate() {
                let seed = 100 + i as u64;
                let r = match c.renderer {
                    Renderer::Luxfarm => ours.run(c, a.budget, seed)?,
                    Renderer::LuxCore => lc.run(variant, c, a.budget, seed, tmp.path())?,
                };
                let m = reference.measure(&r.rgb, c.row_shift(), &mask);
                if let Some(dir) = &a.save_images {
                    let name = format!("{}-{}-{i}.pfm", variant.name(), c.label());
                    write_pfm(&dir.join(name.replace(['+', ' ', ':'], "_")), a.res, &r.rgb)?;
                }
                println!(
                    "{} run {i}: {:<36} {:>9.0} samples/s, {:>7.1} spp in {:.1} s, RMSE {:.5}",
                    variant.name(),
                    c.label(),
                    r.samples_per_sec,
                    r.spp,
                    r.seconds,
                    m.rmse
                );
                runs[k].push(r);
            }
        }
        let sums: Vec<Summary> = who
            .iter()
            .zip(&runs)
            .map(|(c, rs)| summarize(c, rs, &reference, &mask))
            .collect();
        out.push_str(&report(variant, &sums, a.budget));
    }
    println!("machine: {} (after)", crate::support::machine());
    print!("{out}");
    Ok(ExitCode::SUCCESS)
}

fn summarize(c: &Contestant, runs: &[Run], reference: &Reference, mask: &[bool]) -> Summary {
    let ms: Vec<_> = runs
        .iter()
        .map(|r| reference.measure(&r.rgb, c.row_shift(), mask))
        .collect();
    Summary {
        who: c.clone(),
        rate: median(runs.iter().map(|r| r.samples_per_sec).collect()),
        cpu_rate: median(runs.iter().map(|r| r.samples_per_cpu_sec).collect()),
        spp: median(runs.iter().map(|r| r.spp).collect()),
        seconds: median(runs.iter().map(|r| r.seconds).collect()),
        rmse: root_mean_square(ms.iter().map(|m| m.rmse)),
        median_rmse: median(ms.iter().map(|m| m.rmse).collect()),
        raw_rmse: root_mean_square(ms.iter().map(|m| m.raw_rmse)),
        mean_ratio: median(ms.iter().map(|m| m.mean_ratio).collect()),
    }
}

fn find<'a>(sums: &'a [Summary], r: Renderer, integ: &str, sampler: &str) -> Option<&'a Summary> {
    sums.iter().find(|s| {
        s.who.renderer == r
            && s.who.integrator.eq_ignore_ascii_case(integ)
            && s.who.sampler.eq_ignore_ascii_case(sampler)
            && !s.who.adaptive
    })
}

/// A renderer's contestant of this integrator with the lowest RMSE (its best sampler).
fn best<'a>(sums: &'a [Summary], r: Renderer, integ: &str) -> Option<&'a Summary> {
    sums.iter()
        .filter(|s| s.who.renderer == r && s.who.integrator.eq_ignore_ascii_case(integ))
        .min_by(|a, b| a.rmse.total_cmp(&b.rmse))
}

/// The table of one scene, and the ratios the issue asks for.
fn report(variant: Variant, sums: &[Summary], budget: f64) -> String {
    let mut out = String::new();
    let base = find(sums, Renderer::Luxfarm, "path", "random");
    let _ = writeln!(
        out,
        "\n{} at {budget} s:\n| renderer | samples/s | samples/CPU-s | spp | s | RMSE | median run's RMSE | raw RMSE | mean / reference | RMSE / luxfarm path+random |",
        variant.name()
    );
    let _ = writeln!(out, "|---|---|---|---|---|---|---|---|---|---|");
    for s in sums {
        let rel = base.map_or("-".into(), |b| format!("{:.3}", s.rmse / b.rmse));
        let _ = writeln!(
            out,
            "| {} | {:.0} | {:.0} | {:.1} | {:.1} | {:.5} | {:.5} | {:.5} | {:.4} | {rel} |",
            s.who.label(),
            s.rate,
            s.cpu_rate,
            s.spp,
            s.seconds,
            s.rmse,
            s.median_rmse,
            s.raw_rmse,
            s.mean_ratio
        );
    }
    let pairs = [
        (
            (Renderer::Luxfarm, "bidirectional", "metropolis"),
            (Renderer::Luxfarm, "path", "random"),
        ),
        (
            (Renderer::Luxfarm, "bidirectional", "random"),
            (Renderer::LuxCore, "BIDIRCPU", "RANDOM"),
        ),
        (
            (Renderer::Luxfarm, "bidirectional", "metropolis"),
            (Renderer::LuxCore, "BIDIRCPU", "METROPOLIS"),
        ),
        (
            (Renderer::Luxfarm, "path", "random"),
            (Renderer::LuxCore, "PATHCPU", "RANDOM"),
        ),
    ];
    let bests = [
        (
            best(sums, Renderer::Luxfarm, "bidirectional"),
            best(sums, Renderer::LuxCore, "BIDIRCPU"),
        ),
        (
            best(sums, Renderer::Luxfarm, "path"),
            best(sums, Renderer::LuxCore, "PATHCPU"),
        ),
    ];
    let named = pairs
        .iter()
        .map(|((ra, ia, sa), (rb, ib, sb))| (find(sums, *ra, ia, sa), find(sums, *rb, ib, sb)));
    let lines = bests
        .into_iter()
        .map(|p| ("best of each: ", p))
        .chain(named.map(|p| ("", p)));
    for (what, pair) in lines {
        if let (Some(x), Some(y)) = pair {
            let _ = writeln!(
                out,
                "{}: {what}{} / {}: RMSE at equal time {:.3} (median runs {:.3})",
                variant.name(),
                x.who.label(),
                y.who.label(),
                x.rmse / y.rmse,
                x.median_rmse / y.median_rmse
            );
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contestants_take_their_renderers_adaptive_option_only() {
        let c = Contestant::parse(Renderer::Luxfarm, "path:sobol:noiseaware").unwrap();
        assert!(c.adaptive);
        assert_eq!(c.label(), "luxfarm path+sobol+noiseaware");
        let c = Contestant::parse(Renderer::LuxCore, "PATHCPU:SOBOL").unwrap();
        assert!(!c.adaptive);
        assert_eq!(c.label(), "LuxCore PATHCPU+SOBOL");
        let c = Contestant::parse(Renderer::LuxCore, "PATHCPU:RANDOM:adaptive").unwrap();
        assert_eq!(c.label(), "LuxCore PATHCPU+RANDOM+adaptive");
        for (r, bad) in [
            (Renderer::Luxfarm, "path:random:adaptive"),
            (Renderer::LuxCore, "PATHCPU:RANDOM:noiseaware"),
            (Renderer::LuxCore, "BIDIRCPU:METROPOLIS:adaptive"),
            (Renderer::Luxfarm, "path"),
            (Renderer::Luxfarm, "path:random:noiseaware:x"),
        ] {
            assert!(Contestant::parse(r, bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn the_cover_is_a_closed_box_with_outward_normals() {
        let c = 0.3;
        let (p, tris) = cover_mesh(c);
        let center = [0.0, 0.0, (COVER_Z.0 + COVER_Z.1) / 2.0];
        let mut area = 0.0;
        for t in tris {
            let [a, b, d] = t.map(|i| p[i as usize]);
            let (u, v) = (sub(b, a), sub(d, a));
            let n = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            let out = sub(a, center);
            assert!(n[0] * out[0] + n[1] * out[1] + n[2] * out[2] > 0.0, "{t:?}");
            area += (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() / 2.0;
        }
        let h = COVER_Z.1 - COVER_Z.0;
        let expected = 2.0 * (2.0 * c) * (2.0 * c) + 4.0 * (2.0 * c) * h;
        assert!((area - expected).abs() < 1e-12, "{area} vs {expected}");
        assert_eq!(
            Variant::parse("caustic-covered").unwrap().name(),
            "caustic-covered"
        );
        assert_eq!(Variant::parse("caustic").unwrap().name(), "caustic");
    }

    fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }
}
