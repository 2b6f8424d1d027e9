//! Surface integrators: `path` (unidirectional path tracing with next-event estimation and
//! multiple importance sampling) and `directlighting` (direct light at every hit plus perfect
//! specular chains), with LuxRender's parameters:
//!
//! - path: `maxdepth` (16), `rrstrategy` none/probability/efficiency ("efficiency"),
//!   `rrcontinueprob` (0.65), `includeenvironment` (true), `directlightsampling` (true),
//!   `lightstrategy` one/all/auto/importance ("auto"), `shadowraycount` (1).
//! - directlighting: `maxdepth` (5) specular bounces, `lightstrategy`, `shadowraycount`.
//!
//! Depth convention (as LuxCore's, which the benchmark reference uses): `maxdepth` is the
//! number of path vertices that receive direct lighting; at the last vertex the light sample
//! takes the full weight (no BSDF continuation to share it with).
//!
//! Light sample weighting: with `one`, each of the `shadowraycount` draws picks light i with
//! probability q_i and samples it with density p; with `all`, light i gets
//! `nsamples × shadowraycount` draws. With n_i the expected draws on light i, a light sample
//! contributes f·L·w/(n_i·p) and a BSDF-sampled hit on the light f·L·w'/p_b, where w, w'
//! are power-heuristic weights over (n_i·p, p_b).

pub mod direct;
pub mod directlighting;
pub mod path;

use crate::lxs::{Diagnostic, Entity};
use crate::plugin::{BuildError, Stmt};
use crate::spectrum::Rgb;

pub use directlighting::DirectLightingIntegrator;
pub use path::PathIntegrator;

use crate::geometry::Ray;
use crate::light::LightStrategy;
use crate::sampler::SampleStream;
use crate::scene::World;

/// Settings shared by both integrators.
#[derive(Clone, Copy, Debug)]
pub struct DirectSettings {
    pub strategy: LightStrategy,
    pub shadow_rays: u32,
}

impl DirectSettings {
    fn build(s: &mut Stmt) -> DirectSettings {
        let p = s.params();
        let name = p.string_or("lightstrategy", "auto");
        let strategy = LightStrategy::parse(name).unwrap_or_else(|| {
            s.warn(format!("unknown lightstrategy \"{name}\", using \"auto\""));
            LightStrategy::Auto
        });
        DirectSettings {
            strategy,
            shadow_rays: p.int_or("shadowraycount", 1).max(1) as u32,
        }
    }
}

#[derive(Clone, Debug)]
pub enum Integrator {
    Path(PathIntegrator),
    DirectLighting(DirectLightingIntegrator),
}

impl Integrator {
    /// Builds the scene's SurfaceIntegrator; each integrator file reads its own parameters.
    /// LuxRender's default (no statement) is bidirectional, which luxfarm does not implement:
    /// it and the other unsupported integrators fall back to `path` with a warning.
    pub fn build(
        e: Option<&Entity>,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Integrator, BuildError> {
        let default = Entity {
            kind: "path".into(),
            ..Default::default()
        };
        let e = e.unwrap_or(&default);
        let mut s = Stmt::new("SurfaceIntegrator", e, warnings);
        Ok(match e.kind.as_str() {
            "path" => Integrator::Path(PathIntegrator::build(&mut s)?),
            "directlighting" => Integrator::DirectLighting(DirectLightingIntegrator::build(&mut s)),
            "distributedpath" => {
                s.warn(
                    "SurfaceIntegrator \"distributedpath\" is not supported; rendering with \"path\" \
                     (with the materials' compo_* flags)",
                );
                let fallback = Entity {
                    kind: "path".into(),
                    loc: e.loc.clone(),
                    ..Default::default()
                };
                let mut fs = Stmt::new("SurfaceIntegrator", &fallback, s.warnings());
                let mut p = PathIntegrator::build(&mut fs)?;
                p.compositing = true;
                Integrator::Path(p)
            }
            other => {
                s.warn(format!(
                    "SurfaceIntegrator \"{other}\" is not supported; rendering with \"path\""
                ));
                let fallback = Entity {
                    kind: "path".into(),
                    loc: e.loc.clone(),
                    ..Default::default()
                };
                let mut fs = Stmt::new("SurfaceIntegrator", &fallback, s.warnings());
                Integrator::Path(PathIntegrator::build(&mut fs)?)
            }
        })
    }

    pub fn direct_settings(&self) -> DirectSettings {
        match self {
            Integrator::Path(p) => p.direct,
            Integrator::DirectLighting(d) => d.direct,
        }
    }

    /// Radiance along a camera ray, added per light group into `l` (cleared by the caller);
    /// returns the sample's alpha (1 when the camera ray hit something).
    pub fn li(&self, scene: &World, ray: Ray, s: &mut SampleStream, l: &mut [Rgb]) -> f32 {
        match self {
            Integrator::Path(p) => p.li(scene, ray, s, l),
            Integrator::DirectLighting(d) => d.li(scene, ray, s, l),
        }
    }
}

/// Adds `c` to light group `g` when it is a usable contribution.
pub(crate) fn add_group(l: &mut [Rgb], g: usize, c: Rgb) {
    if let Some(slot) = l.get_mut(g) {
        *slot += c;
    }
}
