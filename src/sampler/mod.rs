//! Samplers: random, lowdiscrepancy, sobol, metropolis, erpt; every value derived from (seed,
//! stream, pixel, sample index, dimension), or for metropolis and erpt from a chain's primary
//! sample vector ([`metropolis`], [`erpt`]).
//!
//! [`Sampler::build`] dispatches a `Sampler` statement to the sampler's file, which reads its
//! parameters with LuxRender's names and defaults (random with 4 samples per pixel when the
//! scene has none, as LuxRender). LuxRender's other
//! samplers fall back with a warning: `bestcandidate`, `stratified` and `halton` to
//! lowdiscrepancy.
//!
//! `"bool noiseaware"` (random, lowdiscrepancy, sobol and the fallbacks to them) makes a pass
//! give each pixel a number of samples in proportion to a sampling map built, as LuxRender 1.x
//! builds it, from each pixel's spread of contributions over its visibility threshold
//! ([`map`]; the render session keeps the map). With metropolis, as in
//! LuxRender, the map weighs the chains' target (luminance × map density) and places their
//! large steps ([`map_warp`]); each contribution is divided by the density, so the image
//! stays unbiased. Erpt ignores the parameter with a warning, as LuxRender's. The user
//! sampling map (`crate::render::usermap`) applies to the same samplers
//! ([`Sampler::takes_maps`]).
//!
//! Metropolis and erpt samplers do not visit pixels: the render session runs their chains
//! ([`metropolis::Chain`], [`erpt::ErptChain`]) and traces each proposal through
//! [`Sampler::start_primary`], a stream over the proposed values whose dimensions 0 and 1
//! span the whole sampled film area.
//!
//! [`Sampler::start`] opens the [`SampleStream`] of one sample: a pure function of
//! `(seed, stream, px, py, index)` and of how many dimensions have been drawn, never of
//! threads or call order. Two stream ids give statistically independent estimates.
//!
//! # Dimension layout (every integrator must follow it)
//!
//! | dims | drawn with | meaning |
//! |------|------------|---------|
//! | 0, 1 | `next_2d` | film position within the pixel (`p_film = (px, py) + u`) |
//! | 2, 3 | `next_2d` | lens position |
//! | 4    | `next_1d` | time (shutter) |
//! | 5 .. | either    | the integrator's, in a fixed order per path vertex |
//!
//! A value nobody reads is not drawn: the path integrator draws a material's selection
//! sample, a BSDF's lobe choice and direction, and the light pick sample only where the hit's
//! material or the scene's lights read them. So which dimensions a vertex takes depends on
//! its material (as it already did on whether the BSDF is specular); every sampler keys each
//! dimension on its own, so that changes no value's distribution.
//!
//! [`SampleStream::camera_sample`] draws dims 0..5 in that order. Dimensions are counted:
//! `next_1d` uses one, `next_2d` two. For the best stratification, draw 2D quantities with
//! `next_2d` (lowdiscrepancy and sobol stratify each 2D request jointly).

pub mod erpt;
mod hash;
mod lowdiscrepancy;
pub mod map;
mod map_filter;
pub mod map_warp;
pub mod metropolis;
mod random;
mod sobol;

pub use hash::{combine, mix64, pixel_key, unit_f32};

use crate::camera::CameraSample;
use crate::lxs::{Diagnostic, Entity, Loc};
use crate::plugin::{BuildError, Stmt};
use glam::Vec2;

/// The sequence family.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SamplerKind {
    Random,
    LowDiscrepancy,
    Sobol,
    /// Kelemen-style Metropolis over the primary sample space (a stream over a chain's
    /// values).
    Metropolis,
    /// Energy redistribution path tracing: chains of small mutations from uniform seeds
    /// (streams over a chain's values, like metropolis).
    Erpt,
}

/// A sampler: its sequence and samples per pixel per pass.
#[derive(Clone, Debug, PartialEq)]
pub struct Sampler {
    kind: SamplerKind,
    pixel_samples: u32,
    /// log2 of `pixel_samples` for lowdiscrepancy (a power of two there).
    log2_n: u32,
    /// The metropolis parameters (metropolis only).
    mlt: Option<metropolis::MltParams>,
    /// The erpt parameters (erpt only).
    erpt: Option<erpt::ErptParams>,
    /// `noiseaware`: pixels are sampled in proportion to a sampling map ([`map`]).
    noise_aware: bool,
}

/// `pixelsamples` of a sampler statement: at least 1.
fn pixel_samples(s: &Stmt) -> Result<u32, BuildError> {
    let n = s
        .params()
        .int_or("pixelsamples", DEFAULT_PIXEL_SAMPLES as i32);
    u32::try_from(n).ok().filter(|&n| n >= 1).ok_or_else(|| {
        s.err(format!(
            "sampler \"{}\": pixelsamples must be at least 1, got {n}",
            s.kind()
        ))
    })
}

/// `xsamples × ysamples` of the old stratified-style statements (2 × 2 by default).
fn xy_samples(s: &Stmt, xs: Option<i32>, ys: Option<i32>) -> Result<u32, BuildError> {
    let prod = i64::from(xs.unwrap_or(2)) * i64::from(ys.unwrap_or(2));
    u32::try_from(prod).ok().filter(|&n| n >= 1).ok_or_else(|| {
        s.err(format!(
            "xsamples * ysamples must be at least 1, got {prod}"
        ))
    })
}

/// LuxRender's default `pixelsamples`.
pub const DEFAULT_PIXEL_SAMPLES: u32 = 4;

impl Sampler {
    /// Builds the sampler of a `Sampler` statement (`None`: LuxRender's default, random with
    /// 4 samples per pixel). Each sampler file reads its own parameters; this reads the ones
    /// every sampler shares and dispatches on the name.
    pub fn build(
        e: Option<&Entity>,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Sampler, BuildError> {
        let Some(e) = e else {
            return Sampler::new(SamplerKind::Random, DEFAULT_PIXEL_SAMPLES);
        };
        let mut s = Stmt::new("sampler", e, warnings);
        let p = s.params();
        // LuxRender's pixel visiting order: irrelevant to a deterministic per-pixel sampler.
        let _ = p.string("pixelsampler");
        let noise_aware = p.bool("noiseaware") == Some(true);
        let (kind, n) = match e.kind.as_str() {
            "random" => random::build(&mut s)?,
            "lowdiscrepancy" => lowdiscrepancy::build(&s)?,
            "sobol" => sobol::build(&s)?,
            "stratified" | "bestcandidate" | "halton" => lowdiscrepancy::build_legacy(&mut s)?,
            "metropolis" => {
                let (kind, n, mlt) = metropolis::build(&mut s)?;
                let mut smp = Sampler::new(kind, n).map_err(|x| BuildError::new(&e.loc, x.message))?;
                smp.mlt = Some(mlt);
                smp.noise_aware = noise_aware;
                return Ok(smp);
            }
            "erpt" => {
                if noise_aware {
                    s.warn("noiseaware is not supported by erpt (nor by LuxRender's); ignored");
                }
                let (kind, n, params) = erpt::build(&mut s)?;
                let mut smp = Sampler::new(kind, n).map_err(|x| BuildError::new(&e.loc, x.message))?;
                smp.erpt = Some(params);
                return Ok(smp);
            }
            other => {
                return Err(s.err(format!(
                    "unknown sampler \"{other}\" (known: random, lowdiscrepancy, sobol, metropolis, erpt; bestcandidate, stratified, halton fall back)"
                )))
            }
        };
        let mut smp = Sampler::new(kind, n).map_err(|x| BuildError::new(&e.loc, x.message))?;
        smp.noise_aware = noise_aware;
        Ok(smp)
    }

    /// A sampler of this kind; lowdiscrepancy rounds `pixel_samples` up to a power of two
    /// (with a warning), as LuxRender does.
    pub fn new(kind: SamplerKind, pixel_samples: u32) -> Result<Sampler, BuildError> {
        let mut n = pixel_samples.max(1);
        if kind == SamplerKind::LowDiscrepancy && !n.is_power_of_two() {
            let up = n.checked_next_power_of_two().ok_or_else(|| {
                BuildError::new(&Loc::default(), format!("pixelsamples {n} too large"))
            })?;
            tracing::warn!("lowdiscrepancy sampler: pixelsamples {n} rounded up to {up}");
            n = up;
        }
        Ok(Sampler {
            kind,
            pixel_samples: n,
            log2_n: n.trailing_zeros(),
            mlt: (kind == SamplerKind::Metropolis).then(metropolis::MltParams::default),
            erpt: (kind == SamplerKind::Erpt).then(erpt::ErptParams::default),
            noise_aware: false,
        })
    }

    /// Whether pixels are drawn by a sampling map (`noiseaware`; never for erpt).
    pub fn noise_aware(&self) -> bool {
        self.noise_aware && self.takes_maps()
    }

    /// Whether the sampler draws pixels by sampling maps at all (noise-aware or the user's):
    /// every sampler but erpt.
    pub fn takes_maps(&self) -> bool {
        self.kind != SamplerKind::Erpt
    }

    /// Why a user sampling map is not applied with this sampler (`None`: it is).
    pub fn map_refusal(&self) -> Option<&'static str> {
        match self.kind {
            SamplerKind::Erpt => Some(
                "the erpt sampler does not take sampling maps (nor does LuxRender's); the map \
                 is not applied",
            ),
            _ => None,
        }
    }

    /// This sampler with noise-aware sampling on or off (erpt stays off).
    pub fn with_noise_aware(mut self, on: bool) -> Sampler {
        self.noise_aware = on;
        self
    }

    pub fn kind(&self) -> SamplerKind {
        self.kind
    }

    /// The metropolis parameters, when this is a metropolis sampler.
    pub fn mlt(&self) -> Option<&metropolis::MltParams> {
        self.mlt.as_ref()
    }

    /// The erpt parameters, when this is an erpt sampler.
    pub fn erpt(&self) -> Option<&erpt::ErptParams> {
        self.erpt.as_ref()
    }

    /// Whether the film's eye buffer is normalised per screen (the sample density follows
    /// the image, not the pixels).
    pub fn per_screen(&self) -> bool {
        matches!(self.kind, SamplerKind::Metropolis | SamplerKind::Erpt)
    }

    /// A stream over a chain's proposed `values` (see [`metropolis`], [`erpt`]): dimension `d` is
    /// `values[d]`; dimensions beyond them are drawn from `fresh_key` and appended (take the
    /// vector back with [`SampleStream::into_values`]). Dimensions 0 and 1 place the sample
    /// on the film area starting at raster `origin` of size `span`.
    pub fn start_primary(
        values: Vec<f32>,
        fresh_key: u64,
        origin: Vec2,
        span: Vec2,
    ) -> SampleStream {
        SampleStream {
            kind: SamplerKind::Metropolis,
            key: fresh_key,
            index: 0,
            log2_n: 0,
            dim: 0,
            px: 0,
            py: 0,
            values,
            origin,
            span,
            stratified: None,
        }
    }

    /// Samples per pixel in one pass.
    pub fn pixel_samples(&self) -> u32 {
        self.pixel_samples
    }

    /// The stream of sample `index` (counting over all passes: pass `k` uses indices
    /// `k * pixel_samples ..`) of pixel (`px`, `py`).
    pub fn start(&self, seed: u64, stream: u64, px: u32, py: u32, index: u64) -> SampleStream {
        self.start_at(seed, stream, px as i32, py as i32, index)
    }

    /// [`Sampler::start`] for any pixel, including those left of or above the image:
    /// LuxRender samples `filter.sample_extent(..)`, which reaches beyond the image by the
    /// filter radius, so border pixels get full filter coverage. For pixels inside the image
    /// both give the same values.
    pub fn start_at(&self, seed: u64, stream: u64, px: i32, py: i32, index: u64) -> SampleStream {
        let pk = pixel_key(seed, stream, px as u32, py as u32);
        let key = match self.kind {
            SamplerKind::Random => random::sample_key(pk, index),
            SamplerKind::LowDiscrepancy => lowdiscrepancy::block_key(pk, index, self.log2_n),
            SamplerKind::Sobol => sobol::run_key(pk, index),
            // Outside a chain a metropolis or erpt stream draws independent values (as random).
            SamplerKind::Metropolis | SamplerKind::Erpt => random::sample_key(pk, index),
        };
        SampleStream {
            // The chains' streams come from `start_primary`; a pixel's stream is random.
            kind: match self.kind {
                SamplerKind::Erpt => SamplerKind::Random,
                k => k,
            },
            key,
            index,
            log2_n: self.log2_n,
            dim: 0,
            px,
            py,
            values: Vec::new(),
            origin: Vec2::new(px as f32, py as f32),
            span: Vec2::ONE,
            stratified: None,
        }
    }
}

/// The values of one sample, drawn dimension after dimension (see the module docs).
#[derive(Clone, Debug)]
pub struct SampleStream {
    kind: SamplerKind,
    /// Key of this sample's pixel and block (LD), run (sobol) or sample (random).
    key: u64,
    index: u64,
    log2_n: u32,
    dim: u32,
    px: i32,
    py: i32,
    /// A chain's primary sample values (metropolis, erpt), grown as dimensions are drawn.
    values: Vec<f32>,
    /// Raster position and size of the film area dimensions 0 and 1 span.
    origin: Vec2,
    span: Vec2,
    /// An erpt seed's point of a stratified sequence: the dimensions its values do not hold
    /// yet are drawn from it instead of at random (`basesampler`).
    stratified: Option<erpt::SeedPoint>,
}

/// Most dimensions a primary sample vector grows to (beyond it values are drawn afresh and
/// not kept, which is still a valid, if less correlated, proposal).
const MAX_PRIMARY_DIMS: u32 = 4096;

impl SampleStream {
    /// Dimension `d` of a metropolis stream: the chain's value, or a fresh one appended.
    fn primary(&mut self, d: u32) -> f32 {
        if let Some(v) = self.values.get(d as usize) {
            return *v;
        }
        if d >= MAX_PRIMARY_DIMS {
            return random::value(self.key, d);
        }
        for i in self.values.len() as u32..=d {
            self.values.push(random::value(self.key, i));
        }
        self.values.get(d as usize).copied().unwrap_or(0.0)
    }

    /// This primary stream with the dimensions its values do not hold yet drawn from the
    /// stratified seed point `p` (an erpt seed under a stratified `basesampler`).
    pub fn with_stratified_fresh(mut self, p: erpt::SeedPoint) -> SampleStream {
        self.stratified = Some(p);
        self
    }

    /// Dimension `d` of a primary stream drawn by one 1D request: from the stratified point
    /// when it is the next value to append, else [`SampleStream::primary`].
    fn primary_1d(&mut self, d: u32) -> f32 {
        match self.stratified {
            Some(p) if self.values.len() == d as usize && d < MAX_PRIMARY_DIMS => {
                let v = sobol::value_1d(p.run_key, p.index, d);
                self.values.push(v);
                v
            }
            _ => self.primary(d),
        }
    }

    /// Dimensions `d`, `d + 1` of a primary stream drawn by one 2D request: jointly
    /// stratified from the stratified point when both are to be appended (dimensions
    /// skipped before them are drawn at random), else [`SampleStream::primary`].
    fn primary_2d(&mut self, d: u32) -> Vec2 {
        match self.stratified {
            Some(p) if self.values.len() <= d as usize && d < MAX_PRIMARY_DIMS - 1 => {
                if d > 0 {
                    self.primary(d - 1);
                }
                let v = sobol::value_2d(p.run_key, p.index, d);
                self.values.extend([v.x, v.y]);
                v
            }
            _ => Vec2::new(self.primary(d), self.primary(d.saturating_add(1))),
        }
    }

    /// The primary sample values this stream drew (metropolis, erpt).
    pub fn into_values(self) -> Vec<f32> {
        self.values
    }

    /// The next dimension, in [0, 1).
    pub fn next_1d(&mut self) -> f32 {
        let d = self.dim;
        self.dim = self.dim.saturating_add(1);
        match self.kind {
            SamplerKind::Metropolis | SamplerKind::Erpt => self.primary_1d(d),
            SamplerKind::Random => random::value(self.key, d),
            SamplerKind::LowDiscrepancy => {
                lowdiscrepancy::value_1d(self.key, self.index, self.log2_n, d)
            }
            SamplerKind::Sobol => sobol::value_1d(self.key, self.index, d),
        }
    }

    /// The next two dimensions, each in [0, 1).
    pub fn next_2d(&mut self) -> Vec2 {
        let d = self.dim;
        self.dim = self.dim.saturating_add(2);
        match self.kind {
            SamplerKind::Metropolis | SamplerKind::Erpt => self.primary_2d(d),
            SamplerKind::Random => {
                Vec2::new(random::value(self.key, d), random::value(self.key, d + 1))
            }
            SamplerKind::LowDiscrepancy => {
                lowdiscrepancy::value_2d(self.key, self.index, self.log2_n, d)
            }
            SamplerKind::Sobol => sobol::value_2d(self.key, self.index, d),
        }
    }

    /// Dimensions drawn so far.
    pub fn dimension(&self) -> u32 {
        self.dim
    }

    /// Jumps to dimension `dim` (for a fixed per-bounce layout, e.g. `5 + bounce * K`, so
    /// that a branch drawing fewer values does not shift the later ones).
    pub fn set_dimension(&mut self, dim: u32) {
        self.dim = dim;
    }

    /// The pixel this stream samples.
    pub fn pixel(&self) -> (i32, i32) {
        (self.px, self.py)
    }

    /// Draws dims 0..5 (film 2D, lens 2D, time) and returns the camera sample with `p_film`
    /// in full-image raster coordinates. Call it first.
    pub fn camera_sample(&mut self) -> CameraSample {
        let u = self.next_2d();
        let p_lens = self.next_2d();
        let time = self.next_1d();
        CameraSample {
            p_film: self.origin + u * self.span,
            p_lens,
            time,
        }
    }
}

#[cfg(test)]
mod tests;
