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
    render_seeded(scene, extra, 3)
}

/// [`render`] with another seed.
fn render_seeded(scene: &Path, extra: &[&str], seed: u32) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_luxfarm"))
        .arg("render")
        .arg(scene)
        .args(["--haltspp", "2", "--seed", &seed.to_string()])
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

/// The Z channel of an EXR, row by row.
fn exr_depths(path: &Path) -> Vec<f32> {
    let img = exr::prelude::read_all_flat_layers_from_file(path).expect("an EXR");
    let z = img.layer_data[0]
        .channel_data
        .list
        .iter()
        .find(|c| c.name.to_string() == "Z")
        .expect("a Z channel");
    z.sample_data.values_as_f32().collect()
}

/// The median relative difference of two depth images over the pixels `a` sees a surface
/// in, and the pixels where one sees a surface and the other none.
fn depth_difference(a: &[f32], b: &[f32]) -> (f32, usize) {
    let mut rel: Vec<f32> = a
        .iter()
        .zip(b)
        .filter(|(x, y)| **x > 0.0 && **y > 0.0)
        .map(|(x, y)| (y / x - 1.0).abs())
        .collect();
    rel.sort_by(f32::total_cmp);
    let odd = a
        .iter()
        .zip(b)
        .filter(|(x, y)| (**x > 0.0) != (**y > 0.0))
        .count();
    (rel[rel.len() / 2], odd)
}

#[test]
fn a_farm_render_writes_the_depth_its_workers_merged() {
    // The workers' deltas carry their depth sums: the farm's EXR has a Z channel that differs
    // from a local render's no more than two local renders with different seeds differ (at
    // 2 spp a pixel's depth is the mean of a few samples over its filter footprint).
    let tmp = tempfile::tempdir().unwrap();
    let film =
        r#""bool write_png" ["false"] "bool write_exr" ["true"] "bool write_exr_ZBuf" ["true"]"#;
    let dirs = ["local", "local2", "farm"].map(|d| tmp.path().join(d));
    let scenes = dirs.clone().map(|d| scene(&d, film));
    render(&scenes[0], &[]);
    render_seeded(&scenes[1], &[], 4);
    render(&scenes[2], &["--workers", "2", "--threads", "1"]);
    let [a, a2, b] = dirs.map(|d| exr_depths(&d.join("frame.exr")));
    assert_eq!(a.len(), 24 * 16);
    assert_eq!(a.len(), b.len());
    let hit = a.iter().filter(|&&d| d > 0.0).count();
    assert!(hit > a.len() / 2, "{hit} pixels see a surface");
    let (noise, noise_odd) = depth_difference(&a, &a2);
    let (farm, farm_odd) = depth_difference(&a, &b);
    assert!(
        farm <= 2.0 * noise && farm_odd <= 2 * noise_odd + 2,
        "farm against local: median {farm}, {farm_odd} pixels; two local renders: median \
         {noise}, {noise_odd} pixels"
    );
    // The comparison can fail: depths 10 % short are told apart.
    let short: Vec<f32> = b.iter().map(|d| d * 0.9).collect();
    assert!(depth_difference(&a, &short).0 > 2.0 * noise);
}
