//! The other renderers of the Cornell benchmark, each driven by its runner script in
//! `../shared/bench/` (`luxcore_cornell.py`, `mitsuba_cornell.py`, `cycles_cornell.py`, all
//! built from `cornell_scene.py`). A script renders the scene at a given spp and depth, writes
//! a linear EXR and prints one line of `key=value` statistics; this module runs it, reads
//! that line and the image.
//!
//! Each script's `--maxdepth` counts path segments (LuxCore's `pathdepth.total`); the scripts
//! map it to their renderer's own setting (Mitsuba `max_depth` = D, Cycles `max_bounces` =
//! D − 2). Speed is the script's own statistic (its render loop only); CPU speed is the
//! script's `samples_per_cpu_s` where it prints one, else the child's CPU time less a
//! one-spp run's (start-up, scene build and one pass, in the renderer's favour).

use super::{cpu_seconds, Run};
use anyhow::{bail, Context};
use luxfarm::texture::image_io::load_rgb as load_image;
use std::path::{Path, PathBuf};
use std::process::Command;

/// One of the other renderers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Renderer {
    LuxCore,
    Mitsuba,
    Cycles,
}

impl Renderer {
    pub const ALL: [Renderer; 3] = [Renderer::LuxCore, Renderer::Mitsuba, Renderer::Cycles];

    pub fn name(self) -> &'static str {
        match self {
            Renderer::LuxCore => "LuxCore PATHCPU",
            Renderer::Mitsuba => "Mitsuba 3 scalar_rgb",
            Renderer::Cycles => "Cycles CPU",
        }
    }

    /// The name `--without` takes.
    pub fn key(self) -> &'static str {
        match self {
            Renderer::LuxCore => "luxcore",
            Renderer::Mitsuba => "mitsuba",
            Renderer::Cycles => "cycles",
        }
    }

    fn script(self) -> &'static str {
        match self {
            Renderer::LuxCore => "luxcore_cornell.py",
            Renderer::Mitsuba => "mitsuba_cornell.py",
            Renderer::Cycles => "cycles_cornell.py",
        }
    }

    /// The Python module the script needs (and its pip package).
    fn module(self) -> &'static str {
        match self {
            Renderer::LuxCore => "pyluxcore",
            Renderer::Mitsuba => "mitsuba",
            Renderer::Cycles => "bpy",
        }
    }

    /// Image rows shifted against the reference (LuxCore's own render): LuxCore's cameras map
    /// film rows one row lower than LuxRender's; Mitsuba and Cycles agree with LuxRender
    /// (measured: RMSE 0.037 and 0.024 at a one-row shift against 0.36 unshifted, 64 spp).
    pub fn row_shift(self) -> i64 {
        match self {
            Renderer::LuxCore => 0,
            Renderer::Mitsuba | Renderer::Cycles => 1,
        }
    }
}

/// How to run the scripts.
pub struct Runner {
    pub python: String,
    pub bench_dir: PathBuf,
    pub threads: usize,
    pub maxdepth: u32,
    pub res: u32,
}

/// What one script run printed and wrote.
struct Output {
    rate: f64,
    cpu_rate: Option<f64>,
    spp: f64,
    child_cpu: f64,
    rgb: Vec<[f32; 3]>,
}

impl Runner {
    /// Whether the renderer's Python module imports (the renderer is left out when not).
    pub fn available(&self, r: Renderer) -> bool {
        Command::new(&self.python)
            .args(["-c", &format!("import {}", r.module())])
            .output()
            .is_ok_and(|o| o.status.success())
    }

    fn once(&self, r: Renderer, spp: u32, out: &Path) -> anyhow::Result<Output> {
        let script = self.bench_dir.join(r.script());
        let cpu0 = cpu_seconds(libc::RUSAGE_CHILDREN);
        let o = Command::new(&self.python)
            .arg(&script)
            .args(["--spp", &spp.to_string(), "--res", &self.res.to_string()])
            .args(["--threads", &self.threads.to_string()])
            .args(["--maxdepth", &self.maxdepth.to_string()])
            .arg("--out")
            .arg(out)
            .output()
            .with_context(|| format!("running {} {}", self.python, script.display()))?;
        let child_cpu = cpu_seconds(libc::RUSAGE_CHILDREN) - cpu0;
        let text = String::from_utf8_lossy(&o.stdout);
        let field = |name: &str| crate::support::stat(&text, name);
        // pyluxcore may abort while unloading after a good render: the printed line and the
        // image decide, not the exit status.
        let (Some(rate), Some(spp)) = (field("samples_per_s"), field("spp")) else {
            bail!(
                "{} run failed ({}): {}{}",
                r.name(),
                o.status,
                text,
                String::from_utf8_lossy(&o.stderr)
            );
        };
        let (_, _, px) = load_image(out).map_err(anyhow::Error::msg)?;
        Ok(Output {
            rate,
            cpu_rate: field("samples_per_cpu_s"),
            spp,
            child_cpu,
            rgb: px.iter().map(|c| c.to_array()).collect(),
        })
    }

    /// CPU seconds of a run that are not rendering: a one-spp run's whole CPU time.
    pub fn overhead(&self, r: Renderer, dir: &Path) -> anyhow::Result<f64> {
        Ok(self
            .once(r, 1, &dir.join(format!("{}-1spp.exr", r.key())))?
            .child_cpu)
    }

    /// One timed run at `spp`; `overhead` is subtracted from the child's CPU time when the
    /// script prints no CPU statistic of its own.
    pub fn run(&self, r: Renderer, spp: u32, out: &Path, overhead: f64) -> anyhow::Result<Run> {
        let o = self.once(r, spp, out)?;
        let pixels = f64::from(self.res) * f64::from(self.res);
        let cpu_rate = o
            .cpu_rate
            .unwrap_or_else(|| o.spp * pixels / (o.child_cpu - overhead).max(1e-9));
        Ok(Run {
            samples_per_sec: o.rate,
            samples_per_cpu_sec: cpu_rate,
            // The render's own time by its own statistic (samples over samples/s): LuxCore's
            // printed `elapsed` also holds its start-up and up to 0.2 s of polling, which
            // its samples/s leaves out; Mitsuba's and Cycles' agree with theirs.
            seconds: o.spp * pixels / o.rate.max(1e-9),
            spp: o.spp,
            rgb: o.rgb,
        })
    }

    /// Whether the script prints its own CPU statistic (no overhead run needed).
    pub fn prints_cpu(r: Renderer) -> bool {
        r != Renderer::LuxCore
    }
}
