//! The configurations a study compares, as the user writes them (`--configs`):
//!
//! - `scene`: the scene as written (its own SurfaceIntegrator and Sampler);
//! - `INTEGRATOR/SAMPLER` (e.g. `path/sobol`, `bidirectional/random`): the scene with its
//!   SurfaceIntegrator and Sampler replaced;
//! - `farm:N`: the scene as written, rendered on a local farm of N worker processes.
//!
//! A replaced statement keeps the scene's own parameters when the kind is unchanged. When it
//! changes, the parameters that mean the same thing are carried over so that the comparison
//! renders the same image: `pixelsamples` for samplers; the path length for integrators
//! (`maxdepth` of path/directlighting, `eyedepth`/`lightdepth` of bidirectional).

use luxfarm::lxs::{Entity, Loc, ParamSet, ParamValue, SceneDescription};

/// Surface integrators a study may choose (the ones the render core implements).
const INTEGRATORS: &[&str] = &["path", "bidirectional", "directlighting"];
/// Samplers a study may choose.
const SAMPLERS: &[&str] = &["random", "sobol", "lowdiscrepancy"];
/// Largest local farm a study starts.
pub const MAX_FARM_WORKERS: usize = 16;

/// One configuration of a study.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Config {
    /// The scene's own integrator and sampler.
    Scene,
    Local {
        integrator: String,
        sampler: String,
    },
    Farm {
        workers: usize,
    },
}

impl Config {
    /// Reads one `--configs` item.
    pub fn parse(s: &str) -> Result<Config, String> {
        let s = s.trim();
        if s == "scene" {
            return Ok(Config::Scene);
        }
        if let Some(n) = s.strip_prefix("farm:") {
            let workers: usize = n
                .parse()
                .map_err(|_| format!("{s:?}: farm:N needs a worker count"))?;
            if workers == 0 || workers > MAX_FARM_WORKERS {
                return Err(format!(
                    "{s:?}: a local farm has 1 to {MAX_FARM_WORKERS} workers"
                ));
            }
            return Ok(Config::Farm { workers });
        }
        let Some((i, smp)) = s.split_once('/') else {
            return Err(format!(
                "{s:?}: expected scene, INTEGRATOR/SAMPLER (e.g. path/sobol) or farm:N"
            ));
        };
        if !INTEGRATORS.contains(&i) {
            return Err(format!(
                "{s:?}: integrator {i:?} is not one of {}",
                INTEGRATORS.join(", ")
            ));
        }
        if !SAMPLERS.contains(&smp) {
            return Err(format!(
                "{s:?}: sampler {smp:?} is not one of {}",
                SAMPLERS.join(", ")
            ));
        }
        Ok(Config::Local {
            integrator: i.to_string(),
            sampler: smp.to_string(),
        })
    }

    /// The label of the configuration in tables and plots; `Scene` is named after the
    /// scene's own statements.
    pub fn label(&self, desc: &SceneDescription) -> String {
        match self {
            Config::Scene => format!(
                "{}/{}",
                kind_of(desc.surface_integrator.as_ref(), "path"),
                kind_of(desc.sampler.as_ref(), "random")
            ),
            Config::Local {
                integrator,
                sampler,
            } => format!("{integrator}/{sampler}"),
            Config::Farm { workers } => format!("farm:{workers}"),
        }
    }

    pub fn workers(&self) -> Option<usize> {
        match self {
            Config::Farm { workers } => Some(*workers),
            _ => None,
        }
    }

    /// The scene this configuration renders locally (None for a farm configuration, which
    /// renders the scene file as written).
    pub fn apply(&self, desc: &SceneDescription) -> Option<SceneDescription> {
        match self {
            Config::Scene => Some(desc.clone()),
            Config::Local {
                integrator,
                sampler,
            } => {
                let mut d = desc.clone();
                d.surface_integrator = Some(replace_integrator(
                    d.surface_integrator.as_ref(),
                    integrator,
                ));
                d.sampler = Some(replace_sampler(d.sampler.as_ref(), sampler));
                Some(d)
            }
            Config::Farm { .. } => None,
        }
    }
}

/// The configurations run when `--configs` is not given: the scene's own, the same
/// integrator with the Sobol sampler, bidirectional with Sobol, and local farms of 1..=farm
/// workers. Configurations that render the same thing as an earlier one are left out.
pub fn defaults(desc: &SceneDescription, farm: usize) -> Vec<Config> {
    let own = kind_of(desc.surface_integrator.as_ref(), "path");
    let own = if INTEGRATORS.contains(&own.as_str()) {
        own
    } else {
        "path".to_string()
    };
    let mut out = vec![
        Config::Scene,
        Config::Local {
            integrator: own,
            sampler: "sobol".into(),
        },
        Config::Local {
            integrator: "bidirectional".into(),
            sampler: "sobol".into(),
        },
    ];
    out.extend((1..=farm.min(MAX_FARM_WORKERS)).map(|workers| Config::Farm { workers }));
    dedup(desc, out)
}

/// Leaves out configurations whose label repeats an earlier one.
pub fn dedup(desc: &SceneDescription, configs: Vec<Config>) -> Vec<Config> {
    let mut seen = std::collections::HashSet::new();
    configs
        .into_iter()
        .filter(|c| seen.insert(c.label(desc)))
        .collect()
}

fn kind_of(e: Option<&Entity>, default: &str) -> String {
    e.map_or_else(|| default.to_string(), |e| e.kind.clone())
}

fn int_param(e: Option<&Entity>, name: &str) -> Option<i32> {
    e?.params.params.iter().rev().find_map(|p| match &p.value {
        ParamValue::Integer(v) if p.name == name => v.first().copied(),
        _ => None,
    })
}

fn entity(kind: &str, old: Option<&Entity>, params: ParamSet) -> Entity {
    Entity {
        kind: kind.to_string(),
        params,
        loc: old.map_or_else(Loc::default, |e| e.loc.clone()),
    }
}

fn replace_integrator(old: Option<&Entity>, kind: &str) -> Entity {
    if let Some(e) = old.filter(|e| e.kind == kind) {
        return e.clone();
    }
    let depth = int_param(old, "maxdepth")
        .or_else(|| int_param(old, "eyedepth"))
        .or_else(|| int_param(old, "lightdepth"));
    let mut params = ParamSet::new();
    if let Some(d) = depth {
        if kind == "bidirectional" {
            params.add("eyedepth", ParamValue::Integer(vec![d]));
            params.add("lightdepth", ParamValue::Integer(vec![d]));
        } else {
            params.add("maxdepth", ParamValue::Integer(vec![d]));
        }
    }
    entity(kind, old, params)
}

fn replace_sampler(old: Option<&Entity>, kind: &str) -> Entity {
    if let Some(e) = old.filter(|e| e.kind == kind) {
        return e.clone();
    }
    let mut params = ParamSet::new();
    if let Some(n) = int_param(old, "pixelsamples") {
        params.add("pixelsamples", ParamValue::Integer(vec![n]));
    }
    entity(kind, old, params)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene() -> SceneDescription {
        let mut d = SceneDescription::default();
        let mut p = ParamSet::new();
        p.add("maxdepth", ParamValue::Integer(vec![5]));
        p.add("rrstrategy", ParamValue::String(vec!["none".into()]));
        d.surface_integrator = Some(entity("path", None, p));
        let mut s = ParamSet::new();
        s.add("pixelsamples", ParamValue::Integer(vec![4]));
        d.sampler = Some(entity("random", None, s));
        d
    }

    #[test]
    fn configurations_parse_and_refuse_clearly() {
        assert_eq!(Config::parse("scene"), Ok(Config::Scene));
        assert_eq!(Config::parse("farm:3"), Ok(Config::Farm { workers: 3 }));
        assert_eq!(
            Config::parse(" path/sobol "),
            Ok(Config::Local {
                integrator: "path".into(),
                sampler: "sobol".into()
            })
        );
        for bad in [
            "farm:0",
            "farm:x",
            "farm:99",
            "path",
            "photon/random",
            "path/x",
        ] {
            assert!(Config::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn a_replaced_integrator_keeps_the_path_length_and_samples() {
        let d = scene();
        let c = Config::parse("bidirectional/sobol").unwrap();
        let out = c.apply(&d).unwrap();
        let i = out.surface_integrator.as_ref();
        assert_eq!(i.map(|e| e.kind.as_str()), Some("bidirectional"));
        assert_eq!(int_param(i, "eyedepth"), Some(5));
        assert_eq!(int_param(i, "lightdepth"), Some(5));
        assert_eq!(int_param(out.sampler.as_ref(), "pixelsamples"), Some(4));
        assert_eq!(c.label(&d), "bidirectional/sobol");
        // The same kind keeps every parameter of the scene.
        let same = Config::parse("path/random").unwrap().apply(&d).unwrap();
        assert_eq!(same.surface_integrator, d.surface_integrator);
        assert_eq!(Config::Scene.label(&d), "path/random");
    }

    #[test]
    fn defaults_leave_out_repeats() {
        let mut d = scene();
        let labels: Vec<String> = defaults(&d, 2).iter().map(|c| c.label(&d)).collect();
        assert_eq!(
            labels,
            [
                "path/random",
                "path/sobol",
                "bidirectional/sobol",
                "farm:1",
                "farm:2"
            ]
        );
        d.sampler = Some(entity("sobol", None, ParamSet::new()));
        let labels: Vec<String> = defaults(&d, 0).iter().map(|c| c.label(&d)).collect();
        assert_eq!(labels, ["path/sobol", "bidirectional/sobol"]);
    }
}
