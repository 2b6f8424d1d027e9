//! The `metropolis` sampler: Kelemen-style Metropolis light transport over the primary sample
//! space, as LuxRender 1.x runs it.
//!
//! A [`Chain`] holds the current point of the unit hypercube (the values an integrator drew
//! for its last accepted sample) and proposes the next one: a *large* mutation (probability
//! `largemutationprob`) draws every value afresh; a *small* one moves each value a little
//! (dimensions 0 and 1, the film position, by at most `mutationrange` pixels). The render
//! session traces the proposal through a [`super::SampleStream`] over the proposed values
//! ([`super::Sampler::start_primary`]), measures its luminance and calls [`Chain::judge`],
//! which accepts or rejects it (forcing acceptance after `maxconsecrejects` rejections) and
//! says how much of which sample goes to the film: the "expected values" estimator, both
//! the proposal and the current sample weighted by the acceptance probability, each divided
//! by its luminance over the large-step mean plus `largemutationprob` (the large steps are
//! uniform samples combined by the balance heuristic). Contributions land in the film's
//! per-screen buffers, normalised by the number of steps taken.
//!
//! Everything is a pure function of the chain's key (seed, stream, chain index) and step
//! number, so farm workers on different streams run independent chains.
//!
//! Parameters (LuxRender's names and defaults): `largemutationprob` (0.4), `maxconsecrejects`
//! (512), `mutationrange` ((width + height) / 32 pixels), `usevariance` (false: the target is
//! the luminance; true: luminance weighted by the integrator's MIS weights),
//! `usecooldown` (false: true makes large mutations 50 % likely until the chains have taken
//! as many large steps as the film has pixels), `pixelsamples` (4: mutations per pixel per
//! pass).

use super::hash::{combine, mix64, unit_f32};
use super::{pixel_samples, SamplerKind};
use crate::plugin::{BuildError, Stmt};

/// The Metropolis parameters of a sampler statement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MltParams {
    pub large_prob: f32,
    pub max_rejects: u32,
    /// Largest film move of a small mutation in pixels; `None`: (width + height) / 32.
    pub range: Option<f32>,
    pub use_variance: bool,
    pub cooldown: bool,
}

impl Default for MltParams {
    fn default() -> MltParams {
        MltParams {
            large_prob: 0.4,
            max_rejects: 512,
            range: None,
            use_variance: false,
            cooldown: false,
        }
    }
}

impl MltParams {
    /// The small mutations' film range in pixels for a sampled area of `w` × `h` pixels.
    pub fn range_pixels(&self, w: f32, h: f32) -> f32 {
        self.range.unwrap_or((w + h) / 32.0).max(0.0)
    }
}

/// Reads a `metropolis` statement.
pub(super) fn build(s: &mut Stmt) -> Result<(SamplerKind, u32, MltParams), BuildError> {
    let n = pixel_samples(s)?;
    let p = s.params();
    let large_prob = p.float_or("largemutationprob", 0.4);
    if !(0.0..=1.0).contains(&large_prob) {
        return Err(s.err(format!(
            "sampler \"metropolis\": largemutationprob must be in [0, 1], got {large_prob}"
        )));
    }
    let max_rejects = p.int_or("maxconsecrejects", 512);
    let max_rejects = u32::try_from(max_rejects).map_err(|_| {
        s.err(format!(
            "sampler \"metropolis\": maxconsecrejects must be >= 0, got {max_rejects}"
        ))
    })?;
    let range = p.float("mutationrange");
    if let Some(r) = range {
        if !(r > 0.0 && r.is_finite()) {
            return Err(s.err(format!(
                "sampler \"metropolis\": mutationrange must be a positive number of pixels, got {r}"
            )));
        }
    }
    let use_variance = p.bool_or("usevariance", false);
    let cooldown = p.bool_or("usecooldown", false);
    // LuxRender 1.x's other Metropolis parameters, accepted without effect.
    let _ = p.int("initsamples");
    let _ = p.float("micromutationprob");
    Ok((
        SamplerKind::Metropolis,
        n,
        MltParams {
            large_prob,
            max_rejects,
            range,
            use_variance,
            cooldown,
        },
    ))
}

/// Moves `x` by `dx` (up if `u` < 0.5, else down), wrapping around [0, 1).
fn wrap_move(x: f32, u: f32, dx: f32) -> f32 {
    let y = if u < 0.5 { x + dx } else { x - dx };
    let y = y - y.floor();
    if (0.0..1.0).contains(&y) {
        y
    } else {
        0.0
    }
}

/// A small mutation of an ordinary primary value (Kelemen's, LuxRender's constants
/// s1 = 1/512, s2 = 1/16): most steps near 0, none longer than s2.
pub fn mutate(x: f32, u: f32) -> f32 {
    const S1: f32 = 1.0 / 512.0;
    const S2: f32 = 1.0 / 16.0;
    let t = (2.0 * u - 1.0).abs();
    wrap_move(x, u, S1 / (S1 / S2 + t) - S1 / (S1 / S2 + 1.0))
}

/// A small mutation of a film coordinate: steps of at most `range` (a fraction of the
/// sampled extent), shaped as LuxRender's image mutation (s = 32).
pub fn mutate_scaled(x: f32, u: f32, range: f32) -> f32 {
    const S: f32 = 32.0;
    let r = range.clamp(0.0, 1.0);
    let t = (2.0 * u - 1.0).abs();
    let dx = r / (S / (1.0 + S) + S * S / (1.0 + S) * t) - r / S;
    wrap_move(x, u, dx.max(0.0))
}

/// A small mutation of a whole primary sample vector into `out` (cleared first): every value
/// of `current` moved by [`mutate`], the first two (film position) by [`mutate_scaled`] with
/// `range_xy` (fractions of the sampled extent per axis); the moves are a pure function of
/// `key`. The proposal is symmetric, so a Metropolis acceptance by the target's ratio keeps
/// the target's distribution. Shared by metropolis' small steps and ERPT's mutations.
pub fn small_mutation(current: &[f32], key: u64, range_xy: [f32; 2], out: &mut Vec<f32>) {
    out.clear();
    let k = combine(key, 0x6d75_7461);
    out.extend(current.iter().enumerate().map(|(i, &x)| {
        let u = unit_f32(mix64(
            k ^ (i as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15),
        ));
        match i {
            0 | 1 => mutate_scaled(x, u, range_xy[i]),
            _ => mutate(x, u),
        }
    }));
}

/// What the session must add to the film after one step: the recorded contributions of the
/// previous current sample with `current_weight` (before the chain moved on), and those of
/// the proposal with `proposal_weight`. A zero weight adds nothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Deposit {
    pub current_weight: f32,
    pub proposal_weight: f32,
    pub accepted: bool,
}

/// One Markov chain over the primary sample space.
#[derive(Clone, Debug)]
pub struct Chain {
    key: u64,
    step: u64,
    current: Vec<f32>,
    current_lum: f32,
    /// The sampling map's density at the current sample's film position (1 without a map).
    current_q: f32,
    /// Weight accumulated by the current sample and not yet deposited.
    weight: f32,
    consec_rejects: u32,
    /// Whether the next proposal is a large mutation.
    large: bool,
    pub accepted: u64,
    pub proposed: u64,
}

impl Chain {
    /// Chain `index` of (seed, stream); its first proposal is a large mutation.
    pub fn new(seed: u64, stream: u64, index: u64) -> Chain {
        let key = combine(combine(mix64(seed ^ 0x6d6c_745f_6368_6e31), stream), index);
        Chain {
            key,
            step: 0,
            current: Vec::new(),
            current_lum: 0.0,
            current_q: 1.0,
            weight: 0.0,
            consec_rejects: 0,
            large: true,
            accepted: 0,
            proposed: 0,
        }
    }

    /// Whether the proposal of this step is a large mutation.
    pub fn is_large(&self) -> bool {
        self.large
    }

    /// The key of this step's fresh values (those a proposal draws beyond its vector).
    pub fn step_key(&self) -> u64 {
        combine(self.key, self.step)
    }

    /// The key of uniform sample `i` drawn to estimate the normaliser (independent of the
    /// chain's steps).
    pub fn bootstrap_key(&self, i: u64) -> u64 {
        combine(combine(self.key, 0x626f_6f74), i)
    }

    /// Which of the start-up samples whose targets are `lums` the chain starts from: one
    /// drawn in proportion to its target (importance resampling), so the chain starts close
    /// to its stationary distribution instead of at a uniform point. `None` when every target
    /// is zero (the chain then starts with a large mutation).
    pub fn pick_start(&self, lums: &[f32]) -> Option<usize> {
        let usable = |l: f32| {
            if l.is_finite() && l > 0.0 {
                f64::from(l)
            } else {
                0.0
            }
        };
        let total: f64 = lums.iter().map(|&l| usable(l)).sum();
        if total <= 0.0 {
            return None;
        }
        let u = f64::from(unit_f32(mix64(combine(self.key, 0x7374_6172)))) * total;
        let mut acc = 0.0;
        let mut last = None;
        for (i, &l) in lums.iter().enumerate() {
            let w = usable(l);
            if w > 0.0 {
                acc += w;
                last = Some(i);
                if u < acc {
                    return Some(i);
                }
            }
        }
        last
    }

    /// Starts the chain at `values` (a start-up sample's values, luminance `lum`, map density
    /// `q` at its film position) with nothing gathered yet; its first proposal is large with
    /// probability `p_large`.
    pub fn start_at(&mut self, values: Vec<f32>, lum: f32, q: f32, p_large: f32) {
        self.current = values;
        self.current_lum = positive_or_zero(lum);
        self.current_q = positive_or_zero(q);
        self.weight = 0.0;
        // Salt 4: step 0's salts 1 and 2 decide its acceptance and the next step's kind.
        self.large = self.rand(4) < p_large;
    }

    fn rand(&self, salt: u64) -> f32 {
        unit_f32(mix64(combine(self.step_key(), salt)))
    }

    /// The proposed values of this step: empty for a large mutation (every value drawn
    /// afresh from [`Chain::step_key`]); else the current values mutated, the first two (film
    /// position) by at most `range_xy` (fractions of the sampled extent per axis).
    pub fn propose(&self, range_xy: [f32; 2], out: &mut Vec<f32>) {
        out.clear();
        if self.large {
            return;
        }
        small_mutation(&self.current, self.step_key(), range_xy, out);
    }

    /// Restarts the chain with no current sample: its next proposal is a large mutation and
    /// is accepted (a chain whose start-up samples were all black).
    pub fn restart(&mut self) {
        self.current.clear();
        self.current_lum = 0.0;
        self.current_q = 1.0;
        self.weight = 0.0;
        self.large = true;
    }

    /// Accepts or rejects the proposal whose values are `values`, whose luminance is `lum` and
    /// whose film position has map density `q` (1 without a map), given the large steps'
    /// mean luminance `mean` and the large mutation probability `p_large` in force; prepares
    /// the next step. On acceptance `values` is swapped into the chain (the caller's vector
    /// then holds the old current values).
    ///
    /// The chain's target is `lum × q`. A small mutation is symmetric: it is accepted with
    /// the ratio of targets. A large one draws its film position with density `q`: it is
    /// accepted with the ratio of targets over the ratio of proposal densities, that is of
    /// luminances. Without a map both are LuxRender's rule.
    pub fn judge(
        &mut self,
        values: &mut Vec<f32>,
        lum: f32,
        q: f32,
        mean: f64,
        p_large: f32,
        max_rejects: u32,
    ) -> Deposit {
        let lum = positive_or_zero(lum);
        let q = positive_or_zero(q);
        let inv_mean = if mean > 0.0 { (1.0 / mean) as f32 } else { 1.0 };
        let cur = self.current_lum * self.current_q;
        let acc = if cur > 0.0 && self.consec_rejects < max_rejects {
            if self.large {
                (lum / self.current_lum).min(1.0)
            } else {
                (lum * q / cur).min(1.0)
            }
        } else {
            1.0
        };
        let new_weight = acc + if self.large { 1.0 } else { 0.0 };
        self.weight += 1.0 - acc;
        self.proposed += 1;
        let take = acc >= 1.0 || self.rand(1) < acc;
        let dep = if take {
            let cw = self.weight / (self.current_q * (self.current_lum * inv_mean + p_large));
            self.weight = new_weight;
            self.current_lum = lum;
            self.current_q = q;
            std::mem::swap(&mut self.current, values);
            self.consec_rejects = 0;
            self.accepted += 1;
            Deposit {
                current_weight: finite_or_zero(cw),
                proposal_weight: 0.0,
                accepted: true,
            }
        } else {
            self.consec_rejects = self.consec_rejects.saturating_add(1);
            Deposit {
                current_weight: 0.0,
                proposal_weight: finite_or_zero(new_weight / (q * (lum * inv_mean + p_large))),
                accepted: false,
            }
        };
        self.large = self.rand(2) < p_large;
        self.step += 1;
        dep
    }

    /// Takes the weight the current sample has gathered and not yet deposited (to add it to
    /// the film at the end of a pass); the chain goes on from zero.
    pub fn flush(&mut self, mean: f64, p_large: f32) -> f32 {
        let inv_mean = if mean > 0.0 { (1.0 / mean) as f32 } else { 1.0 };
        let w = self.weight / (self.current_q * (self.current_lum * inv_mean + p_large));
        self.weight = 0.0;
        finite_or_zero(w)
    }
}

fn positive_or_zero(v: f32) -> f32 {
    if v.is_finite() && v > 0.0 {
        v
    } else {
        0.0
    }
}

fn finite_or_zero(w: f32) -> f32 {
    if w.is_finite() && w > 0.0 {
        w
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chains_start_at_samples_in_proportion_to_their_target() {
        let lums = [0.0, 1.0, f32::NAN, 3.0, -2.0];
        let mut counts = [0u32; 5];
        for i in 0..20_000 {
            let j = Chain::new(1, 2, i)
                .pick_start(&lums)
                .expect("a usable target");
            counts[j] += 1;
        }
        assert_eq!((counts[0], counts[2], counts[4]), (0, 0, 0), "{counts:?}");
        let share = f64::from(counts[3]) / 20_000.0;
        assert!((share - 0.75).abs() < 0.015, "{counts:?}");
        assert_eq!(Chain::new(1, 2, 0).pick_start(&[0.0, f32::INFINITY]), None);
    }

    #[test]
    fn a_started_chain_mutates_its_start_and_deposits_nothing_for_it() {
        let mut c = Chain::new(5, 0, 0);
        c.start_at(vec![0.25, 0.5, 0.75], 2.0, 1.0, 0.0);
        assert!(!c.is_large());
        let mut v = Vec::new();
        c.propose([0.01, 0.01], &mut v);
        assert_eq!(v.len(), 3);
        let d = c.judge(&mut v, 2.0, 1.0, 1.0, 0.0, 512);
        assert!(d.accepted);
        assert_eq!(
            d.current_weight, 0.0,
            "the start carries no weight of its own"
        );
    }

    #[test]
    fn mutations_stay_in_the_unit_interval_and_are_small() {
        for i in 0..10_000u32 {
            let x = (i as f32 * 0.618_034).fract();
            let u = (i as f32 * 0.754_877_7).fract();
            let y = mutate(x, u);
            assert!((0.0..1.0).contains(&y), "{x} {u} {y}");
            let d = (y - x).abs().min(1.0 - (y - x).abs());
            assert!(d <= 1.0 / 16.0 + 1e-6, "{x} {u} {y}");
            let z = mutate_scaled(x, u, 0.1);
            let d = (z - x).abs().min(1.0 - (z - x).abs());
            assert!((0.0..1.0).contains(&z) && d <= 0.1 + 1e-6);
        }
    }

    /// The chain samples a 1D target in proportion to its value, and the deposits estimate its
    /// integral: the expected-values estimator on f(x) = 2x (integral 1), 1 + x (1.5).
    #[test]
    fn chain_estimates_integrals_and_follows_the_target() {
        for (f, integral) in [
            (Box::new(|x: f32| 2.0 * x) as Box<dyn Fn(f32) -> f32>, 1.0),
            (Box::new(|x: f32| 1.0 + x), 1.5),
        ] {
            let mut c = Chain::new(3, 0, 0);
            let (mut sum_l, mut n_l) = (0.0f64, 0.0f64);
            let mut total = 0.0f64;
            let mut upper = 0.0f64;
            let mut cur_f = 0.0f32;
            let mut cur_x = 0.0f32;
            let mut v = Vec::new();
            let steps = 200_000;
            for _ in 0..steps {
                c.propose([0.1, 0.1], &mut v);
                if v.is_empty() {
                    v.push(unit_f32(mix64(c.step_key())));
                }
                let x = v[0];
                let fx = f(x);
                let large = c.is_large();
                if large {
                    sum_l += f64::from(fx);
                    n_l += 1.0;
                }
                let d = c.judge(&mut v, fx, 1.0, sum_l / n_l.max(1.0), 0.4, 512);
                total += f64::from(d.current_weight * cur_f) + f64::from(d.proposal_weight * fx);
                if d.current_weight > 0.0 && cur_x > 0.5 {
                    upper += f64::from(d.current_weight * cur_f);
                }
                if d.proposal_weight > 0.0 && x > 0.5 {
                    upper += f64::from(d.proposal_weight * fx);
                }
                if d.accepted {
                    cur_f = fx;
                    cur_x = x;
                }
            }
            let est = total / steps as f64;
            assert!(
                (est - integral).abs() < 0.03 * integral,
                "{est} vs {integral}"
            );
            let rate = c.accepted as f64 / c.proposed as f64;
            assert!(rate > 0.3 && rate < 1.0, "acceptance {rate}");
            // The upper half holds 3/4 of ∫2x and 5/8·... of ∫(1 + x) = 0.875 / 1.5.
            let share = upper / total;
            let want = if integral == 1.0 { 0.75 } else { 0.875 / 1.5 };
            assert!((share - want).abs() < 0.03, "{share} vs {want}");
        }
    }

    /// With a sampling map of density q (1.6 on [0, 0.5), 0.4 above), large steps drawn by q:
    /// the chain spends its time in proportion to f·q, and the deposits still estimate ∫f
    /// (f(x) = 1 + x, integral 1.5; the lower half holds 1.0 / 1.35 of ∫f·q).
    #[test]
    fn chain_with_a_map_follows_it_and_stays_unbiased() {
        let q = |x: f32| if x < 0.5 { 1.6f32 } else { 0.4 };
        // Inverse CDF of q: the lower half takes 0.8 of the mass.
        let warp = |u: f32| {
            if u < 0.8 {
                u / 0.8 * 0.5
            } else {
                0.5 + (u - 0.8) / 0.2 * 0.5
            }
        };
        let f = |x: f32| 1.0 + x;
        let mut c = Chain::new(9, 0, 0);
        let (mut sum_l, mut n_l) = (0.0f64, 0.0f64);
        let (mut total, mut lower_time) = (0.0f64, 0u64);
        let (mut cur_f, mut cur_x) = (0.0f32, 0.0f32);
        let mut v = Vec::new();
        let steps = 400_000u64;
        for _ in 0..steps {
            c.propose([0.1, 0.1], &mut v);
            if v.is_empty() {
                v.push(warp(unit_f32(mix64(c.step_key()))));
            }
            let x = v[0];
            let fx = f(x);
            if c.is_large() {
                sum_l += f64::from(fx);
                n_l += 1.0;
            }
            let d = c.judge(&mut v, fx, q(x), sum_l / n_l.max(1.0), 0.4, 512);
            total += f64::from(d.current_weight * cur_f) + f64::from(d.proposal_weight * fx);
            if d.accepted {
                cur_f = fx;
                cur_x = x;
            }
            lower_time += u64::from(cur_x < 0.5);
        }
        let est = total / steps as f64;
        assert!((est - 1.5).abs() < 0.03 * 1.5, "{est} vs 1.5");
        let share = lower_time as f64 / steps as f64;
        assert!(
            (share - 1.0 / 1.35).abs() < 0.03,
            "time in the lower half {share}"
        );
    }
}
