//! `luxfarm render`: the halt rules of a local render, haltthreshold included (LuxRender's
//! convergence test every `convergencestep` spp), and the error when a scene has none.

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
