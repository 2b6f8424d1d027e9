//! `luxfarm render`: the halt rules of a local render, haltthreshold included (LuxRender's
//! convergence test every `convergencestep` spp), the error when a scene has none, and the
//! user sampling map (`--sampling-map IMAGE`: the film's pixel size, its crop window's when
//! it has one).

use std::path::Path;
use std::process::Command;

/// A 128x96 matte floor and sphere under a small area light, path traced with one sample
/// per pixel and pass (noisy, so the convergence test has work to do); `film` is appended
/// to the Film statement.
fn scene(dir: &Path, film: &str) -> std::path::PathBuf {
    let text = format!(
        r#"LookAt 0 -4 2  0 0 0.5  0 0 1
Camera "perspective" "float fov" [40]
Film "fleximage" "integer xresolution" [128] "integer yresolution" [96]
  "string filename" ["t"] "bool write_png" ["false"] "bool write_exr" ["false"]
  "bool write_resume_flm" ["true"] {film}
PixelFilter "box"
Sampler "random" "integer pixelsamples" [1]
SurfaceIntegrator "path" "integer maxdepth" [3]
WorldBegin
AttributeBegin
AreaLightSource "area" "color L" [20 20 20]
Shape "trianglemesh" "integer indices" [0 2 1 0 3 2] "point P" [0.5 -0.5 3 1 -0.5 3 1 0 3 0.5 0 3]
AttributeEnd
Material "matte" "color Kd" [0.5 0.5 0.5]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point P" [-5 -5 0 5 -5 0 5 5 0 -5 5 0]
Translate 0 0 0.5
Shape "sphere" "float radius" [0.5]
WorldEnd
"#
    );
    let p = dir.join("t.lxs");
    std::fs::write(&p, text).unwrap();
    p
}

fn render(scene: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_luxfarm"))
        .arg("render")
        .arg(scene)
        .arg("-o")
        .arg(out)
        .args(extra)
        .output()
        .expect("run luxfarm")
}

fn spp(flm: &Path) -> f64 {
    let f = std::fs::File::open(flm).unwrap();
    let (film, _) = luxfarm::film::flm::read_flm(std::io::BufReader::new(f)).unwrap();
    film.spp()
}

#[test]
fn haltthreshold_stops_a_local_render_later_when_stricter() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene(
        dir.path(),
        r#""float haltthreshold" [0.5] "float convergencestep" [4]"#,
    );
    let loose = dir.path().join("loose");
    let out = render(&s, &loose, &[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let n_loose = spp(&loose.with_extension("flm"));
    // Two convergence tests at least (the first only takes a snapshot), every 4 spp.
    assert!(n_loose >= 8.0, "stopped at {n_loose} spp");
    let strict = dir.path().join("strict");
    let out = render(&s, &strict, &["--haltthreshold", "0", "--haltspp", "400"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let n_strict = spp(&strict.with_extension("flm"));
    assert!(
        n_strict > n_loose,
        "strict threshold stopped at {n_strict} spp, loose at {n_loose}"
    );
}

/// `--halttime` ends a metropolis render inside its first pass: a pass here is 129 × 97 ×
/// 512 steps (the sample extent × pixelsamples: a minute of this debug build or more, at
/// 0.1 M steps/s on a loaded 2-core machine), and the render stops at the deadline's batch
/// boundary with the samples it took, its film kept. No time is asserted: the wait is a
/// hang guard only.
#[test]
fn halttime_ends_a_metropolis_render_inside_its_first_pass() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene(dir.path(), "");
    let text = std::fs::read_to_string(&s).unwrap().replace(
        r#"Sampler "random" "integer pixelsamples" [1]"#,
        r#"Sampler "metropolis" "integer pixelsamples" [512]"#,
    );
    assert!(text.contains("metropolis"));
    std::fs::write(&s, text).unwrap();
    let out = dir.path().join("mlt");
    let mut child = Command::new(env!("CARGO_BIN_EXE_luxfarm"))
        .arg("render")
        .arg(&s)
        .arg("-o")
        .arg(&out)
        .args(["--halttime", "1", "--threads", "2"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run luxfarm");
    let guard = std::time::Instant::now() + std::time::Duration::from_secs(600);
    while child.try_wait().unwrap().is_none() {
        if std::time::Instant::now() > guard {
            let _ = child.kill();
            panic!("the render did not stop within its first pass");
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    let done = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&done.stderr);
    assert!(done.status.success(), "{err}");
    let n = spp(&out.with_extension("flm"));
    // One pass reads 129 · 97 · 512 / (128 · 96) = 521 spp; a batch of the 16 chains is
    // 4096 steps (0.33 spp).
    assert!(n > 0.0 && n < 512.0, "{n} spp: {err}");
}

#[test]
fn a_scene_without_halt_condition_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene(dir.path(), "");
    let out = render(&s, &dir.path().join("x"), &[]);
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("no halt condition"), "{err}");
    let out = render(&s, &dir.path().join("x"), &["--haltthreshold", "2"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("not a fraction"));
}

/// A gray 8-bit PNG at `path` whose pixel (x, y) is `v(x, y)`.
fn write_png(path: &Path, w: u32, h: u32, v: impl Fn(u32, u32) -> u8) {
    use luxfarm::imageio::{encode_png, ChannelSet, LdrImage};
    let gray: Vec<f32> = (0..w * h)
        .map(|i| (f32::from(v(i % w, i / w)) + 0.5) / 255.0)
        .collect();
    let img = LdrImage {
        width: w,
        height: h,
        rgb: &vec![[0.0; 3]; gray.len()],
        gray: &gray,
        alpha: &[],
    };
    let mut out = Vec::new();
    encode_png(&mut out, &img, ChannelSet::Y, false).unwrap();
    std::fs::write(path, out).unwrap();
}

/// Mean per-pixel weight (the box filter's: sample counts) of the left and right halves of
/// an FLM's film.
fn weight_halves(flm: &Path) -> (f64, f64) {
    let f = std::fs::File::open(flm).unwrap();
    let (film, _) = luxfarm::film::flm::read_flm(std::io::BufReader::new(f)).unwrap();
    let w = film.width();
    let (mut l, mut r) = (0.0, 0.0);
    for (i, p) in film.buffer(0, 0).unwrap().chunks(5).enumerate() {
        if (i as u32 % w) < w / 2 {
            l += p[4];
        } else {
            r += p[4];
        }
    }
    let n = f64::from(w / 2 * film.height());
    (l / n, r / n)
}

#[test]
fn a_sampling_map_of_the_wrong_size_is_an_error_naming_both_sizes() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene(dir.path(), "");
    let map = dir.path().join("map.png");
    write_png(&map, 64, 48, |_, _| 100);
    let out = render(
        &s,
        &dir.path().join("o"),
        &["--haltspp", "1", "--sampling-map", map.to_str().unwrap()],
    );
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("64x48") && err.contains("128x96"), "{err}");
    assert!(err.contains("map.png"), "{err}");
    // a file that is no image
    std::fs::write(&map, b"hello").unwrap();
    let out = render(
        &s,
        &dir.path().join("o"),
        &["--haltspp", "1", "--sampling-map", map.to_str().unwrap()],
    );
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("sampling map image"), "{err}");
}

#[test]
fn a_sampling_map_of_the_films_size_renders_and_weighs_the_samples() {
    let dir = tempfile::tempdir().unwrap();
    // The crop window's buffer is 64x48: the map takes its size.
    let s = scene(dir.path(), r#""float cropwindow" [0 0.5 0 0.5]"#);
    let big = dir.path().join("big.png");
    write_png(&big, 128, 96, |_, _| 100);
    let out = render(
        &s,
        &dir.path().join("o"),
        &["--haltspp", "1", "--sampling-map", big.to_str().unwrap()],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("64x48"), "{err}");
    let map = dir.path().join("map.png");
    write_png(&map, 64, 48, |x, _| if x < 32 { 225 } else { 25 });
    let o = dir.path().join("mapped");
    let out = render(
        &s,
        &o,
        &["--haltspp", "8", "--sampling-map", map.to_str().unwrap()],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (l, r) = weight_halves(&o.with_extension("flm"));
    assert!((l / r - 9.0).abs() < 1.0, "left {l} right {r}");
    assert!(l > 8.0, "left {l}");
}
