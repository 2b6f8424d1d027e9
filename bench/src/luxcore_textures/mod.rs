//! `luxfarm bench luxcore-textures`: every texture class luxfarm shares with LuxCore, rendered
//! on a flat surface by both and compared per pixel (issue 15). LuxCore's textures descend from
//! LuxRender's, so where both follow LuxRender the images agree; where they do not, the case's
//! note says which side LuxRender's sources support.
//!
//! For each case of [`all_cases`] ([`cases`] and [`blender_cases`]; [`scene`] writes both
//! scenes):
//!
//! ```text
//! case --scene::Case::lxs--> LuxRender text --parse + Session (this process)--> film --film_rgb--> A
//!      --scene::Case::luxcore_json--> scripts/luxcore_textures.py (pyluxcore) --> EXR ----------> B
//! A, B --agreement (A one row up: LuxCore's camera rows)--> MAD / mean(B) --> the table row
//! ```
//!
//! The images the textures read (an RGB image, a height field, a normal map) are generated into
//! the output directory first ([`images`]). Every case's scene text, JSON and both images stay
//! in `--out DIR` (a temporary directory otherwise). The verdict is the acceptance point's:
//! mean absolute difference over pixels and channels at most 2 % of LuxCore's mean. The
//! process exits with failure when any case is over it.

mod blender_cases;
mod cases;
mod images;
mod scene;

use crate::image_metrics::{film_rgb, row_pairs};
use anyhow::{bail, Context};
use luxfarm::lxs::{parse_str, ParseOptions};
use luxfarm::render::{Session, SessionOptions};
use luxfarm::texture::image_io::load_rgb as load_image;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

#[derive(clap::Args)]
pub struct Args {
    /// Image width and height in pixels.
    #[arg(long, default_value_t = 96)]
    pub res: u32,
    /// Samples per pixel of both renders.
    #[arg(long, default_value_t = 64)]
    pub spp: u32,
    /// Render threads of both (0: all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Where the scenes and images go (default: a temporary directory, removed afterwards).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Only the cases whose names contain one of these, comma-separated.
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<String>,
    /// Rows luxfarm's image sits above LuxCore's (LuxCore's camera maps film rows one lower).
    #[arg(long, default_value_t = 1)]
    pub shift_rows: i64,
    /// The agreement required: mean absolute difference over LuxCore's mean.
    #[arg(long, default_value_t = 0.02)]
    pub tolerance: f64,
    /// Python interpreter with pyluxcore.
    #[arg(long, default_value = "python3")]
    pub python: String,
    /// The LuxCore script (default: scripts/luxcore_textures.py of this repository).
    #[arg(long)]
    pub script: Option<PathBuf>,
}

/// Per-pixel agreement of image A with the reference B.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Agreement {
    /// Mean of A over the compared pixels and channels.
    pub mean_a: f64,
    /// Mean of B over the compared pixels and channels.
    pub mean_b: f64,
    /// Mean absolute difference over the compared pixels and channels.
    pub mad: f64,
    /// Standard deviation of B over the compared pixels and channels: how much pattern there
    /// is to agree on.
    pub std_b: f64,
}

impl Agreement {
    /// MAD over B's mean (infinite when B is black and A is not, 0 when both are).
    pub fn relative(&self) -> f64 {
        if self.mean_b.abs() > 0.0 {
            self.mad / self.mean_b.abs()
        } else if self.mad == 0.0 {
            0.0
        } else {
            f64::INFINITY
        }
    }
}

/// Compares `a` with `b` (both `w`×`h`, row by row) with A shifted down by `rows` rows, as
/// [`row_pairs`] pairs them; pixels without a partner are left out.
pub fn agreement(a: &[[f32; 3]], b: &[[f32; 3]], w: usize, h: usize, rows: i64) -> Agreement {
    let (mut sa, mut sb, mut sd, mut sbb, mut n) = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0usize);
    for (ia, ib) in row_pairs(w, h, rows) {
        let (Some(pa), Some(pb)) = (a.get(ia), b.get(ib)) else {
            continue;
        };
        for c in 0..3 {
            let (x, y) = (f64::from(pa[c]), f64::from(pb[c]));
            sa += x;
            sb += y;
            sbb += y * y;
            sd += (x - y).abs();
            n += 1;
        }
    }
    let n = n.max(1) as f64;
    let mean_b = sb / n;
    Agreement {
        mean_a: sa / n,
        mean_b,
        mad: sd / n,
        std_b: (sbb / n - mean_b * mean_b).max(0.0).sqrt(),
    }
}

/// Renders a case with luxfarm in this process: linear RGB, and the build's warnings.
fn render_ours(
    text: &str,
    scene_path: &Path,
    spp: u32,
    threads: usize,
) -> anyhow::Result<(Vec<[f32; 3]>, Vec<String>)> {
    let desc = parse_str(
        text,
        &scene_path.to_string_lossy(),
        &ParseOptions::default(),
    )?;
    let base = scene_path.parent().unwrap_or(Path::new("."));
    let opts = SessionOptions {
        threads,
        seed: 1,
        stream: 0,
    };
    let mut s = Session::new(&desc, base, opts)?;
    let warnings = s.warnings().iter().map(|d| d.to_string()).collect();
    while s.film().spp() < f64::from(spp) {
        let st = s.render_pass();
        if !st.complete || st.samples == 0 {
            bail!("render pass did not complete");
        }
    }
    let rgb = film_rgb(s.film()).iter().map(|c| c.to_array()).collect();
    Ok((rgb, warnings))
}

/// Renders a case with LuxCore through the script (run in the case directory, where the
/// image files are) and reads the EXR it writes.
fn render_luxcore(
    a: &Args,
    script: &Path,
    json: &Path,
    exr: &Path,
) -> anyhow::Result<Vec<[f32; 3]>> {
    // Image files are named relative to the case directory, as in the .lxs.
    let dir = json.parent().unwrap_or(Path::new("."));
    let o = Command::new(&a.python)
        .current_dir(dir)
        .arg(script)
        .arg("--json")
        .arg(json)
        .args(["--threads", &a.threads.to_string()])
        .arg("--out")
        .arg(exr)
        .output()
        .with_context(|| format!("running {} {}", a.python, script.display()))?;
    let stdout = String::from_utf8_lossy(&o.stdout);
    if !o.status.success() || !stdout.contains("luxcore_textures spp=") {
        let stderr = String::from_utf8_lossy(&o.stderr);
        bail!(
            "{} failed ({}): {}",
            script.display(),
            o.status,
            stderr
                .lines()
                .rev()
                .find(|l| !l.trim().is_empty())
                .unwrap_or("")
        );
    }
    let (w, h, px) = load_image(exr).map_err(anyhow::Error::msg)?;
    if (w, h) != (a.res as usize, a.res as usize) {
        bail!("{}: {w}x{h}, expected {}x{}", exr.display(), a.res, a.res);
    }
    Ok(px.iter().map(|c| c.to_array()).collect())
}

/// One line of the table.
struct Row {
    name: &'static str,
    result: Result<Agreement, String>,
    note: String,
}

fn print_table(rows: &[Row], tolerance: f64) {
    println!(
        "| case | luxfarm mean | LuxCore mean | LuxCore std/mean | MAD/mean | ≤ {:.0} % | note |",
        tolerance * 100.0
    );
    println!("| --- | ---: | ---: | ---: | ---: | :---: | --- |");
    for r in rows {
        match &r.result {
            Ok(g) => println!(
                "| {} | {:.4} | {:.4} | {:.1} % | {:.2} % | {} | {} |",
                r.name,
                g.mean_a,
                g.mean_b,
                100.0 * g.std_b / g.mean_b.abs().max(1e-12),
                g.relative() * 100.0,
                if g.relative() <= tolerance {
                    "pass"
                } else {
                    "FAIL"
                },
                r.note
            ),
            Err(e) => println!(
                "| {} | – | – | – | – | error | {} |",
                r.name,
                e.replace('|', "/")
            ),
        }
    }
}

/// Every case, in the table's order: the references and 3D procedurals, the blender_*
/// textures, the brick bonds, the uv-mapped, vertex-colour and image textures, and the
/// textures seen through a material.
fn all_cases() -> Vec<scene::Case> {
    let mut v = cases::procedurals();
    v.extend(blender_cases::blenders());
    v.extend(cases::bricks());
    v.extend(cases::surfaces());
    v.extend(cases::materials());
    v
}

/// A case name as a file name: letters and digits kept, runs of anything else one `_`.
fn file_stem(name: &str) -> String {
    let mut s = String::new();
    for c in name.chars() {
        if c.is_ascii_alphanumeric() {
            s.push(c);
        } else if !s.ends_with('_') {
            s.push('_');
        }
    }
    s.trim_matches('_').to_string()
}

fn default_script() -> PathBuf {
    PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scripts/luxcore_textures.py"
    ))
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    luxfarm::film::check_size(a.res, a.res)?;
    let script = a.script.clone().unwrap_or_else(default_script);
    let script = std::fs::canonicalize(&script)
        .with_context(|| format!("{}: no such script (give --script)", script.display()))?;
    let ok = Command::new(&a.python)
        .args(["-c", "import pyluxcore"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        bail!(
            "{} cannot import pyluxcore (pip install pyluxcore numpy)",
            a.python
        );
    }
    let tmp = tempfile::tempdir()?;
    let dir = a.out.clone().unwrap_or_else(|| tmp.path().to_path_buf());
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    let dir = std::fs::canonicalize(&dir)?;
    images::write_all(&dir)?;
    println!(
        "luxcore-textures: {}x{} px, {} spp, luxfarm one row above LuxCore ({} row shift); \
         load {}; images in {}",
        a.res,
        a.res,
        a.spp,
        a.shift_rows,
        crate::support::loadavg(),
        dir.display()
    );
    let mut rows = Vec::new();
    let res = a.res as usize;
    for case in all_cases() {
        if !a.only.is_empty() && !a.only.iter().any(|o| case.name.contains(o.as_str())) {
            continue;
        }
        let stem = file_stem(case.name);
        let lxs_path = dir.join(format!("{stem}.lxs"));
        let json_path = dir.join(format!("{stem}.json"));
        let text = case.lxs(a.res);
        std::fs::write(&lxs_path, &text)?;
        std::fs::write(
            &json_path,
            serde_json::to_string_pretty(&case.luxcore_json(a.res, a.spp))?,
        )?;
        let result = (|| {
            let (ours, warnings) = render_ours(&text, &lxs_path, a.spp, a.threads)?;
            crate::image_metrics::write_rgb_exr(
                &dir.join(format!("{stem}-luxfarm.exr")),
                a.res,
                a.res,
                &ours,
            )?;
            let exr = dir.join(format!("{stem}-luxcore.exr"));
            let theirs = render_luxcore(&a, &script, &json_path, &exr)?;
            anyhow::Ok((agreement(&ours, &theirs, res, res, a.shift_rows), warnings))
        })();
        let (result, note) = match result {
            Ok((g, w)) if w.is_empty() => (Ok(g), case.note.to_string()),
            Ok((g, w)) => (
                Ok(g),
                format!("{} luxfarm warned: {}", case.note, w.join("; ")),
            ),
            Err(e) => (Err(format!("{e:#}")), case.note.to_string()),
        };
        eprintln!("{}: {:?}", case.name, result);
        rows.push(Row {
            name: case.name,
            result,
            note,
        });
    }
    print_table(&rows, a.tolerance);
    println!("load after: {}", crate::support::loadavg());
    let all_pass = rows
        .iter()
        .all(|r| r.result.as_ref().is_ok_and(|g| g.relative() <= a.tolerance));
    Ok(if all_pass {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_images_agree_exactly() {
        let a = vec![[0.2, 0.4, 0.6]; 6];
        let g = agreement(&a, &a, 2, 3, 0);
        assert_eq!(g.mad, 0.0);
        assert!((g.mean_a - 0.4).abs() < 1e-7 && (g.mean_b - 0.4).abs() < 1e-7);
        assert_eq!(g.relative(), 0.0);
    }

    #[test]
    fn hand_computed_difference() {
        // 1x2 images: A = [1, 1, 1], [0, 0, 0]; B = [0.5, 1, 1.5], [0, 0, 0.3].
        let a = [[1.0, 1.0, 1.0], [0.0, 0.0, 0.0]];
        let b = [[0.5, 1.0, 1.5], [0.0, 0.0, 0.3]];
        let g = agreement(&a, &b, 1, 2, 0);
        // |d| sum = 0.5 + 0 + 0.5 + 0 + 0 + 0.3 = 1.3 over 6 values; B's mean 3.3 / 6.
        assert!((g.mad - 1.3 / 6.0).abs() < 1e-6, "{g:?}");
        assert!((g.mean_b - 3.3 / 6.0).abs() < 1e-6, "{g:?}");
        assert!((g.mean_a - 0.5).abs() < 1e-12, "{g:?}");
        assert!((g.relative() - 1.3 / 3.3).abs() < 1e-6, "{g:?}");
        // B's values 0.5, 1, 1.5, 0, 0, 0.3: E[B²] = 3.59 / 6.
        let var = 3.59 / 6.0 - (3.3f64 / 6.0).powi(2);
        assert!((g.std_b - var.sqrt()).abs() < 1e-6, "{g:?}");
    }

    #[test]
    fn the_row_shift_pairs_luxfarm_one_row_above_luxcore() {
        // A shows a bright row 0; B shows it one row lower, as LuxCore's camera does.
        let a = [[1.0; 3], [0.0; 3], [0.0; 3]];
        let b = [[0.0; 3], [1.0; 3], [0.0; 3]];
        assert_eq!(agreement(&a, &b, 1, 3, 1).mad, 0.0);
        let unshifted = agreement(&a, &b, 1, 3, 0);
        assert!((unshifted.mad - 2.0 / 3.0).abs() < 1e-12, "{unshifted:?}");
        // Only the two paired rows count, so B's mean is over rows 1 and 2.
        assert!((agreement(&a, &b, 1, 3, 1).mean_b - 0.5).abs() < 1e-12);
    }

    #[test]
    fn black_references() {
        let z = [[0.0; 3]; 2];
        assert_eq!(agreement(&z, &z, 1, 2, 0).relative(), 0.0);
        let one = [[1.0; 3]; 2];
        assert_eq!(agreement(&one, &z, 1, 2, 0).relative(), f64::INFINITY);
    }

    #[test]
    fn file_stems_are_plain() {
        assert_eq!(
            file_stem("bump imagemap, uscale 32 on uvs spanning 1/32"),
            "bump_imagemap_uscale_32_on_uvs_spanning_1_32"
        );
        assert_eq!(file_stem("reference: constant"), "reference_constant");
    }

    #[test]
    fn every_case_has_a_unique_name_and_a_tex() {
        let all = all_cases();
        let mut names: Vec<_> = all.iter().map(|c| file_stem(c.name)).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), all.len());
        for c in &all {
            assert!(c.lxs.contains("Texture \"tex\""), "{}", c.name);
            assert_eq!(
                c.luxcore.last().map(|t| t.0.as_str()),
                Some("tex"),
                "{}",
                c.name
            );
        }
    }
}
