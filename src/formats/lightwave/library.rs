//! Loading the object files a scene names, each once, and choosing the layers each object item
//! shows.
//!
//! ```text
//! Scene objects (file as written, layer) --paths::Resolver--> file --read within the byte
//!   budget--> object::parse --> Model (cached by canonical path)
//!   --> per object item: (model, layers)
//! ```
//!
//! A file that cannot be found is an error naming it and the .lws line; so is a layer the file
//! does not have. An error inside an object file is located in that file and names the .lws
//! line that loaded it.

use super::items::{ObjectSource, Scene};
use super::model::Model;
use super::object;
use super::paths::{read_within, Found, Resolver};
use crate::lxs::{Diagnostic, LxsError, LxsErrorKind};

pub struct Loaded {
    pub found: Found,
    pub model: Model,
}

/// The models, and for each object item of the scene its model and layer indices (None for
/// nulls).
pub struct Library {
    pub models: Vec<Loaded>,
    pub items: Vec<Option<(usize, Vec<usize>)>>,
}

pub fn load(
    scene: &Scene,
    resolver: &Resolver,
    budget: &mut u64,
    warnings: &mut Vec<Diagnostic>,
) -> Result<Library, LxsError> {
    let mut lib = Library {
        models: Vec::new(),
        items: Vec::new(),
    };
    for o in &scene.objects {
        let loc = &o.common.loc;
        let ObjectSource::File { path, layer } = &o.source else {
            lib.items.push(None);
            continue;
        };
        let found = resolver
            .find(path)
            .ok_or_else(|| resolver.missing("object", path, loc))?;
        let m = match lib
            .models
            .iter()
            .position(|l| l.found.canonical == found.canonical)
        {
            Some(i) => i,
            None => {
                let shown = found.display.to_string_lossy().into_owned();
                let bytes = read_within(&found.canonical, budget, loc)?;
                let model = object::parse(&bytes, &shown).map_err(|mut e| {
                    e.message = format!("{} (object loaded at {loc})", e.message);
                    e
                })?;
                warnings.extend(model.warnings.iter().cloned());
                lib.models.push(Loaded { found, model });
                lib.models.len() - 1
            }
        };
        let model = &lib.models[m].model;
        let layers = match layer {
            None => (0..model.layers.len()).collect(),
            Some(n) => match model.layer_for_scene(*n) {
                Some((i, false)) => vec![i],
                Some((i, true)) => {
                    warnings.push(Diagnostic {
                        loc: loc.clone(),
                        message: format!(
                            "{path} has no layer number {} (LAYR {}): its layer {n} in file order is used",
                            n,
                            n - 1
                        ),
                    });
                    vec![i]
                }
                None => {
                    return Err(LxsError::new(
                        LxsErrorKind::Undefined,
                        loc.clone(),
                        format!(
                            "{path} has no layer {n} (it has {} layer{})",
                            model.layers.len(),
                            if model.layers.len() == 1 { "" } else { "s" }
                        ),
                    ))
                }
            },
        };
        lib.items.push(Some((m, layers)));
    }
    Ok(lib)
}
