//! Loading an Indigo scene's documents: the root `.igs` and, in place, every file an
//! `<include>` names (other `.igs` files, `.igm` material files), as one ordered list of
//! top-level elements.
//!
//! ```text
//! root.igs --xml--> <scene> children ... <include><pathname>x.igm</pathname></include> ...
//!    --> [Item(elem, dir of its file)] in document order, includes expanded where they stand
//! ```
//!
//! Includes resolve against the including file's directory, are confined like .lxs Includes
//! (`ParseOptions::confine_to_root`), count against the byte budget, may nest
//! `max_include_depth` deep and may not include themselves. An included file's root is
//! `<scene>` or `<scenedata>` (material files).

use super::ctx::{err, Ctx};
use super::node::Elem;
use super::xml;
use crate::lxs::{Loc, LxsError, LxsErrorKind};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A top-level element and the directory of the file it was written in.
pub struct Item {
    pub elem: Elem,
    pub dir: PathBuf,
}

/// Parses one file's bytes; `name` is how locations name it.
pub fn parse_file(bytes: &[u8], name: &str, ctx: &Ctx) -> Result<Elem, LxsError> {
    let file: Arc<str> = name.into();
    let parsed = xml::parse(bytes, &file)?;
    ctx.push_warnings(parsed.warnings);
    Ok(parsed.root)
}

/// Loads the root scene `path` and its includes.
pub fn load(path: &Path, ctx: &Ctx) -> Result<Vec<Item>, LxsError> {
    let loc = Loc {
        file: path.to_string_lossy().as_ref().into(),
        line: 0,
        col: 0,
    };
    let bytes = std::fs::read(path).map_err(|e| {
        err(
            LxsErrorKind::Io,
            &loc,
            format!("cannot open scene file: {e}"),
        )
    })?;
    load_bytes(path, &bytes, ctx)
}

/// Loads a root scene given as bytes, named `path` (its includes resolve beside it).
pub fn load_bytes(path: &Path, bytes: &[u8], ctx: &Ctx) -> Result<Vec<Item>, LxsError> {
    let name = path.to_string_lossy().into_owned();
    let loc = Loc {
        file: name.as_str().into(),
        line: 0,
        col: 0,
    };
    ctx.charge(bytes.len() as u64, &loc)?;
    let root = parse_file(bytes, &name, ctx)?;
    if root.name != "scene" {
        return Err(err(
            LxsErrorKind::Syntax,
            &root.loc,
            format!(
                "the root element of an Indigo scene is <scene>, not <{}>",
                root.name
            ),
        ));
    }
    root.mark_used();
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let canon = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
    let mut items = Vec::new();
    let mut stack = vec![canon];
    expand(root, &dir, ctx, &mut stack, &mut items)?;
    Ok(items)
}

fn expand(
    root: Elem,
    dir: &Path,
    ctx: &Ctx,
    stack: &mut Vec<PathBuf>,
    items: &mut Vec<Item>,
) -> Result<(), LxsError> {
    for elem in root.children {
        if elem.name != "include" {
            items.push(Item {
                elem,
                dir: dir.to_path_buf(),
            });
            continue;
        }
        elem.mark_all_used();
        let p = elem.need(ctx, "pathname")?;
        if stack.len() > ctx.opts.max_include_depth {
            return Err(err(
                LxsErrorKind::IncludeTooDeep,
                &p.loc,
                format!("includes nested deeper than {}", ctx.opts.max_include_depth),
            ));
        }
        let resolved = ctx.resolve(p.str(), dir, &p.loc)?;
        let canon = std::fs::canonicalize(&resolved).unwrap_or_else(|_| resolved.clone());
        if stack.contains(&canon) {
            return Err(err(
                LxsErrorKind::IncludeCycle,
                &p.loc,
                format!("{} includes itself", resolved.display()),
            ));
        }
        let Some((path, bytes)) = ctx.read(p.str(), dir, &p.loc, "include")? else {
            continue;
        };
        let inc = parse_file(&bytes, &path.to_string_lossy(), ctx)?;
        if inc.name != "scene" && inc.name != "scenedata" {
            return Err(err(
                LxsErrorKind::Syntax,
                &inc.loc,
                format!(
                    "an included Indigo file's root is <scene> or <scenedata>, not <{}>",
                    inc.name
                ),
            ));
        }
        inc.mark_used();
        let inc_dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        stack.push(canon);
        expand(inc, &inc_dir, ctx, stack, items)?;
        stack.pop();
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lxs::ParseOptions;

    #[test]
    fn includes_expand_in_place_with_cycles_and_escapes_refused() {
        let d = tempfile::tempdir().unwrap();
        std::fs::create_dir_all(d.path().join("mats")).unwrap();
        std::fs::write(
            d.path().join("s.igs"),
            "<scene><camera/><include><pathname>mats\\m.igm</pathname></include><mesh/></scene>",
        )
        .unwrap();
        std::fs::write(
            d.path().join("mats/m.igm"),
            "<scenedata><material/><material/></scenedata>",
        )
        .unwrap();
        let ctx = Ctx::new(&d.path().join("s.igs"), &ParseOptions::default());
        let items = load(&d.path().join("s.igs"), &ctx).unwrap();
        let names: Vec<&str> = items.iter().map(|i| i.elem.name.as_str()).collect();
        assert_eq!(names, ["camera", "material", "material", "mesh"]);
        assert_eq!(items[1].dir, d.path().join("mats"));
        assert!(items[1].elem.loc.file.ends_with("m.igm"));
        assert_eq!(ctx.take_files().len(), 1);

        std::fs::write(
            d.path().join("a.igs"),
            "<scene><include><pathname>b.igs</pathname></include></scene>",
        )
        .unwrap();
        std::fs::write(
            d.path().join("b.igs"),
            "<scene><include><pathname>a.igs</pathname></include></scene>",
        )
        .unwrap();
        let ctx = Ctx::new(&d.path().join("a.igs"), &ParseOptions::default());
        let e = load(&d.path().join("a.igs"), &ctx).err().unwrap();
        assert_eq!(e.kind, LxsErrorKind::IncludeCycle);
        assert!(e.loc.file.ends_with("b.igs"));

        std::fs::write(
            d.path().join("c.igs"),
            "<scene><include><pathname>../x.igs</pathname></include></scene>",
        )
        .unwrap();
        let confined = ParseOptions {
            confine_to_root: true,
            ..ParseOptions::default()
        };
        let ctx = Ctx::new(&d.path().join("c.igs"), &confined);
        let e = load(&d.path().join("c.igs"), &ctx).err().unwrap();
        assert_eq!(e.kind, LxsErrorKind::IncludeOutsideRoot);

        std::fs::write(d.path().join("w.igs"), "<notascene/>").unwrap();
        let ctx = Ctx::new(&d.path().join("w.igs"), &ParseOptions::default());
        assert_eq!(
            load(&d.path().join("w.igs"), &ctx).err().unwrap().kind,
            LxsErrorKind::Syntax
        );
    }
}
