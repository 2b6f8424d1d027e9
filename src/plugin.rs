//! The plugin convention every family follows (camera, sampler, filter, integrator, shape,
//! light, material, texture, volume, tonemapper).
//!
//! ```text
//! Entity ("kind", ParamSet, Loc) --Family::build (family mod.rs: dispatch on the name only)-->
//!     plugin_file::build(&mut Stmt) (reads its own parameters, validates, warns) --> Family
//! ```
//!
//! - A family is a Rust enum (closed set, fast dispatch) in `src/<family>/mod.rs`. Its one
//!   factory is `Family::build(...)`; it matches the statement's name and calls the plugin
//!   file's `build`, nothing else. Unknown names are a [`BuildError`] listing the known ones.
//! - Each plugin lives in one file, `src/<family>/<name>.rs`, with its LuxRender defaults as
//!   constants and a `build` that reads its own parameters through a [`Stmt`]. Parameters read
//!   are marked used on the `ParamSet`; after the build, [`crate::scene`] reports every unused
//!   one as a located warning (a misspelling never passes in silence).
//! - Errors are one type, [`BuildError`] (location + message); warnings go to the statement's
//!   sink ([`Stmt::warn`]) and end in the render's warning list and the log.
//!
//! To add a plugin: write `src/<family>/<name>.rs` with its defaults and `build`, add a variant
//! to the family enum and one arm to the family's `build`.

use crate::lxs::{Diagnostic, Entity, Loc, ParamSet};

/// Why a plugin could not be built from its statement.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{loc}: {message}")]
pub struct BuildError {
    pub loc: Loc,
    pub message: String,
}

impl BuildError {
    pub fn new(loc: &Loc, message: impl Into<String>) -> BuildError {
        BuildError {
            loc: loc.clone(),
            message: message.into(),
        }
    }
}

/// One statement being built: its entity and where its warnings go.
pub struct Stmt<'a> {
    /// How messages name the family ("pixel filter", "sampler", ...).
    pub family: &'static str,
    pub entity: &'a Entity,
    warnings: &'a mut Vec<Diagnostic>,
}

impl<'a> Stmt<'a> {
    pub fn new(
        family: &'static str,
        entity: &'a Entity,
        warnings: &'a mut Vec<Diagnostic>,
    ) -> Stmt<'a> {
        Stmt {
            family,
            entity,
            warnings,
        }
    }

    pub fn params(&self) -> &'a ParamSet {
        &self.entity.params
    }

    pub fn kind(&self) -> &'a str {
        &self.entity.kind
    }

    pub fn loc(&self) -> &'a Loc {
        &self.entity.loc
    }

    /// An error at the statement.
    pub fn err(&self, message: impl Into<String>) -> BuildError {
        BuildError::new(&self.entity.loc, message)
    }

    /// A located warning, logged and kept with the render's warnings.
    pub fn warn(&mut self, message: impl Into<String>) {
        warn(self.warnings, &self.entity.loc, message);
    }

    /// The sink itself, for builders that hand it on.
    pub fn warnings(&mut self) -> &mut Vec<Diagnostic> {
        self.warnings
    }

    /// A float parameter that must be finite.
    pub fn finite(&self, name: &str, default: f32) -> Result<f32, BuildError> {
        let v = self.params().float_or(name, default);
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.err(format!(
                "{} \"{}\": {name} must be finite, got {v}",
                self.family,
                self.kind()
            )))
        }
    }

    /// A float parameter that must be finite and > 0.
    pub fn positive(&self, name: &str, default: f32) -> Result<f32, BuildError> {
        let v = self.params().float_or(name, default);
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(format!(
                "{} \"{}\": {name} must be positive, got {v}",
                self.family,
                self.kind()
            )))
        }
    }

    /// An integer parameter that must be at least `min`.
    pub fn int_at_least(&self, name: &str, default: i32, min: i32) -> Result<u32, BuildError> {
        let v = self.params().int_or(name, default);
        if v >= min && v >= 0 {
            Ok(v as u32)
        } else {
            Err(self.err(format!(
                "{} \"{}\": {name} must be at least {min}, got {v}",
                self.family,
                self.kind()
            )))
        }
    }
}

/// Pushes a located warning and logs it.
pub fn warn(warnings: &mut Vec<Diagnostic>, loc: &Loc, message: impl Into<String>) {
    let message = message.into();
    tracing::warn!("{loc}: {message}");
    warnings.push(Diagnostic {
        loc: loc.clone(),
        message,
    });
}

/// One located warning per parameter of `e` that no plugin read (`label` names the
/// statement: "Shape", "Material", ...).
pub fn report_unused(label: &str, e: &Entity, warnings: &mut Vec<Diagnostic>) {
    for p in e.params.unused() {
        let message = format!("{label} \"{}\": unused parameter \"{}\"", e.kind, p.name);
        warn(warnings, &p.loc, message);
    }
}
