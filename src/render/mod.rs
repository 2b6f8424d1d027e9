//! Render sessions: the frame is cut into tiles rendered in parallel (rayon) into per-tile
//! films, merged into the session film in fixed tile order, so the result depends only on
//! (seed, stream, pass index) — never on the thread count. Every sample's randomness comes
//! from the sampler keyed by (seed, stream, pixel, sample index). This file holds the session,
//! its maps and its film; `pass.rs` renders a pass.
//!
//! Samples whose XYZ is NaN/Inf or whose Y is negative are discarded and counted, never
//! splatted (LuxRender's rule).
//!
//! Integrators whose samples also contribute elsewhere on the film (bidirectional: light
//! subpaths reaching the camera) render their tiles in fixed batches: each batch's tile films
//! and splats are added to the pass film in tile order, so the film still depends only on
//! (seed, stream, pass) and the splats of a whole pass are never held at once.
//!
//! The `metropolis` and `erpt` samplers do not visit pixels: their passes run the session's
//! Markov chains ([`mlt`], [`erpt`]) into the film's per-screen buffers. Such a pass can last
//! minutes on a big film, so it may be wrapped up early, keeping its work
//! ([`Session::set_deadline`], [`Session::wrap_up_flag`], [`stops`]); the cancel flag
//! ([`Session::cancel_flag`]) instead discards the pass it interrupts, tiles or chains.
//!
//! A `noiseaware` sampler draws each pixel's samples of a pass by the session's sampling map
//! (`crate::sampler::map`). Its film keeps each pixel's luminance spread sums
//! (`crate::film::variance`, which farm deltas carry to the master); a local session
//! rebuilds the map from its own film at `convergencestep` spp and then at doubling steps
//! ([`noise`]); a farm worker's session instead takes the maps its master builds from the
//! merged film ([`Session::follow_external_maps`], [`Session::set_sampling_map`]). Passes
//! count the samples they actually took.
//!
//! A session may also be given a user sampling map ([`Session::set_user_map`], read from an
//! image by [`usermap`]): every sampler that takes maps (all but metropolis and erpt) then
//! samples by it, multiplied pixel by pixel with the noise-aware map when the sampler is
//! noise-aware, as LuxRender's film combines them:
//!
//! ```text
//! noise-aware map (built here, or the master's) --\
//!                                                  product (or the one present) --> passes
//! user map (set_user_map) ------------------------/
//! ```
//!
//! On the farm the master combines the two and sends the result; the worker's session takes
//! it as its external map and has no user map of its own.

pub mod buffers;
pub mod counts;
pub mod erpt;
pub mod extent;
pub mod mlt;
pub mod noise;
mod pass;
pub mod setup;
pub mod stops;
mod tile;
pub mod usermap;

use crate::film::{BufferType, Film, FilmParams, VarianceBuffer, ZBuffer};
use crate::lxs::SceneDescription;
use crate::sampler::map::{MapError, SamplingMap};
use setup::{Renderable, SetupError};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Instant;

pub use buffers::film_buffers;
pub use extent::SampleExtent;
pub use tile::{tiles, Tile, TILE_SIZE};

/// Tiles rendered in parallel before their splats are added (a fixed number, so that the
/// film does not depend on the thread count).
const SPLAT_BATCH: usize = 64;

/// An empty film for the scene's buffer (crop window) size, light groups and `buffers`.
fn new_film(scene: &Renderable, buffers: &[BufferType]) -> Result<Film, RenderError> {
    let fp = &scene.setup.film_params;
    Ok(Film::with_buffers(
        fp.x_pixel_count,
        fp.y_pixel_count,
        scene.world.groups().to_vec(),
        buffers.to_vec(),
    )?)
}

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error(transparent)]
    Setup(#[from] SetupError),
    #[error("cannot start the render threads: {0}")]
    Threads(String),
    #[error(transparent)]
    Film(#[from] crate::film::FilmError),
}

/// How a session samples: thread count (0: all cores), job seed and stream id (a farm gives
/// each worker its own stream).
#[derive(Clone, Copy, Debug, Default)]
pub struct SessionOptions {
    pub threads: usize,
    pub seed: u64,
    pub stream: u64,
}

/// What one pass did.
#[derive(Clone, Copy, Debug, Default)]
pub struct PassStats {
    /// Camera samples taken (sample extent pixels × pixelsamples, see [`extent`]; fewer for
    /// a wrapped-up chain pass: those it took).
    pub samples: u64,
    /// Contributions discarded as NaN/Inf/negative.
    pub rejected: u64,
    /// Finite contributions discarded by the film's outlier rejection (`outlierrejection_k`).
    pub outliers: u64,
    pub seconds: f64,
    /// Passes rendered (more than one in a sweep: [`Session::render_passes`]).
    pub passes: u64,
    /// False when the pass was cancelled (its partial work is discarded).
    pub complete: bool,
    /// True when a chain pass was wrapped up before its planned end ([`stops`]): its work is
    /// kept and counted (it is `complete` too).
    pub wrapped_up: bool,
}

pub struct Session {
    scene: Arc<Renderable>,
    buffers: Vec<BufferType>,
    film: Film,
    /// Depths, when the Film asks for a Z output.
    depth: Option<ZBuffer>,
    opts: SessionOptions,
    pass: u64,
    pool: rayon::ThreadPool,
    cancel: Arc<AtomicBool>,
    /// Set: chain passes end at their next batch boundary, keeping their work ([`stops`]).
    wrap_up: Arc<AtomicBool>,
    /// Chain passes end at their first batch boundary at or after it ([`stops`]).
    deadline: Option<Instant>,
    rejected: u64,
    outliers: u64,
    /// The Markov chains of a metropolis sampler.
    mlt: Option<mlt::MltState>,
    /// The seeds and chains of an erpt sampler.
    erpt: Option<erpt::ErptState>,
    /// The sampling map the passes follow (none: uniform): the noise-aware map, the user
    /// map, or their product.
    map: Option<Arc<SamplingMap>>,
    /// The noise-aware map (built from the film, or the master's on a farm worker).
    noise_map: Option<Arc<SamplingMap>>,
    /// The user sampling map, when one was given.
    user_map: Option<Arc<SamplingMap>>,
    /// Rebuilds the map from this session's film (local renders of a noise-aware sampler).
    map_builder: Option<noise::MapBuilder>,
    /// Each pixel's next sample index, from the first pass that follows a map on
    /// ([`counts`]).
    counts: Option<counts::SampleCounts>,
    /// Seconds per pass of the last sweep.
    pass_seconds: Option<f64>,
}

impl Session {
    /// A session over the scene `desc`; `files` opens the files it names (a directory for a
    /// local scene, or a [`crate::fileio::SceneFiles`] confined to a farm bundle).
    pub fn new(
        desc: &SceneDescription,
        files: impl Into<crate::fileio::SceneFiles>,
        opts: SessionOptions,
    ) -> Result<Session, RenderError> {
        let scene = Renderable::build(desc, files)?;
        Session::from_renderable(scene, opts)
    }

    pub fn from_renderable(
        scene: Renderable,
        opts: SessionOptions,
    ) -> Result<Session, RenderError> {
        let buffers = scene.setup.buffers();
        let mut film = new_film(&scene, &buffers)?;
        if scene.setup.sampler.noise_aware() && scene.setup.sampler.takes_maps() {
            // The film keeps the spread of each pixel's contributions, the noise-aware map's
            // measure of noise (`crate::film::variance`); its size is the film's.
            let v = VarianceBuffer::new(film.width(), film.height());
            film.set_variance(Some(v)).map_err(RenderError::from)?;
        }
        let mlt = scene
            .setup
            .sampler
            .mlt()
            .map(|_| mlt::MltState::new(opts.seed, opts.stream));
        let erpt = scene
            .setup
            .sampler
            .erpt()
            .map(|_| erpt::ErptState::new(opts.seed, opts.stream));
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(opts.threads)
            .build()
            .map_err(|e| RenderError::Threads(e.to_string()))?;
        let fp = &scene.setup.film_params;
        let depth = fp
            .wants_zbuf()
            .then(|| ZBuffer::new(fp.x_pixel_count, fp.y_pixel_count));
        let map_builder = scene
            .setup
            .sampler
            .noise_aware()
            .then(|| noise::MapBuilder::new(fp.convergence_step));
        Ok(Session {
            scene: Arc::new(scene),
            buffers,
            film,
            depth,
            opts,
            pass: 0,
            pool,
            cancel: Arc::new(AtomicBool::new(false)),
            wrap_up: Arc::new(AtomicBool::new(false)),
            deadline: None,
            rejected: 0,
            outliers: 0,
            mlt,
            erpt,
            map: None,
            noise_map: None,
            user_map: None,
            map_builder,
            counts: None,
            pass_seconds: None,
        })
    }

    /// Whether this session's sampler draws pixels by a sampling map.
    pub fn noise_aware(&self) -> bool {
        self.scene.setup.sampler.noise_aware()
    }

    /// The sampling map the next pass follows (`None`: uniform).
    pub fn sampling_map(&self) -> Option<&SamplingMap> {
        self.map.as_deref()
    }

    /// Stops rebuilding the map from this session's film: maps come from elsewhere (a
    /// farm worker, whose film is only a delta, takes its master's).
    pub fn follow_external_maps(&mut self) {
        self.map_builder = None;
    }

    /// Whether this session's sampler draws pixels by sampling maps at all (every sampler but
    /// erpt).
    pub fn takes_maps(&self) -> bool {
        self.scene.setup.sampler.takes_maps()
    }

    /// Sets the noise-aware sampling map of the next passes from elsewhere (a farm worker's
    /// master, which has already multiplied in the job's user map). Refused when its size is
    /// not the film buffer's; ignored (false) when the sampler takes no maps.
    pub fn set_sampling_map(&mut self, map: Arc<SamplingMap>) -> Result<bool, MapError> {
        let fp = &self.scene.setup.film_params;
        map.check_film(fp.x_pixel_count, fp.y_pixel_count)?;
        if !self.takes_maps() {
            return Ok(false);
        }
        self.noise_map = Some(map);
        self.combine_maps();
        Ok(true)
    }

    /// Sets (or with `None` clears) the user sampling map of the next passes: LuxRender's
    /// `luxSetUserSamplingMap`. Refused when its size is not the film buffer's; ignored
    /// (false) when the sampler takes no maps (erpt: the caller warns, see
    /// [`crate::sampler::Sampler::map_refusal`]).
    pub fn set_user_map(&mut self, map: Option<Arc<SamplingMap>>) -> Result<bool, MapError> {
        if let Some(m) = &map {
            let fp = &self.scene.setup.film_params;
            m.check_film(fp.x_pixel_count, fp.y_pixel_count)?;
        }
        if !self.takes_maps() {
            return Ok(false);
        }
        self.user_map = map;
        self.combine_maps();
        Ok(true)
    }

    /// The user sampling map, when one is set.
    pub fn user_map(&self) -> Option<&SamplingMap> {
        self.user_map.as_deref()
    }

    /// The map the passes follow: the product of the noise-aware and user maps when both
    /// exist, else the one that does (LuxRender's `Film::UpdateSamplingMap`).
    fn combine_maps(&mut self) {
        self.map = match (&self.noise_map, &self.user_map) {
            (Some(n), Some(u)) => match n.product(u) {
                Ok(m) => Some(Arc::new(m)),
                // Both were checked against the film: sizes always match.
                Err(e) => {
                    tracing::error!("sampling maps not combined: {e}");
                    Some(u.clone())
                }
            },
            (Some(m), None) | (None, Some(m)) => Some(m.clone()),
            (None, None) => None,
        };
    }

    /// After a pass: rebuilds the map from the film when due (local noise-aware renders).
    fn update_map(&mut self) {
        let Some(b) = self.map_builder.as_mut() else {
            return;
        };
        if !b.due(self.film.spp()) {
            return;
        }
        if let Some(m) = b.update(&self.film, &self.scene.setup.film_params.tonemap) {
            self.noise_map = Some(Arc::new(m));
            self.combine_maps();
        }
    }

    /// The world and render setup this session renders.
    pub fn renderable(&self) -> &Renderable {
        &self.scene
    }

    /// Located problems found while building the scene (unused parameters, fallbacks).
    pub fn warnings(&self) -> &[crate::lxs::Diagnostic] {
        &self.scene.warnings
    }

    pub fn film_params(&self) -> &FilmParams {
        &self.scene.setup.film_params
    }

    pub fn film(&self) -> &Film {
        &self.film
    }

    /// The depth buffer, when the Film asks for a Z output (since the last
    /// [`Self::take_film`], which takes it with the film).
    pub fn zbuffer(&self) -> Option<&ZBuffer> {
        self.depth.as_ref()
    }

    /// The depths the EXR output writes (with its normalisation).
    pub fn exr_depths(&self) -> Option<Vec<f32>> {
        let norm = self.scene.setup.film_params.exr.zbuf_norm;
        self.depth.as_ref().map(|z| z.depths(norm))
    }

    /// Passes rendered so far.
    pub fn passes(&self) -> u64 {
        self.pass
    }

    /// Passes that fit in `secs` seconds at the last sweep's pace (1 before any sweep, and
    /// at least 1): for callers bounded by time, so a sweep does not run past their limit.
    pub fn passes_within(&self, secs: f64) -> u64 {
        match self.pass_seconds {
            Some(p) if p > 0.0 && secs.is_finite() => (secs / p).floor().max(1.0) as u64,
            _ => 1,
        }
    }

    /// Camera samples per pixel per pass.
    pub fn pixel_samples(&self) -> u32 {
        self.scene.setup.sampler.pixel_samples()
    }

    /// Samples a pass takes without a sampling map: sample extent pixels × pixelsamples
    /// ([`extent`]; an erpt pass rounds up to whole seeds).
    pub fn pass_samples(&self) -> u64 {
        self.traces_per_pass()
    }

    /// The accumulated film since the last take, with the depth sums when the Film asks for
    /// a Z output (a farm delta carries both); the session's film and depth are cleared.
    pub fn take_film(&mut self) -> Film {
        let mut fresh = self.film.clone();
        fresh.clear();
        let mut film = std::mem::replace(&mut self.film, fresh);
        if let Some(z) = self.depth.as_mut() {
            let mut empty = z.clone();
            empty.clear();
            // The session's depth buffer has the film's size (both from the Film's crop).
            let _ = film.set_depth(Some(std::mem::replace(z, empty)));
        }
        film
    }

    /// The film's buffer layout (eye buffer, and the light buffer of bidirectional renders).
    pub fn buffers(&self) -> &[BufferType] {
        &self.buffers
    }

    /// Samples discarded (NaN/Inf/negative) over the whole session.
    pub fn rejected_samples(&self) -> u64 {
        self.rejected
    }

    /// Finite samples discarded by outlier rejection over the whole session.
    pub fn outlier_samples(&self) -> u64 {
        self.outliers
    }

    /// Set it to stop the current pass between tiles or chain batches (the pass is then
    /// discarded); it stays set, so every later pass is cancelled at once too.
    pub fn cancel_flag(&self) -> Arc<AtomicBool> {
        self.cancel.clone()
    }

    /// Set it (from any thread) to wrap up the current pass of a chain sampler (metropolis,
    /// erpt) at its next batch boundary, keeping its work ([`stops`]); while it stays set
    /// every chain pass ends after its first batch. Pixel-sampler passes ignore it.
    pub fn wrap_up_flag(&self) -> Arc<AtomicBool> {
        self.wrap_up.clone()
    }

    /// Chain passes (metropolis, erpt) started from now on end at their first batch
    /// boundary at or after `deadline` (after at least one batch), keeping their work and
    /// counting the samples they took ([`stops`]); `None` removes it. A caller bound by time
    /// (`halttime`) gives its end, so a pass of minutes does not run past it. Pixel-sampler
    /// passes ignore it (their sweeps are bounded by [`Self::passes_within`]).
    pub fn set_deadline(&mut self, deadline: Option<Instant>) {
        self.deadline = deadline;
    }

    /// The deadline of chain passes, if any ([`Self::set_deadline`]).
    pub fn deadline(&self) -> Option<Instant> {
        self.deadline
    }

    /// Whether this session's passes run Markov chains (metropolis, erpt), which a wrap-up
    /// ends early keeping their work, rather than tiles.
    pub fn runs_chains(&self) -> bool {
        self.mlt.is_some() || self.erpt.is_some()
    }

    /// Acceptance statistics of the metropolis or erpt chains (`None` for other samplers).
    pub fn chain_stats(&self) -> Option<mlt::ChainStats> {
        self.mlt
            .as_ref()
            .map(mlt::MltState::stats)
            .or_else(|| self.erpt.as_ref().map(erpt::ErptState::stats))
    }

    /// The erpt sampler's energy quantum (mean energy per mutation), once estimated.
    pub fn erpt_quantum(&self) -> Option<f64> {
        self.erpt.as_ref().and_then(erpt::ErptState::quantum)
    }

    /// Gives the erpt sampler the quantum an earlier session of this scene and seed
    /// estimated ([`Session::erpt_quantum`], any stream), so it skips its warm-up; the films
    /// are the same either way. Nothing for other samplers or a quantum not positive.
    pub fn set_erpt_quantum(&mut self, ed: f64) {
        if let Some(e) = self.erpt.as_mut() {
            e.set_quantum(ed);
        }
    }
}
