//! Scene formats: the one seam through which every scene file enters luxfarm.
//!
//! ```text
//! path --detect (extension, then content)--> importer --> SceneDescription (+ located warnings)
//! ```
//!
//! [`load`] picks the importer for a file and returns the same [`SceneDescription`] whatever
//! the format, so the CLI (`parse`, `render`, `submit`), the master and the worker never
//! care which format a scene was written in. Every importer:
//!
//! - reports errors as [`SceneError`]s naming file:line:column, and warnings as located
//!   [`crate::lxs::Diagnostic`]s in `SceneDescription::warnings`;
//! - honours [`ParseOptions`]: confinement of every file it reads to the scene's directory
//!   (with `confine_to_root` set it opens them through [`crate::fileio::SceneFiles::confined`],
//!   the one confined open of the core), the byte budget and array limits for untrusted
//!   uploads;
//! - lists in `SceneDescription::files` every file it read besides the root (includes,
//!   meshes), so a farm bundle carries them and a worker can import the scene again.
//!
//! Importers: LuxRender's `.lxs` ([`crate::lxs`]), Indigo's `.igs` ([`indigo`]), LightWave's
//! `.lws` ([`lightwave`]) and mental ray's `.mi` ([`mi`]).

pub mod indigo;
pub mod lightwave;
pub mod mi;

use crate::lxs::{self, Loc, LxsError, LxsErrorKind, ParseOptions, SceneDescription};
use std::io::Read;
use std::path::Path;

/// A located scene error (the .lxs parser's error type serves every format).
pub type SceneError = LxsError;

/// The scene formats luxfarm reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneFormat {
    /// LuxRender 1.x scene text (`.lxs`; `.lxo`/`.lxm` are its Include fragments).
    Lxs,
    /// Indigo Renderer XML scene (`.igs`) with its `.igmesh` meshes and `.igm` materials.
    Indigo,
    /// LightWave scene (`.lws`, LWSC 3-5) with LWO2/LWOB objects, imported at one frame.
    LightWave,
    /// mental ray scene text (`.mi`).
    MentalRay,
}

impl SceneFormat {
    pub fn name(self) -> &'static str {
        match self {
            SceneFormat::Lxs => "LuxRender .lxs",
            SceneFormat::Indigo => "Indigo .igs",
            SceneFormat::LightWave => "LightWave .lws",
            SceneFormat::MentalRay => "mental ray .mi",
        }
    }

    /// The usual extension of a scene of this format (without the dot).
    pub fn extension(self) -> &'static str {
        match self {
            SceneFormat::Lxs => "lxs",
            SceneFormat::Indigo => "igs",
            SceneFormat::LightWave => "lws",
            SceneFormat::MentalRay => "mi",
        }
    }
}

/// File name extensions a user may submit as a scene (lower case, without the dot).
pub const SCENE_EXTENSIONS: &[&str] = &["lxs", "igs", "lws", "mi"];

/// The format of the scene file at `path`: by extension first, then by its first bytes
/// (a scene saved without its usual extension).
pub fn detect(path: &Path) -> Result<SceneFormat, SceneError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    match ext.as_str() {
        "lxs" | "lxo" | "lxm" => return Ok(SceneFormat::Lxs),
        "igs" => return Ok(SceneFormat::Indigo),
        "lws" => return Ok(SceneFormat::LightWave),
        "mi" => return Ok(SceneFormat::MentalRay),
        _ => {}
    }
    let mut head = [0u8; 512];
    let n = std::fs::File::open(path)
        .and_then(|mut f| f.read(&mut head))
        .map_err(|e| io_error(path, &format!("cannot open scene file: {e}")))?;
    detect_content(&head[..n]).ok_or_else(|| {
        LxsError::new(
            LxsErrorKind::Unsupported,
            file_loc(path),
            format!(
                "unknown scene format (known extensions: {})",
                SCENE_EXTENSIONS.join(", ")
            ),
        )
    })
}

/// Recognises a format from the start of a file.
pub fn detect_content(head: &[u8]) -> Option<SceneFormat> {
    if indigo::is_indigo(head) {
        return Some(SceneFormat::Indigo);
    }
    let text = String::from_utf8_lossy(head);
    if lightwave::detect(&text) {
        return Some(SceneFormat::LightWave);
    }
    if mi::looks_like(&text) {
        return Some(SceneFormat::MentalRay);
    }
    let first = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#'))?;
    const LXS_STATEMENTS: &[&str] = &[
        "LookAt",
        "Camera",
        "Film",
        "Sampler",
        "PixelFilter",
        "SurfaceIntegrator",
        "VolumeIntegrator",
        "Renderer",
        "Accelerator",
        "WorldBegin",
        "Include",
        "Transform",
        "ConcatTransform",
        "Scale",
        "Rotate",
        "Translate",
        "Identity",
        "AttributeBegin",
        "TransformBegin",
    ];
    LXS_STATEMENTS
        .iter()
        .any(|s| first.starts_with(s))
        .then_some(SceneFormat::Lxs)
}

/// Imports the scene file at `path` with its includes, whatever its format.
pub fn load(path: &Path, opts: &ParseOptions) -> Result<SceneDescription, SceneError> {
    match detect(path)? {
        SceneFormat::Lxs => lxs::parse_file(path, opts),
        SceneFormat::Indigo => indigo::load(path, opts),
        SceneFormat::LightWave => lightwave::load(path, opts),
        SceneFormat::MentalRay => mi::parse_file(path, opts),
    }
}

/// Imports the scene for inspection (`luxfarm parse`): as [`load`], except that external
/// files an importer reads at import time and cannot find (Indigo meshes and includes) are
/// located warnings instead of an error, as parsing a .lxs does not open the PLY files it
/// names. Rendering needs [`load`], which fails on them.
pub fn inspect(path: &Path, opts: &ParseOptions) -> Result<SceneDescription, SceneError> {
    match detect(path)? {
        SceneFormat::Indigo => indigo::inspect(path, opts),
        _ => load(path, opts),
    }
}

fn file_loc(path: &Path) -> Loc {
    Loc {
        file: path.to_string_lossy().as_ref().into(),
        line: 0,
        col: 0,
    }
}

fn io_error(path: &Path, message: &str) -> SceneError {
    LxsError::new(LxsErrorKind::Io, file_loc(path), message)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn content_detection_finds_lxs_statements_after_comments() {
        let text = b"# exported by LuxBlend\n\n  LookAt 0 0 0 0 1 0 0 0 1\n";
        assert_eq!(detect_content(text), Some(SceneFormat::Lxs));
        assert_eq!(
            detect_content(b"<?xml version=\"1.0\"?>\n<scene>"),
            Some(SceneFormat::Indigo)
        );
        assert_eq!(detect_content(b""), None);
        assert_eq!(
            detect_content(b"LWSC\n5\n\nFirstFrame 1\n"),
            Some(SceneFormat::LightWave)
        );
    }

    #[test]
    fn unknown_extension_and_content_is_a_located_error() {
        let dir = std::env::temp_dir().join(format!("luxfarm-formats-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("scene.txt");
        std::fs::write(&p, "hello").unwrap();
        let e = load(&p, &ParseOptions::default()).unwrap_err();
        assert_eq!(e.kind, LxsErrorKind::Unsupported);
        assert!(e.to_string().contains("scene.txt"), "{e}");
        let lxs = dir.join("renamed.scene");
        std::fs::write(
            &lxs,
            "LookAt 0 -5 0 0 0 0 0 0 1\nCamera \"perspective\"\nWorldBegin\nWorldEnd\n",
        )
        .unwrap();
        assert!(load(&lxs, &ParseOptions::default()).is_ok());
        std::fs::remove_dir_all(&dir).ok();
    }
}
