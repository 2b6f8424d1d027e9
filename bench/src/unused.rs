//! `luxfarm bench unused [--count N] [--runs R]`: issue 21's "model only what a scene
//! requires", measured. Writes two scenes into a temporary directory — a small textured room,
//! and the same room plus N unused named textures (a third of them image maps, each reading
//! its own PNG), N unused materials (several types, most of them textured by the unused
//! textures) and N objects never instanced (half PLY meshes naming files that do not exist,
//! half small inline triangle meshes) — then parses and builds each (`Renderable::build`,
//! alternating, each in a fresh process, best of R) and prints, per scene, parse time, the
//! first build's time (which includes the allocator's deferred work on the parse's garbage),
//! a second build's time (the build's own work), the peak memory the first build adds over
//! the parsed description (VmHWM, Linux), and what the build made
//! ([`luxfarm::scene::BuiltSummary`]).
//!
//! ```text
//! generate --> base.lxs, padded.lxs (+ images/, the PNGs only unused textures name)
//! parse_file --> SceneDescription --Renderable::build--> World.built (what was built)
//! ```
//!
//! The unused statements are part of the file: parsing reads their text, so the parse time
//! and the description's memory grow with it; the build must not.

use anyhow::Context;
use luxfarm::lxs::{self, ParseOptions};
use luxfarm::render::setup::Renderable;
use luxfarm::scene::BuiltSummary;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// Unused textures, materials and objects each.
    #[arg(long, default_value_t = 1000)]
    pub count: usize,
    /// Builds per scene (alternating); the best time is reported.
    #[arg(long, default_value_t = 5)]
    pub runs: u32,
    /// Internal: parse and build this scene once and print one result line (each
    /// measurement runs in a fresh process, so that memory peaks are comparable).
    #[arg(long, hide = true)]
    pub child: Option<PathBuf>,
    /// Write the scenes into this directory (kept) instead of a temporary one.
    #[arg(long)]
    pub dir: Option<PathBuf>,
}

/// Side of the PNGs the image maps read (an unused one costs nothing; a loaded one about
/// 1 MiB as RGBA f32 plus its MIP levels).
const IMAGE_SIDE: u32 = 256;

/// The used part: a room (floor, back wall) with an image-mapped floor, a glossy sphere and
/// one area light.
fn base_text(images: &str) -> String {
    format!(
        "LookAt 0 -4 1.5 0 0 0.8 0 0 1\nCamera \"perspective\" \"float fov\" [45]\n\
         Film \"fleximage\" \"integer xresolution\" [32] \"integer yresolution\" [32]\n\
         Sampler \"random\" \"integer pixelsamples\" [1]\n\
         WorldBegin\n\
         Texture \"floortex\" \"color\" \"imagemap\" \"string filename\" [\"{images}/used.png\"]\n\
         MakeNamedMaterial \"floor\" \"string type\" [\"matte\"] \"texture Kd\" [\"floortex\"]\n\
         MakeNamedMaterial \"ball\" \"string type\" [\"glossy\"] \"color Kd\" [0.2 0.3 0.6]\n\
         AttributeBegin\nNamedMaterial \"floor\"\n\
         Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n\
         \"point P\" [-2 -2 0 2 -2 0 2 2 0 -2 2 0]\n\
         \"float uv\" [0 0 1 0 1 1 0 1]\nAttributeEnd\n\
         AttributeBegin\nNamedMaterial \"ball\"\nTranslate 0 0 0.6\n\
         Shape \"sphere\" \"float radius\" [0.6]\nAttributeEnd\n\
         AttributeBegin\nAreaLightSource \"area\" \"color L\" [8 8 8]\n\
         Shape \"trianglemesh\" \"integer indices\" [0 2 1 0 3 2]\n\
         \"point P\" [-0.5 -0.5 2.5 0.5 -0.5 2.5 0.5 0.5 2.5 -0.5 0.5 2.5]\nAttributeEnd\n"
    )
}

/// The unused part: `n` textures, `n` materials and `n` objects nothing references.
fn unused_text(n: usize, images: &str) -> String {
    let mut s = String::new();
    for i in 0..n {
        let _ = match i % 3 {
            0 => writeln!(
                s,
                "Texture \"u_tex{i}\" \"color\" \"imagemap\" \"string filename\" [\"{images}/u{}.png\"]",
                i / 3
            ),
            1 => writeln!(
                s,
                "Texture \"u_tex{i}\" \"color\" \"checkerboard\" \"color tex1\" [1 0 0] \"color tex2\" [0 0 1]"
            ),
            _ => writeln!(
                s,
                "Texture \"u_tex{i}\" \"float\" \"fbm\" \"integer octaves\" [8]"
            ),
        };
    }
    for i in 0..n {
        let t = i - i % 3;
        let _ = match i % 4 {
            0 => writeln!(
                s,
                "MakeNamedMaterial \"u_mat{i}\" \"string type\" [\"matte\"] \"texture Kd\" [\"u_tex{t}\"]"
            ),
            1 => writeln!(
                s,
                "MakeNamedMaterial \"u_mat{i}\" \"string type\" [\"glossy\"] \"texture Kd\" [\"u_tex{}\"]",
                t + 1
            ),
            2 => writeln!(
                s,
                "MakeNamedMaterial \"u_mat{i}\" \"string type\" [\"glass\"] \"float index\" [1.5]"
            ),
            _ => writeln!(
                s,
                "MakeNamedMaterial \"u_mat{i}\" \"string type\" [\"mix\"] \"string namedmaterial1\" [\"u_mat{}\"] \"string namedmaterial2\" [\"u_mat{}\"] \"float amount\" [0.5]",
                i - 3,
                i - 2
            ),
        };
    }
    for i in 0..n {
        let _ = writeln!(s, "ObjectBegin \"u_obj{i}\"");
        let _ = if i % 2 == 0 {
            writeln!(
                s,
                "Shape \"plymesh\" \"string filename\" [\"missing/u_mesh{i}.ply\"]"
            )
        } else {
            writeln!(
                s,
                "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" [0 0 0 1 0 0 1 1 0 0 1 0]"
            )
        };
        let _ = writeln!(s, "ObjectEnd");
    }
    s
}

/// The two scenes written into `dir`: (base, padded).
pub struct Scenes {
    pub base: PathBuf,
    pub padded: PathBuf,
}

/// Writes both scenes and the images they name into `dir`.
pub fn generate(dir: &Path, count: usize) -> anyhow::Result<Scenes> {
    let images = dir.join("images");
    std::fs::create_dir_all(&images).with_context(|| format!("creating {}", images.display()))?;
    write_png(&images.join("used.png"), 0)?;
    for i in 0..count.div_ceil(3) {
        write_png(&images.join(format!("u{i}.png")), i as u32 + 1)?;
    }
    let base = base_text("images");
    let padded = format!("{base}{}", unused_text(count, "images"));
    let paths = Scenes {
        base: dir.join("base.lxs"),
        padded: dir.join("padded.lxs"),
    };
    std::fs::write(&paths.base, format!("{base}WorldEnd\n"))?;
    std::fs::write(&paths.padded, format!("{padded}WorldEnd\n"))?;
    Ok(paths)
}

/// A `IMAGE_SIDE`² gradient PNG whose colours depend on `seed`.
fn write_png(path: &Path, seed: u32) -> anyhow::Result<()> {
    let img = image::RgbImage::from_fn(IMAGE_SIDE, IMAGE_SIDE, |x, y| {
        image::Rgb([(x + seed) as u8, (y * 3 + seed) as u8, (seed * 7) as u8])
    });
    img.save(path)
        .with_context(|| format!("writing {}", path.display()))
}

/// One measurement of `path`.
pub struct Measured {
    pub parse: f64,
    /// The first build after the parse, in seconds: it also pays the allocator's deferred
    /// work on the parse's freed temporaries (glibc consolidates them at the first large
    /// allocation), which grows with the file.
    pub first_build: f64,
    /// A second build of the same description: the build's own work.
    pub build: f64,
    /// Peak kB the first build added (VmHWM over VmRSS before it).
    pub peak_kb: u64,
    pub built: BuiltSummary,
}

/// Parses `path` and builds it twice.
pub fn parse_and_build(path: &Path) -> anyhow::Result<Measured> {
    let t = Instant::now();
    let desc =
        lxs::parse_file(path, &ParseOptions::default()).map_err(|e| anyhow::anyhow!("{e}"))?;
    let parse = t.elapsed().as_secs_f64();
    let dir = path.parent().unwrap_or(Path::new("."));
    // Reset the peak-RSS counter so that it measures the build on top of the description.
    let _ = std::fs::write("/proc/self/clear_refs", "5");
    let before = status_kb("VmRSS:").unwrap_or(0);
    let build = || -> anyhow::Result<(f64, Renderable)> {
        let t = Instant::now();
        let r = Renderable::build(&desc, dir).map_err(|e| anyhow::anyhow!("{e}"))?;
        Ok((t.elapsed().as_secs_f64(), r))
    };
    let (first_build, r) = build()?;
    let peak_kb = status_kb("VmHWM:").unwrap_or(0).saturating_sub(before);
    let built = r.world.built.clone();
    drop(r);
    let (second, _) = build()?;
    Ok(Measured {
        parse,
        first_build,
        build: second,
        peak_kb,
        built,
    })
}

/// A field of /proc/self/status in kB (VmHWM, VmRSS).
fn status_kb(field: &str) -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with(field))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

pub fn run(args: Args) -> anyhow::Result<std::process::ExitCode> {
    if let Some(path) = &args.child {
        let m = parse_and_build(path)?;
        println!(
            "{} {} {} {} {}",
            m.parse,
            m.first_build,
            m.build,
            m.peak_kb,
            built_line(&m.built)
        );
        return Ok(std::process::ExitCode::SUCCESS);
    }
    let tmp = tempfile::tempdir()?;
    let dir = args.dir.as_deref().unwrap_or(tmp.path());
    let scenes = generate(dir, args.count)?;
    println!(
        "machine load before: {}; {} unused textures, materials and objects; each build in a fresh process",
        crate::support::loadavg(),
        args.count
    );
    // Best of the runs: parse, first build, build (seconds), peak (kB).
    let mut best = [[f64::INFINITY; 4]; 2];
    let mut built: [String; 2] = Default::default();
    for _ in 0..args.runs.max(1) {
        for (k, path) in [&scenes.base, &scenes.padded].into_iter().enumerate() {
            let (v, s) = child(path)?;
            for (b, x) in best[k].iter_mut().zip(v) {
                *b = b.min(x);
            }
            built[k] = s;
        }
    }
    for (k, name) in ["without", "with"].into_iter().enumerate() {
        let [p, f, b, m] = best[k];
        println!(
            "{name:>7} the unused: parse {:.2} ms, first build {:.2} ms, build {:.2} ms, build peak +{:.2} MB; built {}",
            p * 1e3,
            f * 1e3,
            b * 1e3,
            m / 1024.0,
            built[k]
        );
    }
    let ratio = |i: usize| best[1][i] / best[0][i].max(1e-12);
    println!(
        "with / without: build {:.3}, first build {:.3}, build peak memory {:.3}, same things built: {}",
        ratio(2),
        ratio(1),
        ratio(3),
        built[0] == built[1]
    );
    println!("machine load after: {}", crate::support::loadavg());
    Ok(std::process::ExitCode::SUCCESS)
}

/// What was built, on one line.
fn built_line(s: &BuiltSummary) -> String {
    format!(
        "shapes={} objects={} materials={} textures={} images={} lights={}",
        s.shapes,
        s.objects,
        s.materials.join(","),
        s.textures.join(","),
        s.images,
        s.lights
    )
}

/// Runs one measurement in a fresh `luxfarm bench unused --child PATH` process: parse, first
/// build, build, peak, and what was built.
fn child(path: &Path) -> anyhow::Result<([f64; 4], String)> {
    let exe = std::env::current_exe()?;
    let out = std::process::Command::new(exe)
        .args(["bench", "unused", "--child"])
        .arg(path)
        .output()?;
    anyhow::ensure!(
        out.status.success(),
        "measuring {}: {}",
        path.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    let mut it = text.trim().splitn(5, ' ');
    let mut v = [0.0; 4];
    for x in v.iter_mut() {
        *x = it.next().context("short child output")?.parse()?;
    }
    Ok((v, it.next().unwrap_or_default().to_string()))
}
