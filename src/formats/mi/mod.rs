//! mental ray scene files (`.mi`): the importer behind [`crate::formats`].
//!
//! ```text
//! .mi text --lexer (line:column)--> cursor --parse (statements, $include, $ifdef)-->
//!     MiScene (options, cameras, objects, instances, instgroups, lights, shaders,
//!              materials, the render statement)
//!     --assemble (walk from the render root)--> SceneDescription (+ located notes)
//! ```
//!
//! One file per concern: [`lexer`] and [`cursor`] (tokens and typed reads), [`params`]
//! (shader parameter lists), [`options`], [`camera`], [`objects`] (polygon groups, with
//! [`triangulate`]), [`instances`] (instances and instgroups, world→local matrices),
//! [`lights`] (mental ray's `miLight`: point, spot, directional, the area primitives and
//! object lights, onto luxfarm's light model; the block itself is read in `light_block.rs`),
//! [`shaders`] (shaders and materials onto luxfarm materials), [`parse`] (the statement loop)
//! and [`assemble`] (with `walk.rs`, the walk of the scene graph from the render root).
//!
//! What a scene cannot say in luxfarm's terms is a located warning in
//! `SceneDescription::warnings`; what is malformed is a located error. [`ParseOptions`]
//! bounds the input: total bytes over all files, include depth and confinement, and the
//! length of every list (vectors, vertices, polygons, parameters, placements).

pub mod assemble;
pub mod camera;
pub mod cursor;
pub mod instances;
pub mod lexer;
mod light_block;
pub mod lights;
pub mod objects;
pub mod options;
pub mod params;
pub mod parse;
pub mod shaders;
pub mod triangulate;
mod walk;

use crate::lxs::{LxsError, ParseOptions, SceneDescription};
use std::path::Path;

/// Imports the .mi file at `path` with what it includes.
pub fn parse_file(path: &Path, opts: &ParseOptions) -> Result<SceneDescription, LxsError> {
    let scene = parse::read_file(path, opts)?;
    assemble::assemble(&scene, opts.max_array_len)
}

/// Imports .mi text named `name` (a path: includes resolve against its directory).
pub fn parse_str(
    text: &str,
    name: &str,
    opts: &ParseOptions,
) -> Result<SceneDescription, LxsError> {
    let scene = parse::read_str(text, name, opts)?;
    assemble::assemble(&scene, opts.max_array_len)
}

/// The top-level statements a .mi file starts with (after comments).
const FIRST_WORDS: &[&str] = &[
    "$include",
    "$ifdef",
    "$ifndef",
    "$define",
    "options",
    "camera",
    "object",
    "instance",
    "instgroup",
    "light",
    "shader",
    "material",
    "declare",
    "link",
    "verbose",
    "version",
    "render",
];

/// Whether the start of a file looks like mental ray scene text: its first word (after
/// blank lines and `#` comments) is a .mi statement followed by a blank or a quote.
pub fn looks_like(head: &str) -> bool {
    let Some(line) = head
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#'))
    else {
        return false;
    };
    FIRST_WORDS.iter().any(|w| {
        line.strip_prefix(w)
            .is_some_and(|rest| rest.is_empty() || rest.starts_with([' ', '\t', '"', '<']))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn detection_by_content() {
        assert!(looks_like("# exported\n\n$include \"base.mdl\"\n"));
        assert!(looks_like("options \"opt\"\n"));
        assert!(looks_like("verbose on"));
        assert!(!looks_like("LookAt 0 0 0 0 1 0 0 0 1"));
        assert!(!looks_like("objects are nice"));
        assert!(!looks_like("<?xml version=\"1.0\"?>"));
        assert!(!looks_like(""));
    }
}
