//! The `erpt` sampler: energy redistribution path tracing (Cline, Talbot & Egbert 2005) over
//! the primary sample space, as LuxRender 1.x offers it.
//!
//! ```text
//! seed (a uniform sample, energy e) --chain_plan(e, ed, ξ)--> n chains, quantum q
//!   each chain: chainlength × { small_mutation --trace--> judge } --deposits of q--> film
//! ```
//!
//! Every *seed* is an ordinary uniform sample of the primary sample space; its energy `e` is
//! the luminance of what it brings to the film. It starts `n = ⌊e / (chainlength · ed) + ξ⌋`
//! Markov chains (ξ uniform), where the energy quantum `ed` is the mean seed energy per
//! mutation, estimated once from `initsamples` warm-up samples. Each chain takes
//! `chainlength` small mutations ([`super::metropolis::small_mutation`], the film move at
//! most `mutationrange` pixels), accepted by the luminance ratio, and deposits `ed` per step
//! ("equal deposition"): spread over the current and the proposed sample by the acceptance
//! probability (the expected-values estimator LuxRender's ERPT uses), each scaled to the
//! quantum by its own luminance. The expected deposit of a seed is its energy `e` (E[n] ·
//! chainlength · ed = e), and since the chains start in proportion to the image and keep it
//! (symmetric proposals, Metropolis acceptance), the deposits are unbiased per screen: the
//! film's eye buffer is normalised by the number of seeds, like metropolis'.
//!
//! A seed far brighter than the quantum would start many chains; [`MAX_CHAINS`] bounds them,
//! the quantum of such a seed then being `e / (MAX_CHAINS · chainlength)` (its expected
//! deposit is still `e`). A warm-up that saw no light leaves `ed` unknown: every seed with
//! energy then starts one chain of quantum `e / chainlength`.
//!
//! Parameters (LuxRender's names; defaults from its scene-format documentation):
//! `initsamples` (100000 warm-up samples), `chainlength` (2000 mutations per chain),
//! `mutationrange` ((width + height) / 50 pixels), `basesampler` (the seeds' sampler, see
//! below; default "random"), `pixelsamples` (4: a pass takes about extent pixels ×
//! pixelsamples traces, see `crate::render::erpt`).
//!
//! # Stratified seeds (`basesampler`)
//!
//! LuxRender 1.x draws ERPT's seeds with the sampler `basesampler` names ("random" or
//! "lowdiscrepancy" in its exporters). Here a seed is a point of the whole sampled frame
//! rather than of one pixel, and a pass takes a few hundred seeds, so a stratified base must
//! be progressive over the frame: with "lowdiscrepancy" or "sobol", seed `i` of a session is
//! point `i` of the padded, Owen-scrambled (0,2)-sequence the sobol sampler uses
//! ([`SeedPoint`]; every 1D and 2D request of a seed draws its own scrambled, shuffled
//! copy). Any power-of-two run of seeds is then stratified over the frame and in every 2D
//! request, and each seed is still uniform on its own, so the estimate stays unbiased and
//! sessions on different streams (different scrambles) stay independent. A chain's mutations
//! draw fresh dimensions at random, as with a random base. LuxRender's older stratified
//! samplers ("stratified", "halton", "bestcandidate") use the same sequence, with a warning.

use super::hash::{combine, mix64, unit_f32};
use super::metropolis::small_mutation;
use super::{pixel_samples, SamplerKind};
use crate::plugin::{BuildError, Stmt};

/// LuxRender's default number of warm-up samples.
pub const DEFAULT_INIT_SAMPLES: u32 = 100_000;
/// LuxRender's default chain length (mutations per chain).
pub const DEFAULT_CHAIN_LENGTH: u32 = 2000;
/// Most chains one seed starts (LuxRender caps them at 100 too).
pub const MAX_CHAINS: u32 = 100;

/// How seeds are drawn (`basesampler`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum BaseSampler {
    /// Independent uniform seeds.
    #[default]
    Random,
    /// Seeds from a stratified sequence over the frame ([`SeedPoint`]).
    Stratified,
}

/// A seed's point of the stratified sequence: the sobol sampler's run key and index.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SeedPoint {
    pub(super) run_key: u64,
    pub(super) index: u64,
}

impl SeedPoint {
    /// The ξ of the seed's chain count, stratified over the seeds like their dimensions
    /// (a request of its own, past every dimension a stream draws).
    pub fn chain_xi(&self) -> f32 {
        super::sobol::value_1d(self.run_key, self.index, u32::MAX)
    }
}

/// The stratified point of seed `index` (counted over the session's passes) of (seed,
/// stream): a sequence of its own per session.
pub fn seed_point(seed: u64, stream: u64, index: u64) -> SeedPoint {
    let sequence = combine(session_key(seed, stream), 0x6261_7365);
    SeedPoint {
        run_key: super::sobol::run_key(sequence, index),
        index,
    }
}

/// The ERPT parameters of a sampler statement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErptParams {
    /// Warm-up samples estimating the energy quantum.
    pub init_samples: u32,
    /// Mutations per chain (at least 1).
    pub chain_length: u32,
    /// Largest film move of a mutation in pixels; `None`: (width + height) / 50.
    pub range: Option<f32>,
    /// How seeds are drawn.
    pub base: BaseSampler,
}

impl Default for ErptParams {
    fn default() -> ErptParams {
        ErptParams {
            init_samples: DEFAULT_INIT_SAMPLES,
            chain_length: DEFAULT_CHAIN_LENGTH,
            range: None,
            base: BaseSampler::Random,
        }
    }
}

impl ErptParams {
    /// The mutations' film range in pixels for a sampled area of `w` × `h` pixels.
    pub fn range_pixels(&self, w: f32, h: f32) -> f32 {
        self.range.unwrap_or((w + h) / 50.0).max(0.0)
    }
}

/// Reads an `erpt` statement.
pub(super) fn build(s: &mut Stmt) -> Result<(SamplerKind, u32, ErptParams), BuildError> {
    let n = pixel_samples(s)?;
    let p = s.params();
    let init = p.int_or("initsamples", DEFAULT_INIT_SAMPLES as i32);
    let init_samples = u32::try_from(init)
        .ok()
        .filter(|&v| v >= 1)
        .ok_or_else(|| {
            s.err(format!(
                "sampler \"erpt\": initsamples must be at least 1, got {init}"
            ))
        })?;
    let len = p.int_or("chainlength", DEFAULT_CHAIN_LENGTH as i32);
    let chain_length = u32::try_from(len).ok().filter(|&v| v >= 1).ok_or_else(|| {
        s.err(format!(
            "sampler \"erpt\": chainlength must be at least 1, got {len}"
        ))
    })?;
    let range = p.float("mutationrange");
    if let Some(r) = range {
        if !(r > 0.0 && r.is_finite()) {
            return Err(s.err(format!(
                "sampler \"erpt\": mutationrange must be a positive number of pixels, got {r}"
            )));
        }
    }
    let base = base_sampler(s)?;
    Ok((
        SamplerKind::Erpt,
        n,
        ErptParams {
            init_samples,
            chain_length,
            range,
            base,
        },
    ))
}

/// Reads `basesampler`: random (the default), the stratified samplers, or an error for the
/// Markov chain samplers, which cannot draw independent seeds.
fn base_sampler(s: &mut Stmt) -> Result<BaseSampler, BuildError> {
    let Some(name) = s.params().string("basesampler") else {
        return Ok(BaseSampler::Random);
    };
    match name {
        "random" => Ok(BaseSampler::Random),
        "lowdiscrepancy" | "sobol" => Ok(BaseSampler::Stratified),
        "stratified" | "halton" | "bestcandidate" => {
            s.warn(format!(
                "sampler \"erpt\": basesampler \"{name}\" is not implemented; seeds are drawn \
                 by the stratified sequence of \"lowdiscrepancy\" and \"sobol\" (unbiased)"
            ));
            Ok(BaseSampler::Stratified)
        }
        other => Err(s.err(format!(
            "sampler \"erpt\": basesampler must be random, lowdiscrepancy or sobol (or \
             stratified, halton, bestcandidate), got \"{other}\""
        ))),
    }
}

/// The key of a session's ERPT randomness: (seed, stream) of the session.
fn session_key(seed: u64, stream: u64) -> u64 {
    combine(mix64(seed ^ 0x6572_7074_5f73_6431), stream)
}

/// The key of seed `index` (counted over the session's passes) of (seed, stream).
pub fn seed_key(seed: u64, stream: u64, index: u64) -> u64 {
    combine(combine(session_key(seed, stream), 0x7365_6564), index)
}

/// The key of warm-up sample `index` under `seed` (independent of every seed and chain). It
/// does not depend on the stream: every session of a scene and seed (every farm lease of a
/// job) estimates the same quantum, so one computed before can stand in for the warm-up.
pub fn warm_up_key(seed: u64, index: u64) -> u64 {
    combine(mix64(seed ^ 0x6572_7074_5f77_7570), index)
}

/// The key of chain `j` of the seed keyed `seed_key`.
pub fn chain_key(seed_key: u64, j: u32) -> u64 {
    combine(combine(seed_key, 0x6368_6169), u64::from(j))
}

/// The ξ of a seed's chain count.
pub fn seed_xi(seed_key: u64) -> f32 {
    unit_f32(mix64(combine(seed_key, 0x7869)))
}

/// How a seed of energy `e` redistributes it: the number of chains and the energy each of
/// their steps deposits, for the quantum `ed` (mean energy per mutation; not positive:
/// unknown), `chain_length` steps per chain and a uniform `xi`. The expected total deposit
/// (chains × chain_length × quantum) is `e` for every `e` ≥ 0.
pub fn chain_plan(e: f64, ed: f64, chain_length: u32, xi: f32) -> (u32, f64) {
    let m = f64::from(chain_length.max(1));
    if !(e > 0.0 && e.is_finite()) {
        return (0, 0.0);
    }
    if !(ed > 0.0 && ed.is_finite()) {
        return (1, e / m);
    }
    let a = e / (m * ed);
    if a > f64::from(MAX_CHAINS) {
        return (MAX_CHAINS, e / (f64::from(MAX_CHAINS) * m));
    }
    // a ≤ MAX_CHAINS and ξ < 1: n ≤ MAX_CHAINS.
    let n = (a + f64::from(xi.clamp(0.0, 1.0))).floor();
    (n.clamp(0.0, f64::from(MAX_CHAINS)) as u32, ed)
}

/// What the session adds to the film after one step: the recorded contributions of the
/// sample the chain leaves (on acceptance) with `current_weight`, or of the rejected
/// proposal with `proposal_weight`; weights are per unit of contribution (the quantum over
/// the sample's luminance, times its share of the step). Zero adds nothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Deposit {
    pub current_weight: f64,
    pub proposal_weight: f64,
    pub accepted: bool,
}

/// One ERPT chain: a Markov chain of small mutations from a seed, depositing a fixed quantum
/// per step.
#[derive(Clone, Debug)]
pub struct ErptChain {
    key: u64,
    step: u64,
    current: Vec<f32>,
    current_lum: f32,
    quantum: f64,
    /// Steps' shares the current sample has gathered and not yet deposited.
    weight: f64,
    pub accepted: u64,
    pub proposed: u64,
}

impl ErptChain {
    /// A chain keyed `key` starting at the seed whose values are `values` and luminance
    /// `lum`, depositing `quantum` per step.
    pub fn new(key: u64, values: Vec<f32>, lum: f32, quantum: f64) -> ErptChain {
        ErptChain {
            key,
            step: 0,
            current: values,
            current_lum: if lum.is_finite() && lum > 0.0 {
                lum
            } else {
                0.0
            },
            quantum,
            weight: 0.0,
            accepted: 0,
            proposed: 0,
        }
    }

    /// The key of this step's fresh values (dimensions beyond the current vector).
    pub fn step_key(&self) -> u64 {
        combine(self.key, self.step)
    }

    /// Steps taken so far.
    pub fn steps(&self) -> u64 {
        self.step
    }

    /// The proposal of this step: the current values mutated (film position by at most
    /// `range_xy`, fractions of the sampled extent per axis).
    pub fn propose(&self, range_xy: [f32; 2], out: &mut Vec<f32>) {
        small_mutation(&self.current, self.step_key(), range_xy, out);
    }

    /// Accepts or rejects the proposal whose values are `values` and luminance `lum`; on
    /// acceptance `values` is swapped into the chain (the caller's vector then holds the old
    /// current values).
    pub fn judge(&mut self, values: &mut Vec<f32>, lum: f32) -> Deposit {
        let lum = if lum.is_finite() && lum > 0.0 {
            lum
        } else {
            0.0
        };
        let acc = if self.current_lum > 0.0 {
            f64::from((lum / self.current_lum).min(1.0))
        } else {
            1.0
        };
        self.weight += 1.0 - acc;
        self.proposed += 1;
        let u = unit_f32(mix64(combine(self.step_key(), 0x6163_6370)));
        let take = acc >= 1.0 || f64::from(u) < acc;
        let dep = if take {
            let cw = self.per_unit(self.weight, self.current_lum);
            self.weight = acc;
            self.current_lum = lum;
            std::mem::swap(&mut self.current, values);
            self.accepted += 1;
            Deposit {
                current_weight: cw,
                proposal_weight: 0.0,
                accepted: true,
            }
        } else {
            Deposit {
                current_weight: 0.0,
                proposal_weight: self.per_unit(acc, lum),
                accepted: false,
            }
        };
        self.step += 1;
        dep
    }

    /// Takes the weight the current sample has gathered and not yet deposited (at the end
    /// of the chain).
    pub fn flush(&mut self) -> f64 {
        let w = self.per_unit(self.weight, self.current_lum);
        self.weight = 0.0;
        w
    }

    /// `share` steps' quanta per unit of a sample of luminance `lum`.
    fn per_unit(&self, share: f64, lum: f32) -> f64 {
        let w = share * self.quantum / f64::from(lum);
        if w.is_finite() && w > 0.0 {
            w
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every plan deposits the seed's energy on average over ξ, whatever the quantum (and
    /// exactly for capped and unknown quanta).
    #[test]
    fn plans_deposit_the_seed_energy_on_average() {
        let m = 50;
        for (e, ed) in [
            (0.3, 0.01),
            (1.0, 0.02),
            (2.7, 0.02),
            (5.0, 1e-5),
            (4.0, 0.0),
            (0.0, 0.1),
        ] {
            let k = 10_000;
            let mut total = 0.0;
            for i in 0..k {
                let xi = (i as f32 + 0.5) / k as f32;
                let (n, q) = chain_plan(e, ed, m, xi);
                assert!(n <= MAX_CHAINS);
                total += f64::from(n) * f64::from(m) * q;
            }
            let mean = total / f64::from(k);
            assert!(
                (mean - e).abs() <= 1e-3 * e.max(1e-9),
                "e {e} ed {ed}: {mean}"
            );
        }
        assert_eq!(chain_plan(1.0, 1e-6, 10, 0.5).0, MAX_CHAINS);
        assert_eq!(chain_plan(f64::NAN, 1.0, 10, 0.5), (0, 0.0));
        // A seed of the mean energy starts one chain on average, a dim one fewer.
        assert_eq!(chain_plan(0.5, 0.5 / 20.0, 20, 0.99).0, 1);
        assert_eq!(chain_plan(0.1, 0.5 / 20.0, 20, 0.5).0, 0);
    }

    /// ERPT on a 1D target: seeds uniform on [0, 1), chains of small mutations; the deposits
    /// per seed estimate the integral and follow the target (f = 2x: 1, 3/4 of it above 0.5;
    /// f = 1 + x: 1.5, 0.875 above 0.5). A wrong quantum or chain count fails the integral.
    #[test]
    fn seeds_and_chains_estimate_integrals() {
        type F = Box<dyn Fn(f32) -> f32>;
        let cases: [(F, f64, f64); 2] = [
            (Box::new(|x| 2.0 * x), 1.0, 0.75),
            (Box::new(|x| 1.0 + x), 1.5, 0.875),
        ];
        for (f, integral, upper_part) in cases {
            let m = 16u32;
            let seeds = 20_000u64;
            // The quantum from a warm-up of its own.
            let warm = 4000;
            let mean = (0..warm)
                .map(|i| f64::from(f(unit_f32(mix64(combine(99, i))))))
                .sum::<f64>()
                / warm as f64;
            let ed = mean / f64::from(m);
            let (mut total, mut upper) = (0.0f64, 0.0f64);
            let (mut acc, mut prop) = (0u64, 0u64);
            let mut v = Vec::new();
            for s in 0..seeds {
                let key = combine(7, s);
                let x0 = unit_f32(mix64(key));
                let e = f(x0);
                let (n, q) = chain_plan(f64::from(e), ed, m, unit_f32(mix64(key ^ 1)));
                for j in 0..n {
                    let mut c = ErptChain::new(combine(key, u64::from(j)), vec![x0], e, q);
                    let mut cur = x0;
                    for _ in 0..m {
                        c.propose([0.1, 0.1], &mut v);
                        let x = v[0];
                        let d = c.judge(&mut v, f(x));
                        let dc = d.current_weight * f64::from(f(cur));
                        let dp = d.proposal_weight * f64::from(f(x));
                        total += dc + dp;
                        upper += if cur > 0.5 { dc } else { 0.0 };
                        upper += if x > 0.5 { dp } else { 0.0 };
                        if d.accepted {
                            cur = x;
                        }
                    }
                    let w = c.flush() * f64::from(f(cur));
                    total += w;
                    upper += if cur > 0.5 { w } else { 0.0 };
                    acc += c.accepted;
                    prop += c.proposed;
                }
            }
            let est = total / seeds as f64;
            assert!(
                (est - integral).abs() < 0.03 * integral,
                "{est} vs {integral}"
            );
            let share = upper / total;
            assert!(
                (share - upper_part / integral).abs() < 0.03,
                "{share} vs {}",
                upper_part / integral
            );
            let rate = acc as f64 / prop as f64;
            assert!(rate > 0.3 && rate < 1.0, "acceptance {rate}");
        }
    }

    #[test]
    fn rejected_zero_proposals_deposit_nothing() {
        let mut c = ErptChain::new(1, vec![0.5, 0.5], 2.0, 0.5);
        let mut v = vec![0.1, 0.1];
        let d = c.judge(&mut v, 0.0);
        assert!(!d.accepted);
        assert_eq!(d.proposal_weight, 0.0);
        // The rejected step's share stays with the current sample: 0.5 / 2 per unit.
        assert!((c.flush() - 0.25).abs() < 1e-12);
    }
}
