//! The texture test scene `tests/data/surfaces/textures.lxs`: every LuxRender 1.x texture
//! class, in each of its value types, with every 2D mapping and 3D coordinate system. Every
//! declared texture must build with no warning (no fallback, no unread parameter), and the
//! scene (colour textures as matte Kd, float textures as bump maps) must build and render with
//! no warning to a finite, lit film.

mod render_util;

use luxfarm::lxs::TextureType;
use luxfarm::render::setup::Renderable;
use luxfarm::render::SessionOptions;
use luxfarm::texture::{TextureCtx, TextureSet};
use render_util::*;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The classes of the scene format document's "Texture Types" table, and LuxRender 1.x's
/// hitpoint textures.
const CLASSES: &[&str] = &[
    "add",
    "band",
    "bilerp",
    "blackbody",
    "brick",
    "cauchy",
    "checkerboard",
    "cloud",
    "colordepth",
    "constant",
    "dots",
    "equalenergy",
    "fbm",
    "fresnelcolor",
    "fresnelname",
    "gaussian",
    "harlequin",
    "imagemap",
    "lampspectrum",
    "luxpop",
    "marble",
    "mix",
    "multimix",
    "normalmap",
    "scale",
    "sellmeier",
    "sopra",
    "subtract",
    "tabulateddata",
    "uv",
    "uvmask",
    "windy",
    "wrinkled",
    "blender_blend",
    "blender_clouds",
    "blender_distortednoise",
    "blender_magic",
    "blender_marble",
    "blender_musgrave",
    "blender_noise",
    "blender_stucci",
    "blender_voronoi",
    "blender_wood",
    "hitpointcolor",
    "hitpointalpha",
    "hitpointgrey",
];

fn scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/surfaces/textures.lxs")
}

#[test]
fn every_texture_class_builds_without_a_warning() {
    let path = scene();
    let desc = parse(&path);
    let present: BTreeSet<&str> = desc
        .textures
        .iter()
        .map(|t| t.entity.kind.as_str())
        .collect();
    for class in CLASSES {
        assert!(present.contains(class), "the scene lacks a {class} texture");
    }
    let base_dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut set = TextureSet::new(
        &desc,
        TextureCtx {
            files: base_dir.into(),
        },
    );
    for t in &desc.textures {
        let built = match t.value_type {
            TextureType::Fresnel => set.named_fresnel(&t.name, &t.entity.loc).map(drop),
            ty => set.named(ty, &t.name, &t.entity.loc).map(drop),
        };
        if let Err(e) = built {
            panic!("{} ({}): {e}", t.name, t.entity.kind);
        }
    }
    let warnings: Vec<String> = set.warnings.iter().map(|w| w.to_string()).collect();
    assert!(warnings.is_empty(), "{warnings:#?}");
}

#[test]
fn the_texture_scene_renders_without_a_warning() {
    let path = scene();
    let desc = parse(&path);
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let built = Renderable::build(&desc, &base).expect("scene builds");
    let warnings: Vec<String> = built.warnings.iter().map(|w| w.to_string()).collect();
    assert!(warnings.is_empty(), "{warnings:#?}");
    let film = render(&desc, &base, SessionOptions::default(), 1);
    let px = normalized_xyz(&film);
    assert!(px.iter().flatten().all(|v| v.is_finite()));
    let lit = px.iter().filter(|p| p[1] > 0.0).count();
    assert!(lit > px.len() / 4, "{lit} of {} pixels lit", px.len());
}
