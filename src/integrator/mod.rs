//! Surface integrators: `path` (unidirectional path tracing with next-event estimation and
//! multiple importance sampling), `directlighting` (direct light at every hit plus perfect
//! specular chains) and `bidirectional` (bidirectional path tracing, [`bidirectional`]), with
//! LuxRender's parameters:
//!
//! - path: `maxdepth` (16), `rrstrategy` none/probability/efficiency ("efficiency"),
//!   `rrcontinueprob` (0.65), `includeenvironment` (true), `directlightsampling` (true),
//!   `lightstrategy` (older name `strategy`; "auto"; see [`crate::light::strategy`]),
//!   `shadowraycount` (1).
//! - directlighting: `maxdepth` (5) specular bounces, `lightstrategy`, `shadowraycount`.
//!
//! Depth convention (as LuxCore's, which the benchmark reference uses): `maxdepth` is the
//! number of path vertices that receive direct lighting; at the last vertex the light sample
//! takes the full weight (no BSDF continuation to share it with).
//!
//! - bidirectional: see [`bidirectional`].
//!
//! A scene without a SurfaceIntegrator statement renders with `path`, LuxRender 1.x's
//! built-in default (its exporters write `bidirectional`). LuxRender integrators not built
//! here (distributedpath, exphotonmap, igi, sppm, ...) fall back to `path` with a located
//! warning.
//!
//! Every integrator fills a [`SampleOut`]: radiance per light group at the sample's film
//! position, its alpha, and (bidirectional) [`Splat`]s at other film positions.
//!
//! Light sample weighting: with `one`, each of the `shadowraycount` draws picks light i with
//! probability q_i and samples it with density p; with `all`, light i gets
//! `nsamples × shadowraycount` draws. With n_i the expected draws on light i, a light sample
//! contributes f·L·w/(n_i·p) and a BSDF-sampled hit on the light f·L·w'/p_b, where w, w'
//! are power-heuristic weights over (n_i·p, p_b).

pub mod bidirectional;
pub mod direct;
pub mod directlighting;
pub mod path;
pub mod spectral;
pub mod volume;

use crate::lxs::{Diagnostic, Entity};
use crate::plugin::{BuildError, Stmt};
use crate::spectrum::Rgb;

pub use bidirectional::BidirIntegrator;
pub use directlighting::DirectLightingIntegrator;
pub use path::PathIntegrator;
pub use volume::VolumeIntegrator;

use crate::camera::Camera;
use crate::geometry::Ray;
use crate::light::LightStrategy;
use crate::material::bsdf::Bsdf;
use crate::material::Material;
use crate::sampler::SampleStream;
use crate::scene::World;
use glam::Vec2;

/// Settings shared by both integrators.
#[derive(Clone, Copy, Debug)]
pub struct DirectSettings {
    pub strategy: LightStrategy,
    pub shadow_rays: u32,
}

impl DirectSettings {
    fn build(s: &mut Stmt) -> DirectSettings {
        let p = s.params();
        let strategy = LightStrategy::from_params(p, "lightstrategy").unwrap_or_else(|name| {
            s.warn(format!("unknown lightstrategy \"{name}\", using \"auto\""));
            LightStrategy::Auto
        });
        DirectSettings {
            strategy,
            shadow_rays: p.int_or("shadowraycount", 1).max(1) as u32,
        }
    }
}

/// A contribution of a sample at another film position than the sample's own (a light
/// subpath reaching the camera): it goes to the film's per-screen buffer.
#[derive(Clone, Copy, Debug)]
pub struct Splat {
    /// Raster position over the full image.
    pub p_film: glam::Vec2,
    pub group: u32,
    pub l: Rgb,
    /// Its multiple importance sampling weight (Metropolis' `usevariance` hint).
    pub weight: f32,
}

/// What one sample contributes, reused from sample to sample by a render thread.
#[derive(Clone, Debug, Default)]
pub struct SampleOut {
    /// Radiance per light group at the sample's film position.
    pub l: Vec<Rgb>,
    /// Per light group, Σ weight × Y of the weighted contributions in `l` (bidirectional;
    /// divided by Y of `l` it is LuxRender's variance hint).
    pub weight_lum: Vec<f32>,
    pub alpha: f32,
    pub splats: Vec<Splat>,
    /// Bidirectional path tracing's vertex arrays.
    pub bidir: bidirectional::Scratch,
}

impl SampleOut {
    /// An empty output for `groups` light groups.
    pub fn new(groups: usize) -> SampleOut {
        SampleOut {
            l: vec![Rgb::BLACK; groups],
            weight_lum: vec![0.0; groups],
            ..SampleOut::default()
        }
    }

    /// Clears the contributions (keeps the allocations).
    pub fn clear(&mut self) {
        self.l.iter_mut().for_each(|c| *c = Rgb::BLACK);
        self.weight_lum.iter_mut().for_each(|v| *v = 0.0);
        self.splats.clear();
        self.alpha = 1.0;
    }
}

/// LuxRender 1.x integrators luxfarm does not build; they render with `path`.
pub const FALLBACK: [&str; 4] = ["distributedpath", "exphotonmap", "igi", "sppm"];

#[derive(Clone, Debug)]
pub enum Integrator {
    Path(PathIntegrator),
    DirectLighting(DirectLightingIntegrator),
    Bidirectional(BidirIntegrator),
}

impl Integrator {
    /// Builds the scene's SurfaceIntegrator; each integrator file reads its own parameters.
    /// Without a statement: `path`, LuxRender 1.x's built-in default. Integrators luxfarm does
    /// not build fall back to `path` with a located warning naming it.
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
            "bidirectional" => Integrator::Bidirectional(BidirIntegrator::build(&mut s)?),
            other => {
                let what = if FALLBACK.contains(&other) {
                    "is not built by luxfarm"
                } else {
                    "is not a LuxRender integrator luxfarm knows"
                };
                s.warn(format!(
                    "SurfaceIntegrator \"{other}\" {what}; rendering with \"path\" (its defaults)"
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
            Integrator::Bidirectional(b) => b.direct_settings(),
        }
    }

    /// Lets the integrator resolve what depends on the built world (bidirectional: its
    /// light subpath selection and sample dimension layout).
    pub fn prepare(&mut self, world: &World) {
        if let Integrator::Bidirectional(b) = self {
            b.prepare(world);
        }
    }

    /// Tells the integrator how far media are rendered (the scene's VolumeIntegrator).
    pub fn set_volume(&mut self, v: VolumeIntegrator) {
        match self {
            Integrator::Path(p) => p.volume = v,
            Integrator::DirectLighting(d) => d.volume = v,
            Integrator::Bidirectional(b) => b.volume = v,
        }
    }

    /// Whether samples may contribute away from their own film position ([`Splat`]s: the
    /// film then needs a per-screen "light" buffer).
    pub fn splats(&self) -> bool {
        matches!(self, Integrator::Bidirectional(_))
    }

    /// Radiance along a camera ray, added per light group into `l` (cleared by the caller);
    /// returns the sample's alpha (1 when the camera ray hit something). Bidirectional
    /// samples need [`Self::sample`].
    pub fn li(&self, scene: &World, ray: Ray, s: &mut SampleStream, l: &mut [Rgb]) -> f32 {
        match self {
            Integrator::Path(p) => p.li(scene, ray, s, l),
            Integrator::DirectLighting(d) => d.li(scene, ray, s, l),
            Integrator::Bidirectional(_) => 0.0,
        }
    }

    /// Everything one camera sample contributes, into `out` (cleared here).
    pub fn sample(
        &self,
        scene: &World,
        camera: &Camera,
        ray: Ray,
        s: &mut SampleStream,
        out: &mut SampleOut,
    ) {
        out.clear();
        match self {
            Integrator::Path(p) => out.alpha = p.li(scene, ray, s, &mut out.l),
            Integrator::DirectLighting(d) => out.alpha = d.li(scene, ray, s, &mut out.l),
            Integrator::Bidirectional(b) => b.sample(scene, camera, ray, s, out),
        }
    }
}

/// Adds `c` to light group `g` when it is a usable contribution.
pub(crate) fn add_group(l: &mut [Rgb], g: usize, c: Rgb) {
    if let Some(slot) = l.get_mut(g) {
        *slot += c;
    }
}

/// The samples [`Bsdf::sample_f`] reads, drawn only where its lobes read them
/// ([`Bsdf::sample_uses`]): an unread dimension would cost a sampler evaluation for nothing.
/// Every sampler keys its dimensions independently, so skipping one leaves the others as
/// they are distributed.
pub(crate) fn bsdf_samples(bsdf: &Bsdf, s: &mut SampleStream) -> (f32, Vec2) {
    let (uses_u, uses_u2) = bsdf.sample_uses();
    let u = if uses_u { s.next_1d() } else { 0.5 };
    let u2 = if uses_u2 {
        s.next_2d()
    } else {
        Vec2::splat(0.5)
    };
    (u, u2)
}

/// The sample a material's `bsdf` selects its component with ([`Material::uses_select`]),
/// drawn only for materials that read it (mix, layered and those built on them).
pub(crate) fn select_sample(material: &Material, s: &mut SampleStream) -> f32 {
    if material.uses_select() {
        s.next_1d()
    } else {
        0.5
    }
}
