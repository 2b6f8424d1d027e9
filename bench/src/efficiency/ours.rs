//! luxfarm's side of the efficiency benchmark: the Cornell benchmark scene
//! (`cornell-mesh.lxs`), or its caustic variant, with its Film, Sampler and SurfaceIntegrator
//! lines set to the contestant's, rendered in this process pass by pass until the wall-time
//! budget is spent. Scene building is left out of the timing.

use super::{cover_mesh, Contestant, Variant};
use crate::cornell::ours::render_until;
use crate::cornell::Run;
use anyhow::{bail, Context};
use luxfarm::lxs::{parse_str, ParseOptions};
use std::path::{Path, PathBuf};

/// The lines of `cornell-mesh.lxs` (as `cornell_scene.py` writes them) this module replaces.
const FILM: &str = r#"Film "fleximage" "integer xresolution" [256] "integer yresolution" [256]"#;
const SAMPLER: &str = r#"Sampler "random" "integer pixelsamples" [1]"#;
const INTEGRATOR: &str =
    r#"SurfaceIntegrator "path" "integer maxdepth" [8] "string rrstrategy" ["none"]"#;
const LAMP_L: &str = r#""color L" [17 12 4]"#;
const LAMP_P: &str =
    r#""point P" [-0.25 -0.25 1.99 0.25 -0.25 1.99 0.25 0.25 1.99 -0.25 0.25 1.99]"#;

/// The scene text of one variant at one resolution, and where it lives.
pub struct Ours {
    text: String,
    path: PathBuf,
    threads: usize,
    /// Path depth in segments.
    depth: u32,
}

impl Ours {
    pub fn new(
        scene: &Path,
        variant: Variant,
        res: u32,
        depth: u32,
        threads: usize,
    ) -> anyhow::Result<Ours> {
        let text = std::fs::read_to_string(scene)
            .with_context(|| format!("reading {}", scene.display()))?;
        for line in [FILM, SAMPLER, INTEGRATOR, LAMP_L, LAMP_P] {
            if !text.contains(line) {
                bail!(
                    "{}: expected the line cornell_scene.py writes: {line}",
                    scene.display()
                );
            }
        }
        let mut text = text.replace(
            FILM,
            &format!(
                r#"Film "fleximage" "integer xresolution" [{res}] "integer yresolution" [{res}]"#
            ),
        );
        if let Variant::Caustic { half, scale, cover } = variant {
            let l = [17.0, 12.0, 4.0].map(|c: f64| c * scale);
            text = text.replace(
                LAMP_L,
                &format!(r#""color L" [{} {} {}]"#, l[0], l[1], l[2]),
            );
            let p = format!(
                r#""point P" [{m} {m} 1.99 {h} {m} 1.99 {h} {h} 1.99 {m} {h} 1.99]"#,
                m = -half,
                h = half
            );
            text = text.replace(LAMP_P, &p);
            if cover > 0.0 {
                text = text.replacen("WorldEnd", &cover_statement(cover), 1);
            }
        }
        Ok(Ours {
            text,
            path: scene.to_path_buf(),
            threads,
            depth,
        })
    }

    /// The scene's Sampler and SurfaceIntegrator statements for a contestant. Path depth is
    /// in segments: LuxRender's path `maxdepth` D − 1 allows D (light sampled at vertices
    /// 0..maxdepth−1); bidirectional's `eyedepth` / `lightdepth` count vertices with the
    /// camera and the light, so D + 1 of each allows D segments on either side, as LuxCore's
    /// `path.maxdepth` / `light.maxdepth` D. Russian roulette off on both.
    fn statements(&self, c: &Contestant) -> anyhow::Result<(String, String)> {
        let (integrator, sampler) = (c.integrator.as_str(), c.sampler.as_str());
        let d = self.depth;
        let integ = match integrator {
            "path" => format!(
                r#"SurfaceIntegrator "path" "integer maxdepth" [{}] "string rrstrategy" ["none"]"#,
                d - 1
            ),
            "bidirectional" => format!(
                r#"SurfaceIntegrator "bidirectional" "integer eyedepth" [{e}] "integer lightdepth" [{e}] "float eyerrthreshold" [1] "float lightrrthreshold" [1]"#,
                e = d + 1
            ),
            other => bail!("integrator {other:?}: path or bidirectional"),
        };
        let noiseaware = if c.adaptive {
            r#" "bool noiseaware" ["true"]"#
        } else {
            ""
        };
        Ok((
            format!(r#"Sampler "{sampler}" "integer pixelsamples" [1]{noiseaware}"#),
            integ,
        ))
    }

    /// Renders `c` for `budget` wall seconds (the last pass may run past it), on stream `seed`.
    pub fn run(&self, c: &Contestant, budget: f64, seed: u64) -> anyhow::Result<Run> {
        let (sampler, integ) = self.statements(c)?;
        let text = self
            .text
            .replace(SAMPLER, &sampler)
            .replace(INTEGRATOR, &integ);
        let desc = parse_str(
            &text,
            &self.path.to_string_lossy(),
            &ParseOptions::default(),
        )?;
        let base = self.path.parent().unwrap_or(Path::new("."));
        render_until(&desc, base, self.threads, seed, |s, t| {
            if t >= budget {
                0
            } else {
                s.passes_within(budget - t)
            }
        })
    }
}

/// The glass slab of half-side `c` ([`cover_mesh`]) as scene statements, then `WorldEnd`.
fn cover_statement(c: f64) -> String {
    let (p, tris) = cover_mesh(c);
    let points: Vec<String> = p.iter().flatten().map(f64::to_string).collect();
    let indices: Vec<String> = tris.iter().flatten().map(u32::to_string).collect();
    format!(
        "AttributeBegin # glass slab under the lamp\n  NamedMaterial \"glass\"\n  \
         Shape \"trianglemesh\" \"integer indices\" [{}] \"point P\" [{}]\nAttributeEnd\nWorldEnd",
        indices.join(" "),
        points.join(" ")
    )
}
