//! luxfarm's side of the Cornell benchmark: `cornell-mesh.lxs` with its Sampler line set to
//! the sampler under test and its path depth set to the benchmark's, rendered in this process
//! pass by pass until the film holds the spp asked for. Scene building is left out of the
//! timing, as the other renderers' samples/s statistics leave it out.

use super::{cpu_seconds, Run};
use crate::image_metrics::film_rgb;
use anyhow::{bail, Context};
use luxfarm::lxs::{parse_str, ParseOptions};
use luxfarm::render::{Session, SessionOptions};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The benchmark scene's text and where it lives.
pub struct Ours {
    text: String,
    path: PathBuf,
    threads: usize,
}

/// The scene's one Sampler and SurfaceIntegrator statements, as `cornell_scene.py` writes them.
const SAMPLER: &str = r#"Sampler "random" "integer pixelsamples" [1]"#;
const DEPTH: &str = r#""integer maxdepth" [8]"#;

impl Ours {
    /// Reads the scene; `maxdepth` is LuxRender's (vertices with light sampling).
    pub fn new(scene: &Path, maxdepth: u32, threads: usize) -> anyhow::Result<Ours> {
        let text = std::fs::read_to_string(scene)
            .with_context(|| format!("reading {}", scene.display()))?;
        if !text.contains(SAMPLER) || !text.contains(DEPTH) {
            bail!(
                "{}: expected the lines cornell_scene.py writes ({SAMPLER}; {DEPTH})",
                scene.display()
            );
        }
        Ok(Ours {
            text: text.replace(DEPTH, &format!(r#""integer maxdepth" [{maxdepth}]"#)),
            path: scene.to_path_buf(),
            threads,
        })
    }

    /// Renders `spp` samples per pixel (on average, with noise-aware sampling) with the
    /// sampler `spec` (see [`sampler_statement`]), on stream `seed`.
    pub fn run(&self, spec: &str, spp: u32, seed: u64) -> anyhow::Result<Run> {
        let text = self.text.replace(SAMPLER, &sampler_statement(spec)?);
        let desc = parse_str(
            &text,
            &self.path.to_string_lossy(),
            &ParseOptions::default(),
        )?;
        let base = self.path.parent().unwrap_or(Path::new("."));
        let target = f64::from(spp);
        render_until(&desc, base, self.threads, seed, |s, _| {
            let film = s.film();
            let left = (target - film.spp()) * film.pixel_count() as f64;
            if left <= 0.0 {
                0
            } else {
                (left / s.pass_samples().max(1) as f64).ceil() as u64
            }
        })
    }
}

/// The Sampler statement of a sampler spec `name` or `name:noiseaware` (LuxRender's
/// `"bool noiseaware"`: each pass spreads its samples by the film's noise map).
pub fn sampler_statement(spec: &str) -> anyhow::Result<String> {
    let (name, noise_aware) = match spec.split_once(':') {
        None => (spec, false),
        Some((name, "noiseaware")) => (name, true),
        Some((_, other)) => bail!("sampler {spec}: unknown option {other} (noiseaware)"),
    };
    let mut line = format!(r#"Sampler "{name}" "integer pixelsamples" [1]"#);
    if noise_aware {
        line.push_str(r#" "bool noiseaware" ["true"]"#);
    }
    Ok(line)
}

/// Renders `desc` in this process on stream `seed` in sweeps of passes
/// ([`Session::render_passes`]) until `left(session, elapsed seconds)`, the passes still to
/// render (checked before each sweep), is 0; scene building is left out of the timing.
/// Shared by `bench cornell` (a spp target) and `bench efficiency` (a time budget).
pub fn render_until(
    desc: &luxfarm::lxs::SceneDescription,
    base: &Path,
    threads: usize,
    seed: u64,
    mut left: impl FnMut(&Session, f64) -> u64,
) -> anyhow::Result<Run> {
    let opts = SessionOptions {
        threads,
        seed,
        stream: 0,
    };
    let mut s = Session::new(desc, base, opts)?;
    let start = Instant::now();
    let cpu0 = cpu_seconds(libc::RUSAGE_SELF);
    let mut samples = 0u64;
    loop {
        let max = left(&s, start.elapsed().as_secs_f64());
        if max == 0 {
            break;
        }
        let st = s.render_passes(max);
        if !st.complete || st.samples == 0 {
            bail!("render pass did not complete");
        }
        samples += st.samples;
    }
    let secs = start.elapsed().as_secs_f64();
    let cpu = cpu_seconds(libc::RUSAGE_SELF) - cpu0;
    Ok(Run {
        samples_per_sec: samples as f64 / secs.max(1e-9),
        samples_per_cpu_sec: samples as f64 / cpu.max(1e-9),
        seconds: secs,
        spp: s.film().spp(),
        rgb: film_rgb(s.film()).iter().map(|c| c.to_array()).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::sampler_statement;

    #[test]
    fn sampler_specs_become_statements() {
        assert_eq!(
            sampler_statement("sobol").unwrap(),
            r#"Sampler "sobol" "integer pixelsamples" [1]"#
        );
        assert_eq!(
            sampler_statement("sobol:noiseaware").unwrap(),
            r#"Sampler "sobol" "integer pixelsamples" [1] "bool noiseaware" ["true"]"#
        );
        assert!(sampler_statement("sobol:adaptive").is_err());
    }
}
