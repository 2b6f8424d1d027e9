//! The .lxs scene language: lexer, parser, graphics state, and the resulting
//! [`SceneDescription`]. The parser drives a [`SceneBuilder`] mirroring LuxRender's API and
//! never creates render objects.
//!
//! ```text
//! text --lexer (streaming, byte level)--> parser (statements, values, Includes)
//!      --SceneBuilder calls--> DescriptionBuilder (graphics state) --> SceneDescription
//! ```

pub mod builder;
pub mod describe;
pub mod description;
pub mod error;
pub(crate) mod include;
pub mod lexer;
pub mod params;
pub mod parser;
pub mod suggest;
mod values;

pub use builder::SceneBuilder;
pub use describe::DescriptionBuilder;
pub use description::*;
pub use error::{LxsError, LxsErrorKind, LxsResult};
pub use params::{Loc, Param, ParamSet, ParamType, ParamValue, SpectrumValue};

use std::path::Path;

/// Limits and policies for parsing, in particular of untrusted scenes (the server).
#[derive(Clone, Debug)]
pub struct ParseOptions {
    /// Includes must resolve (symlinks followed) inside the root scene's directory; absolute
    /// paths and `..` escapes are refused.
    pub confine_to_root: bool,
    /// Deepest Include nesting (LuxRender allows 32).
    pub max_include_depth: usize,
    /// Most values in one array (a parameter or a statement's numbers).
    pub max_array_len: usize,
    /// Most bytes read over the root file and all its Includes.
    pub max_total_bytes: u64,
    /// Most parameter values instancing may copy (shapes of an object instanced inside
    /// another definition, emitting shapes placed per instance): copies multiply what the
    /// input holds.
    pub max_copied_values: u64,
    /// The animation frame to import, for formats whose scenes are animated (LightWave);
    /// `None`: the scene's own current frame. Formats without animation ignore it.
    pub frame: Option<i64>,
}

impl Default for ParseOptions {
    fn default() -> Self {
        ParseOptions {
            confine_to_root: false,
            max_include_depth: 32,
            max_array_len: 1 << 28,
            max_total_bytes: u64::MAX,
            max_copied_values: describe::MAX_COPIED_VALUES,
            frame: None,
        }
    }
}

/// Parses a scene file with its Includes into a description.
pub fn parse_file(path: &Path, opts: &ParseOptions) -> Result<SceneDescription, LxsError> {
    let name = path.to_string_lossy().into_owned();
    let file = std::fs::File::open(path).map_err(|e| {
        LxsError::new(
            LxsErrorKind::Io,
            Loc {
                file: name.as_str().into(),
                line: 0,
                col: 0,
            },
            format!("cannot open scene file: {e}"),
        )
    })?;
    let canonical = std::fs::canonicalize(path).ok();
    let mut builder = DescriptionBuilder::new(&name).with_copy_limit(opts.max_copied_values);
    let mut parser = parser::Parser::new(Box::new(file), &name, canonical, opts);
    parser.run(&mut builder)?;
    Ok(builder.finish())
}

/// Parses scene text named `name` (a path: Includes resolve against its directory).
pub fn parse_str(
    text: &str,
    name: &str,
    opts: &ParseOptions,
) -> Result<SceneDescription, LxsError> {
    let mut builder = DescriptionBuilder::new(name).with_copy_limit(opts.max_copied_values);
    parse_with(text.as_bytes(), name, opts, &mut builder)?;
    Ok(builder.finish())
}

/// Drives any [`SceneBuilder`] over text read from `reader`, named `name`.
pub fn parse_with<'a>(
    reader: impl std::io::Read + 'a,
    name: &str,
    opts: &ParseOptions,
    builder: &mut dyn SceneBuilder,
) -> Result<(), LxsError> {
    let mut parser = parser::Parser::new(Box::new(reader), name, None, opts);
    parser.run(builder)
}
