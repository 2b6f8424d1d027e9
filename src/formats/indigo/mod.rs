//! Indigo scenes (`.igs`, Indigo Renderer's XML scene format, with its `.igmesh` binary
//! meshes and `.igm` material files) imported as the [`SceneDescription`] the .lxs parser
//! produces: LuxRender entities with LuxRender parameter names.
//!
//! ```text
//! .igs --load (xml: locations, lenient cleaning; includes in place)--> [Item]
//!      --scene (settings, camera, tonemap, media, materials, meshes, models, lights)--> Scene
//!      --emit (LuxRender statement order)--> DescriptionBuilder --> SceneDescription
//! ```
//!
//! One file per concern: [`xml`] (reading with locations), [`node`] (typed element
//! accessors, duplicate and unused-element reports), [`ctx`] (paths, confinement, budget,
//! missing files), [`load`] (includes), [`scene`] (dialects and dispatch), [`settings`],
//! [`camera`], [`material`] (its parameter readers in `material_conv.rs`), [`texture`],
//! [`spectrum`], [`medium`], [`lights`], [`geometry`] (meshes and models), [`mesh`],
//! [`igmesh`], [`obj`], [`emit`].
//!
//! Every diagnostic names file:line:column of the XML element. The external files the scene
//! reads (includes, meshes) are listed in `SceneDescription::files`; textures, nk data and IES
//! files are `filename`/`mapname`/`name`/`iesname` parameters the render core reads. A mesh or
//! include whose file is missing does not stop the reading: [`import`] returns it;
//! [`load`] (what `luxfarm render` and `submit`, the master and the worker use) fails with one
//! error naming every missing file and the element that names it, and [`inspect`] (what
//! `luxfarm parse` uses) turns each into a located warning.

pub mod camera;
pub mod ctx;
pub mod emit;
pub mod geometry;
pub mod igmesh;
pub mod lights;
pub mod load;
pub mod material;
mod material_conv;
pub mod medium;
pub mod mesh;
pub mod node;
pub mod obj;
pub mod scene;
pub mod settings;
pub mod spectrum;
pub mod texture;
pub mod xml;

use crate::lxs::{
    DescriptionBuilder, Loc, LxsError, LxsErrorKind, ParseOptions, SceneBuilder, SceneDescription,
};
pub use ctx::Missing;
use std::path::Path;

/// An imported scene and the external files it names that could not be found.
pub struct Import {
    pub desc: SceneDescription,
    pub missing: Vec<Missing>,
}

/// Whether the start of a file is an Indigo scene: XML whose root element is `<scene>`.
pub fn is_indigo(head: &[u8]) -> bool {
    let text = String::from_utf8_lossy(head);
    let mut s = text.trim_start_matches('\u{feff}').trim_start();
    loop {
        if let Some(rest) = s.strip_prefix("<?") {
            match rest.find("?>") {
                Some(e) => s = rest[e + 2..].trim_start(),
                None => return false,
            }
        } else if let Some(rest) = s.strip_prefix("<!--") {
            match rest.find("-->") {
                Some(e) => s = rest[e + 3..].trim_start(),
                None => return false,
            }
        } else if let Some(rest) = s.strip_prefix("<!") {
            match rest.find('>') {
                Some(e) => s = rest[e + 1..].trim_start(),
                None => return false,
            }
        } else {
            break;
        }
    }
    s.strip_prefix("<scene")
        .and_then(|r| r.chars().next())
        .is_some_and(|c| c == '>' || c == '/' || c.is_whitespace())
}

/// Imports the Indigo scene at `path`; missing external files are returned, not an error.
pub fn import(path: &Path, opts: &ParseOptions) -> Result<Import, LxsError> {
    let ctx = ctx::Ctx::new(path, opts);
    let items = load::load(path, &ctx)?;
    finish(path, items, ctx)
}

/// Imports an Indigo scene given as bytes, named `path` (what it includes or names resolves
/// beside that path).
pub fn import_bytes(path: &Path, bytes: &[u8], opts: &ParseOptions) -> Result<Import, LxsError> {
    let ctx = ctx::Ctx::new(path, opts);
    let items = load::load_bytes(path, bytes, &ctx)?;
    finish(path, items, ctx)
}

fn finish(path: &Path, items: Vec<load::Item>, ctx: ctx::Ctx) -> Result<Import, LxsError> {
    let name = path.to_string_lossy().into_owned();
    let root = Loc {
        file: name.as_str().into(),
        line: 1,
        col: 1,
    };
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "indigo".into());
    let scene = scene::read(&items, &stem, &root, &ctx)?;
    let mut b = DescriptionBuilder::new(&name);
    for f in ctx.take_files() {
        b.include(&f, &root)?;
    }
    emit::emit(&scene, &mut b, &ctx)?;
    for item in &items {
        let e = &item.elem;
        if e.is_used() {
            e.report_unused(&ctx);
        } else {
            ctx.warn(
                &e.loc,
                format!(
                    "<{}> is not an Indigo scene element luxfarm knows: ignored",
                    e.name
                ),
            );
        }
    }
    let mut desc = b.finish();
    desc.warnings.extend(ctx.take_warnings());
    Ok(Import {
        desc,
        missing: ctx.take_missing(),
    })
}

/// Imports the Indigo scene at `path` for inspection: missing external files become located
/// warnings.
pub fn inspect(path: &Path, opts: &ParseOptions) -> Result<SceneDescription, LxsError> {
    let mut imp = import(path, opts)?;
    for m in imp.missing {
        imp.desc.warnings.push(crate::lxs::Diagnostic {
            loc: m.loc,
            message: format!(
                "{} file {} not found: the scene cannot be rendered without it",
                m.what, m.path
            ),
        });
    }
    Ok(imp.desc)
}

/// Imports the Indigo scene at `path`; fails naming every external file that is missing.
pub fn load(path: &Path, opts: &ParseOptions) -> Result<SceneDescription, LxsError> {
    let imp = import(path, opts)?;
    let Some(first) = imp.missing.first() else {
        return Ok(imp.desc);
    };
    let list: Vec<String> = imp
        .missing
        .iter()
        .map(|m| format!("{} {} (named at {})", m.what, m.path, m.loc))
        .collect();
    Err(LxsError::new(
        LxsErrorKind::MissingInclude,
        first.loc.clone(),
        format!(
            "{} file(s) the scene needs are missing: {}",
            imp.missing.len(),
            list.join("; ")
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn content_detection() {
        assert!(is_indigo(
            b"<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<scene>\n<camera/>"
        ));
        assert!(is_indigo(
            b"\xef\xbb\xbf<!-- exported -->\n<!==== banner ====>\n<scene >"
        ));
        assert!(!is_indigo(b"<?xml version=\"1.0\"?><scenedata>"));
        assert!(!is_indigo(b"<scenery>"));
        assert!(!is_indigo(b"LookAt 0 0 0 0 1 0 0 0 1"));
        assert!(!is_indigo(b"<!-- never closed"));
    }
}
