//! The same scene gives the same files locally and on a farm: `luxfarm render` and
//! `luxfarm render --workers 1` write exactly the outputs the Film statement asks for
//! (`write_png`, `write_tga`, `write_exr`, `write_resume_flm`), named the same way (the Film's
//! `filename` beside the scene, or `-o BASENAME` with the suffix appended), and when an FLM is
//! asked the two FLMs carry the same header (resolution, light groups, buffer configurations
//! and every parameter).

mod cli_common;

use cli_common::SceneSpec;
use luxfarm::film::flm::read_flm;
use luxfarm::film::FlmHeader;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The tiny scene at 24x16 with its lamp (a smaller one, off centre) in the light group
/// "lamp"; `film` is appended to the Film statement.
fn scene(dir: &Path, film: &str) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let film = format!(
        r#"Film "fleximage" "integer xresolution" [24] "integer yresolution" [16]
  "string filename" ["frame"] {film}"#
    );
    let spec = SceneSpec {
        light_group: Some("lamp"),
        lamp: r#""integer indices" [0 2 1 0 3 2] "point P" [0.5 -0.5 3 1 -0.5 3 1 0 3 0.5 0 3]"#,
        ..SceneSpec::tiny(&film)
    };
    let p = dir.join("scene.lxs");
    std::fs::write(&p, spec.text()).unwrap();
    p
}

/// Runs `luxfarm render SCENE --haltspp 2 EXTRA...`, killed if it takes longer than the
/// bound (a broken farm fails the test instead of hanging it).
fn render(scene: &Path, extra: &[&str]) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_luxfarm"))
        .arg("render")
        .arg(scene)
        .args(["--haltspp", "2", "--seed", "3"])
        .args(extra)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run luxfarm");
    let end = Instant::now() + Duration::from_secs(300);
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if Instant::now() > end {
            let _ = child.kill();
            let _ = child.wait();
            panic!("luxfarm render {extra:?} did not finish in 300 s");
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let mut err = String::new();
    if let Some(mut e) = child.stderr.take() {
        use std::io::Read;
        let _ = e.read_to_string(&mut err);
    }
    assert!(status.success(), "luxfarm render {extra:?}: {err}");
}

/// Names of the files in `dir` except the scene.
fn outputs(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "scene.lxs")
        .collect()
}

fn header(flm: &Path) -> FlmHeader {
    let f = std::fs::File::open(flm).unwrap();
    read_flm(std::io::BufReader::new(f)).unwrap().1
}

fn set(names: &[&str]) -> BTreeSet<String> {
    names.iter().map(|s| s.to_string()).collect()
}

#[test]
fn local_and_farm_renders_write_the_files_the_film_asks_for() {
    let tmp = tempfile::tempdir().unwrap();
    let film = r#""bool write_png" ["true"] "bool write_tga" ["true"] "bool write_exr" ["false"]
  "bool write_resume_flm" ["true"]"#;
    let local = scene(&tmp.path().join("local"), film);
    let farm = scene(&tmp.path().join("farm"), film);
    render(&local, &[]);
    render(&farm, &["--workers", "1", "--threads", "1"]);
    let expected = set(&["frame.png", "frame.tga", "frame.flm"]);
    assert_eq!(outputs(local.parent().unwrap()), expected);
    assert_eq!(outputs(farm.parent().unwrap()), expected);
    let (a, b) = (
        header(&tmp.path().join("local/frame.flm")),
        header(&tmp.path().join("farm/frame.flm")),
    );
    assert_eq!((a.width, a.height, a.groups), (24, 16, 1));
    assert_eq!(a, b, "the local and the farm FLM headers differ");
    assert!(
        b.group_names() == ["lamp"],
        "light group names: {:?}",
        b.group_names()
    );
}

#[test]
fn an_explicit_base_name_gets_the_suffix_appended_locally_and_on_a_farm() {
    let tmp = tempfile::tempdir().unwrap();
    // Only an EXR: no PNG (on by default), no FLM.
    let film = r#""bool write_png" ["false"] "bool write_exr" ["true"]"#;
    let s = scene(&tmp.path().join("scene"), film);
    let (local, farm) = (tmp.path().join("local"), tmp.path().join("farm"));
    std::fs::create_dir_all(&local).unwrap();
    std::fs::create_dir_all(&farm).unwrap();
    render(&s, &["-o", local.join("take.v1").to_str().unwrap()]);
    let farm_base = farm.join("take.v1");
    let farm_base = farm_base.to_str().unwrap();
    render(&s, &["--workers", "1", "--threads", "1", "-o", farm_base]);
    assert_eq!(outputs(&local), set(&["take.v1.exr"]));
    assert_eq!(outputs(&farm), set(&["take.v1.exr"]));
    assert_eq!(outputs(s.parent().unwrap()), BTreeSet::new());
}
