//! LuxCore's side of the efficiency benchmark, and the references: `scripts/luxcore_efficiency.py`
//! builds the same scene (from `../shared/bench/cornell_scene.py`) in LuxCore's scene language,
//! renders it with one engine and sampler for a wall time, writes a linear EXR and prints one
//! line of `key=value` statistics, which this module reads.

use super::{Contestant, Variant};
use crate::cornell::{cpu_seconds, Run};
use anyhow::{bail, Context};
use luxfarm::texture::image_io::load_rgb as load_image;
use std::path::{Path, PathBuf};
use std::process::Command;

/// How to run the script.
pub struct LuxCore {
    pub python: String,
    pub script: PathBuf,
    pub shared: PathBuf,
    pub threads: usize,
    /// Path depth in segments (`path.maxdepth`, `light.maxdepth`, `pathdepth.total`).
    pub depth: u32,
    pub res: u32,
}

impl LuxCore {
    /// Whether pyluxcore imports.
    pub fn available(&self) -> bool {
        Command::new(&self.python)
            .args(["-c", "import pyluxcore"])
            .output()
            .is_ok_and(|o| o.status.success())
    }

    /// Renders with contestant `c`'s engine and sampler (LuxCore's names) for `seconds` on
    /// seed `seed`, writing `out`.
    pub fn render(
        &self,
        variant: Variant,
        c: &Contestant,
        seconds: f64,
        seed: u64,
        out: &Path,
    ) -> anyhow::Result<Run> {
        let (engine, sampler) = (c.integrator.as_str(), c.sampler.as_str());
        let mut cmd = Command::new(&self.python);
        cmd.arg(&self.script)
            .arg("--shared")
            .arg(&self.shared)
            .args(["--engine", engine, "--sampler", sampler])
            .args(["--halttime", &seconds.to_string()])
            .args(["--res", &self.res.to_string()])
            .args(["--maxdepth", &self.depth.to_string()])
            .args(["--threads", &self.threads.to_string()])
            .args(["--seed", &seed.to_string()])
            .arg("--out")
            .arg(out);
        if c.adaptive {
            cmd.arg("--adaptive");
        }
        if let Variant::Caustic { half, scale, cover } = variant {
            cmd.args(["--lamp-half", &half.to_string()])
                .args(["--lamp-scale", &scale.to_string()]);
            if cover > 0.0 {
                cmd.args(["--lamp-cover", &cover.to_string()]);
            }
        }
        let cpu0 = cpu_seconds(libc::RUSAGE_CHILDREN);
        let o = cmd
            .output()
            .with_context(|| format!("running {} {}", self.python, self.script.display()))?;
        let cpu = cpu_seconds(libc::RUSAGE_CHILDREN) - cpu0;
        let text = String::from_utf8_lossy(&o.stdout);
        let field = |name: &str| crate::support::stat(&text, name);
        // pyluxcore may abort while unloading after a good render: the printed line and the
        // image decide, not the exit status.
        let (Some(rate), Some(spp), Some(elapsed)) =
            (field("samples_per_s"), field("spp"), field("elapsed"))
        else {
            bail!(
                "LuxCore {engine} run failed ({}): {}{}",
                o.status,
                text,
                String::from_utf8_lossy(&o.stderr)
            );
        };
        let (_, _, px) = load_image(out).map_err(anyhow::Error::msg)?;
        let samples = spp * f64::from(self.res) * f64::from(self.res);
        Ok(Run {
            samples_per_sec: rate,
            // The child's whole CPU time, start-up and scene build included: LuxCore's
            // figure per CPU second here is a little low.
            samples_per_cpu_sec: samples / cpu.max(1e-9),
            seconds: elapsed,
            spp,
            rgb: px.iter().map(|c| c.to_array()).collect(),
        })
    }

    /// A contestant's render.
    pub fn run(
        &self,
        variant: Variant,
        c: &Contestant,
        budget: f64,
        seed: u64,
        tmp: &Path,
    ) -> anyhow::Result<Run> {
        let out = tmp.join(format!(
            "{}-{}-{}-{seed}.exr",
            c.integrator, c.sampler, c.adaptive
        ));
        self.render(variant, c, budget, seed, &out)
    }
}
