//! `luxfarm parse SCENE [--json]`: imports a scene of any format (.lxs, .igs, .lws, .mi)
//! with its includes and prints a summary (camera, film, counts, warnings with their
//! locations) or the whole SceneDescription as JSON. Exit status 0 when it parses, 2 with the error on stderr when it does not.

use luxfarm::formats;
use luxfarm::lxs::{Entity, ParseOptions, SceneDescription};
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// The scene file (.lxs, .igs, .lws or .mi: the format is detected).
    pub scene: PathBuf,
    /// Print the whole SceneDescription as JSON instead of a summary.
    #[arg(long)]
    pub json: bool,
    /// Refuse Includes outside the scene's directory (as the server does).
    #[arg(long)]
    pub confine: bool,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let opts = ParseOptions {
        confine_to_root: args.confine,
        ..ParseOptions::default()
    };
    let desc = match formats::inspect(&args.scene, &opts) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("error: {e}");
            return Ok(ExitCode::from(2));
        }
    };
    let mut out = std::io::stdout().lock();
    if args.json {
        serde_json::to_writer(&mut out, &to_json(desc)?)?;
        writeln!(out)?;
    } else {
        out.write_all(summary(&desc).as_bytes())?;
    }
    Ok(ExitCode::SUCCESS)
}

/// The description as JSON (`named_textures` becomes a list of `{type, name, index}`).
pub fn to_json(desc: SceneDescription) -> anyhow::Result<serde_json::Value> {
    Ok(serde_json::to_value(&desc)?)
}

fn kind(e: Option<&Entity>) -> String {
    e.map(|e| e.kind.clone())
        .unwrap_or_else(|| "(default)".into())
}

/// The named volumes (media) as ` (name: kind, ...)`, empty when there are none.
fn volume_names(d: &SceneDescription) -> String {
    if d.volumes.is_empty() {
        return String::new();
    }
    let names: Vec<String> = d
        .volumes
        .iter()
        .map(|v| {
            format!(
                "{}: {}",
                v.name.as_deref().unwrap_or("(unnamed)"),
                v.entity.kind
            )
        })
        .collect();
    format!(" ({})", names.join(", "))
}

/// The human-readable summary.
pub fn summary(d: &SceneDescription) -> String {
    let mut s = String::new();
    s += &format!("scene: {} ({} file(s))\n", d.root_file, d.files.len());
    match &d.camera {
        Some(c) => {
            let fov = c.entity.params.float("fov");
            c.entity.params.reset_used();
            let fov = fov.map(|f| format!(" fov {f}")).unwrap_or_default();
            s += &format!("camera: {}{fov}\n", c.entity.kind);
        }
        None => s += "camera: (none: LuxRender's default perspective)\n",
    }
    match &d.film {
        Some(f) => {
            let p = &f.params;
            let x = p.int_or("xresolution", 800);
            let y = p.int_or("yresolution", 600);
            let spp = p
                .int("haltspp")
                .map(|v| format!(" haltspp {v}"))
                .unwrap_or_default();
            p.reset_used();
            s += &format!("film: {} {x}x{y}{spp}\n", f.kind);
        }
        None => s += "film: (none)\n",
    }
    s += &format!(
        "sampler: {}, filter: {}, surface integrator: {}\n",
        kind(d.sampler.as_ref()),
        kind(d.pixel_filter.as_ref()),
        kind(d.surface_integrator.as_ref())
    );
    let area = d.shapes.iter().filter(|x| x.area_light.is_some()).count();
    let named = d.materials.iter().filter(|m| m.name.is_some()).count();
    s += &format!(
        "shapes: {} ({} area-lit)\nlights: {}\nmaterials: {} ({} named)\ntextures: {}\nobjects: {}\ninstances: {}\nvolumes: {}{}\nlight groups: {}\n",
        d.shapes.len(),
        area,
        d.lights.len(),
        d.materials.len(),
        named,
        d.textures.len(),
        d.objects.len(),
        d.instances.len(),
        d.volumes.len(),
        volume_names(d),
        d.light_groups.join(", ")
    );
    s += &format!("warnings: {}\n", d.warnings.len());
    for w in &d.warnings {
        s += &format!("  warning: {w}\n");
    }
    s
}
