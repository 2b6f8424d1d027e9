//! The realistic camera end to end: a scene with a lens file renders (the sphere in front of
//! the lens shows in the image centre, inverted back upright), its Film's image effects apply
//! and its Z buffer holds the sphere's distance; a lens file outside the scene directory is a
//! located error.

mod render_util;

use luxfarm::render::setup::Renderable;
use luxfarm::render::{Session, SessionOptions};
use luxfarm::tonemap;
use render_util::*;
use std::path::{Path, PathBuf};

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/imaging")
}

#[test]
fn realistic_scene_with_effects_renders() {
    let path = data().join("realistic_effects.lxs");
    let desc = parse(&path);
    let mut s = Session::new(&desc, data(), SessionOptions::default()).expect("builds");
    assert!(s.render_pass().complete);
    let img = tonemap::tonemap_display(s.film(), &s.film_params().tonemap);
    let (w, h) = (img.width as usize, img.height as usize);
    let centre = img.rgb[(h / 2) * w + w / 2];
    assert!(centre[1] > 0.05, "{centre:?}");
    assert!(img.rgb.iter().flatten().all(|v| v.is_finite()));
    // The sphere (radius 40 at 300) is hit near the axis at about 260 from the lens front.
    let z = s.zbuffer().expect("Z buffer asked for").raw();
    let zc = z[(h / 2) * w + w / 2];
    assert!((zc - 260.0).abs() < 5.0, "{zc}");
}

#[test]
fn lens_file_outside_the_scene_directory_is_refused() {
    let text = std::fs::read_to_string(data().join("realistic_effects.lxs"))
        .unwrap()
        .replace("singlet.dat", "../../../Cargo.toml");
    let desc = parse_text(&text, &data().join("x.lxs"));
    // Confined as on the farm (a local render reads what its user points it at).
    let files = luxfarm::fileio::SceneFiles::confined(&data(), &data()).unwrap();
    let err = match Renderable::build(&desc, files) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("must be refused"),
    };
    assert!(
        err.contains("leaves the scene's directory") && err.contains(":5:"),
        "{err}"
    );
}
