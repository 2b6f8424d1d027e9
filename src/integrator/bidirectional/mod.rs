//! The `bidirectional` integrator: bidirectional path tracing with every connection
//! strategy weighted by multiple importance sampling (power heuristic), as LuxRender's
//! default integrator.
//!
//! Per camera sample: an eye subpath from the camera ([`walk::eye_walk`]) and one light
//! subpath per `lightpathstrategy` draw ([`walk::light_walk`]); then every strategy
//! ([`strategies`]): the eye path meeting lights (s = 0), direct lighting at each eye vertex
//! with the `lightstrategy` selection (s = 1), every light vertex joined to every eye vertex
//! (s, t ≥ 2), and every light vertex joined to the camera (t = 1, the light's own origin
//! included when it lies on an area light, as LuxRender joins it). The last ones land at
//! other film positions: they are returned as splats, which the render session adds to the
//! film's per-screen "light" buffer; the others go to the sample's own position ("eye"
//! buffer). Weights follow [`mis`]; each strategy's path densities are gathered in
//! `weight.rs`.
//!
//! Participating media: both subpaths carry the medium they are in; see [`walk`] (medium
//! vertices, distance sampling), [`vertex`] (their densities) and [`strategies`]
//! (transmittance along connections). The emission of region volumes is added along every
//! segment of the eye subpath, times the eye throughput at the segment's start, with weight
//! 1 (as path adds it: no light subpath or connection can end on volume emission, so the eye
//! path is its only strategy); light subpaths gather none. It goes to the first light
//! group, as path's does.
//!
//! Parameters (LuxRender's names and defaults): `eyedepth` (8) and `lightdepth` (8) vertices
//! per subpath (the camera and the light included, at most [`MAX_DEPTH`]),
//! `eyerrthreshold` and `lightrrthreshold` (0: Russian roulette on each vertex's scattering
//! efficiency; 1: none), `lightstrategy` (auto) and `lightpathstrategy` (auto).

pub mod layout;
pub mod mis;
pub mod strategies;
pub mod vertex;
pub mod walk;
mod weight;

use super::{DirectSettings, SampleOut, VolumeIntegrator};
use crate::camera::Camera;
use crate::geometry::Ray;
use crate::light::{LightSelector, LightStrategy};
use crate::plugin::{BuildError, Stmt};
use crate::sampler::SampleStream;
use crate::scene::World;
use layout::Layout;
use mis::PathDensities;
use vertex::{Ctx, Vertex};

/// Largest `eyedepth` / `lightdepth` accepted (LuxRender advises against 16 and more).
pub const MAX_DEPTH: u32 = 64;

/// The walks' vertices and the weight computation's arrays, reused from sample to sample.
#[derive(Clone, Debug, Default)]
pub struct Scratch {
    eye: Vec<Vertex>,
    light: Vec<Vertex>,
    crossings: Vec<(usize, Vertex)>,
    dens: PathDensities,
}

#[derive(Clone, Debug)]
pub struct BidirIntegrator {
    /// Eye subpath vertices, the camera included.
    pub eye_depth: u32,
    /// Light subpath vertices, the light included.
    pub light_depth: u32,
    pub eye_rr: f32,
    pub light_rr: f32,
    /// Direct lighting's light choice (`lightstrategy`).
    pub direct_strategy: LightStrategy,
    /// Light subpaths' light choice (`lightpathstrategy`).
    pub path_strategy: LightStrategy,
    /// How far media are rendered (the scene's VolumeIntegrator): attenuation only with
    /// `emission`, medium vertices (up to `max_scatters` per subpath) with `single`/`multi`.
    pub volume: VolumeIntegrator,
    path_selector: LightSelector,
    path_count: u32,
    layout: Layout,
}

fn strategy(s: &mut Stmt, name: &str) -> LightStrategy {
    LightStrategy::from_params(s.params(), name).unwrap_or_else(|v| {
        s.warn(format!("unknown {name} \"{v}\", using \"auto\""));
        LightStrategy::Auto
    })
}

fn depth(s: &mut Stmt, name: &str) -> Result<u32, BuildError> {
    let d = s.params().int_or(name, 8);
    if d < 1 {
        return Err(s.err(format!("{name} must be at least 1, got {d}")));
    }
    let d = d as u32;
    if d > MAX_DEPTH {
        s.warn(format!(
            "{name} {d} is more than {MAX_DEPTH}; using {MAX_DEPTH}"
        ));
        return Ok(MAX_DEPTH);
    }
    Ok(d)
}

fn threshold(s: &mut Stmt, name: &str) -> Result<f32, BuildError> {
    let v = s.params().float_or(name, 0.0);
    if !(v >= 0.0 && v.is_finite()) {
        return Err(s.err(format!("{name} must be a number >= 0, got {v}")));
    }
    Ok(v)
}

impl BidirIntegrator {
    /// Reads a `bidirectional` statement.
    pub fn build(s: &mut Stmt) -> Result<BidirIntegrator, BuildError> {
        let eye_depth = depth(s, "eyedepth")?;
        let light_depth = depth(s, "lightdepth")?;
        Ok(BidirIntegrator {
            eye_depth,
            light_depth,
            eye_rr: threshold(s, "eyerrthreshold")?,
            light_rr: threshold(s, "lightrrthreshold")?,
            direct_strategy: strategy(s, "lightstrategy"),
            path_strategy: strategy(s, "lightpathstrategy"),
            volume: VolumeIntegrator::default(),
            path_selector: LightSelector::All,
            path_count: 0,
            layout: Layout::new(eye_depth, light_depth, 0),
        })
    }

    /// What direct lighting needs from the world (its light strategy; one light sample).
    pub fn direct_settings(&self) -> DirectSettings {
        DirectSettings {
            strategy: self.direct_strategy,
            shadow_rays: 1,
        }
    }

    /// Resolves the light choices against the world's lights and fixes the dimension layout.
    pub fn prepare(&mut self, world: &World) {
        let n = world.lights().len() as u32;
        self.path_selector = LightSelector::new(self.path_strategy, world.lights());
        self.path_count = self.path_selector.count(n as usize);
        let direct = world.selector().count(n as usize);
        self.layout = Layout::new(self.eye_depth, self.light_depth, direct);
    }

    pub fn path_selector(&self) -> &LightSelector {
        &self.path_selector
    }

    /// Sample dimensions one sample draws (after [`Self::prepare`]).
    pub fn dimensions(&self) -> u32 {
        self.layout.total(self.path_count)
    }

    /// Traces both subpaths of one camera sample and adds every strategy's weighted
    /// contribution to `out` (`out.l` per light group at the sample's position, `out.splats`
    /// elsewhere); sets `out.alpha`.
    pub fn sample(
        &self,
        world: &World,
        camera: &Camera,
        ray: Ray,
        s: &mut SampleStream,
        out: &mut SampleOut,
    ) {
        let mut sc = std::mem::take(&mut out.bidir);
        let ctx = Ctx {
            world,
            camera,
            bidir: self,
            time: ray.time,
        };
        let lens = camera.lens_point(&ray);
        let walked = walk::eye_walk(
            &ctx,
            ray,
            lens,
            s,
            &self.layout,
            &mut sc.eye,
            &mut sc.crossings,
        );
        out.alpha = walked.alpha;
        // In the first light group, as path's (LuxRender's volume integrator's group).
        strategies::add_eye(out, 0, walked.medium_emission, 1.0);
        let ne = sc.eye.len();
        for t in 2..=ne {
            strategies::emission(&ctx, &mut sc.dens, &sc.eye, t, out);
            strategies::direct(&ctx, &mut sc.dens, &sc.eye, t, s, out);
        }
        let crossings = std::mem::take(&mut sc.crossings);
        for (n, v) in &crossings {
            strategies::crossing(&ctx, &mut sc.dens, &mut sc.eye, *n, v, out);
        }
        sc.crossings = crossings;
        for p in 0..self.path_count {
            let (index, draws) = match &self.path_selector {
                LightSelector::All => (p, 1.0),
                sel => {
                    s.set_dimension(self.layout.light_origin(p));
                    match sel.pick(p, s.next_1d()) {
                        Some((i, q)) => (i as u32, q),
                        None => continue,
                    }
                }
            };
            walk::light_walk(&ctx, index, draws, p, s, &self.layout, &mut sc.light);
            let nl = sc.light.len();
            if camera.connectable() {
                strategies::origin_to_camera(&ctx, &mut sc.dens, &sc.eye, &sc.light, index, out);
            }
            for sl in 2..=nl {
                for t in 2..=ne {
                    strategies::connect(&ctx, &mut sc.dens, &sc.eye, t, &sc.light, sl, index, out);
                }
                if camera.connectable() {
                    strategies::to_camera(&ctx, &mut sc.dens, &sc.eye, &sc.light, sl, index, out);
                }
            }
        }
        out.bidir = sc;
    }
}
