//! Every LuxRender TestSuite scene (`../shared/scenes/testsuite`) builds its own Sampler and
//! SurfaceIntegrator: none that asks for metropolis, erpt or bidirectional logs a fallback
//! or a refusal for them (issue 14), and none logs a warning about its volumes (issue 16).
//! The scenes are found on disk, so a scene added to the suite is checked too.

mod render_util;

use luxfarm::integrator::Integrator;
use luxfarm::lxs::{parse_file, LxsErrorKind, ParseOptions};
use luxfarm::render::setup::Renderable;
use luxfarm::sampler::SamplerKind;
use render_util::scene_path;
use std::path::{Path, PathBuf};

/// The `.lxs` files under `dir`, recursively, sorted.
fn scenes(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return out;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            out.extend(scenes(&p));
        } else if p.extension().is_some_and(|x| x == "lxs") {
            out.push(p);
        }
    }
    out.sort();
    out
}

#[test]
fn no_testsuite_scene_falls_back_from_metropolis_erpt_or_bidirectional() {
    let all = scenes(&scene_path("testsuite"));
    assert!(all.len() >= 10, "TestSuite scenes found: {}", all.len());
    let mut asked = 0;
    for path in &all {
        // One scene of the suite lacks its geometry file (sunsky_params: tested in
        // lxs_scenes.rs); the others must parse.
        let desc = match parse_file(path, &ParseOptions::default()) {
            Ok(d) => d,
            Err(e) if e.kind == LxsErrorKind::MissingInclude => continue,
            Err(e) => panic!("{}: {e}", path.display()),
        };
        let sampler = desc.sampler.as_ref().map_or("random", |s| s.kind.as_str());
        let integrator = desc
            .surface_integrator
            .as_ref()
            .map_or("path", |s| s.kind.as_str());
        let transport = ["metropolis", "erpt"].contains(&sampler) || integrator == "bidirectional";
        if !transport {
            continue;
        }
        asked += 1;
        let dir = path.parent().expect("scene directory");
        let r = Renderable::build(&desc, dir).expect("scene builds");
        let kind = r.setup.sampler.kind();
        match sampler {
            "metropolis" => assert_eq!(kind, SamplerKind::Metropolis, "{}", path.display()),
            "erpt" => assert_eq!(kind, SamplerKind::Erpt, "{}", path.display()),
            _ => {}
        }
        if integrator == "bidirectional" {
            assert!(
                matches!(r.setup.integrator, Integrator::Bidirectional(_)),
                "{}",
                path.display()
            );
        }
        let bad: Vec<_> = r
            .warnings
            .iter()
            .filter(|w| {
                let m = &w.message;
                let about = [
                    "ampler",
                    "SurfaceIntegrator",
                    "metropolis",
                    "erpt",
                    "bidirectional",
                ]
                .iter()
                .any(|k| m.contains(k));
                let fallback = [
                    "rendering with",
                    "not supported",
                    "not built",
                    "fall back",
                    "using \"",
                ]
                .iter()
                .any(|k| m.contains(k));
                about && fallback
            })
            .collect();
        assert!(bad.is_empty(), "{}: {bad:?}", path.display());
    }
    assert!(
        asked >= 5,
        "scenes asking for metropolis, erpt or bidirectional: {asked}"
    );
}

/// No TestSuite scene logs a warning about its volumes (issue 16): every `MakeNamedVolume`,
/// `Interior`, `Exterior` and `VolumeIntegrator` it writes is built. Both the description's
/// warnings and the scene build's are read.
#[test]
fn no_testsuite_scene_warns_about_its_volumes() {
    let all = scenes(&scene_path("testsuite"));
    assert!(all.len() >= 10, "TestSuite scenes found: {}", all.len());
    let mut built = 0;
    for path in &all {
        let desc = match parse_file(path, &ParseOptions::default()) {
            Ok(d) => d,
            Err(e) if e.kind == LxsErrorKind::MissingInclude => continue,
            Err(e) => panic!("{}: {e}", path.display()),
        };
        let dir = path.parent().expect("scene directory");
        let r = Renderable::build(&desc, dir).expect("scene builds");
        built += 1;
        let bad: Vec<String> = desc
            .warnings
            .iter()
            .chain(&r.warnings)
            .map(|w| w.message.to_lowercase())
            .filter(|m| {
                ["volume", "medium", "media", "interior", "exterior"]
                    .iter()
                    .any(|k| m.contains(k))
            })
            .collect();
        assert!(bad.is_empty(), "{}: {bad:?}", path.display());
    }
    assert!(built >= 10, "TestSuite scenes built: {built}");
}
