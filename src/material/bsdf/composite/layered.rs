//! The layered material's BSDF, after LuxRender's `LayeredBSDF`: a stack of BSDFs (layer 0
//! faces the side of the geometric normal) that light crosses and bounces between as if each
//! were its own infinitely thin surface.
//!
//! `f(wo, wi)` is a stochastic estimate, as in LuxRender: a random walk enters the stack from
//! `wo` and another from `wi` (each sampling the layer it reaches and moving up or down with
//! the side of the sampled direction, at most 3 bounces per layer); every pair of vertices on
//! the same layer is connected through that layer's `f`, weighted by the balance heuristic
//! over the ways the same chain of scattering events could have been split between the two
//! walks (specular events cannot be the connection). LuxRender builds that chain's densities
//! with an index shifted by one on the `wi` side; here both sides use the density of the
//! event that produced each vertex.
//!
//! Randomness comes from a seed fixed per hit and hashed with the pair, so `f` is a
//! deterministic function of (wo, wi) within a hit (f, pdf and reverse evaluations agree)
//! and renders are reproducible. Sampling is LuxRender's: with probability 1/2 a chain of
//! specular events through the stack (a delta sample), otherwise a uniformly distributed
//! direction on the reflected or the transmitted side (1/2 each), so the non-specular pdf is
//! `1/(8π)` for every pair.

use super::ONE_MINUS_EPSILON;
use crate::material::bsdf::{Bsdf, BsdfSample};
use crate::spectrum::Rgb;
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;

/// Probability of sampling the specular chain.
const PROB_SPECULAR: f32 = 0.5;
/// Bounces allowed per layer in each walk.
const BOUNCES_PER_LAYER: usize = 3;

#[derive(Clone, Debug)]
pub struct Layered {
    /// The layers, front (side of the geometric normal) first.
    pub layers: Vec<Bsdf>,
    /// Per-hit seed of the estimator.
    pub seed: u64,
}

/// SplitMix64: a small generator for the walks.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn next(&mut self) -> f32 {
        ((self.next_u64() >> 40) as f32 / (1u64 << 24) as f32).min(ONE_MINUS_EPSILON)
    }
    fn next2(&mut self) -> Vec2 {
        Vec2::new(self.next(), self.next())
    }
}

fn hash_dirs(seed: u64, a: Vec3A, b: Vec3A) -> u64 {
    let mut h = seed ^ 0x51_7cc1_b727_220a;
    for v in [a.x, a.y, a.z, b.x, b.y, b.z] {
        h = (h ^ v.to_bits() as u64).wrapping_mul(0x100_0000_01b3);
        h ^= h >> 29;
    }
    h
}

/// One scattering event of a walk: the layer, the direction the walk arrived from (pointing
/// away from the layer), the throughput before it, and how its arrival was sampled.
#[derive(Clone, Copy, Debug)]
struct Vertex {
    layer: usize,
    dir: Vec3A,
    throughput: Rgb,
    /// Density of the sample that led here, and of the reverse choice at the previous event.
    pdf_fwd: f32,
    pdf_back: f32,
    specular: bool,
}

impl Layered {
    fn max_bounces(&self) -> usize {
        BOUNCES_PER_LAYER * self.layers.len()
    }

    /// The layer a walk entering from `dir` meets first.
    fn entry(&self, dir: Vec3A, ng: Vec3A) -> usize {
        if dir.dot(ng) < 0.0 {
            self.layers.len().saturating_sub(1)
        } else {
            0
        }
    }

    /// The layer after leaving `layer` toward `dir`, if still inside the stack.
    fn next_layer(&self, layer: usize, dir: Vec3A, ng: Vec3A) -> Option<usize> {
        if dir.dot(ng) > 0.0 {
            layer.checked_sub(1)
        } else {
            Some(layer + 1).filter(|&l| l < self.layers.len())
        }
    }

    fn walk(&self, start: Vec3A, ng: Vec3A, rng: &mut Rng) -> Vec<Vertex> {
        let mut out = Vec::with_capacity(self.max_bounces());
        let mut v = Vertex {
            layer: self.entry(start, ng),
            dir: start,
            throughput: Rgb::WHITE,
            pdf_fwd: 1.0,
            pdf_back: 1.0,
            specular: false,
        };
        for _ in 0..self.max_bounces() {
            let Some(b) = self.layers.get(v.layer) else {
                break;
            };
            out.push(v);
            let Some(s) = b.sample_f(v.dir, rng.next(), rng.next2()) else {
                break;
            };
            let back = if s.specular {
                s.pdf
            } else {
                b.pdf(s.wi, v.dir)
            };
            let w = s.f * (s.wi.dot(b.frame.n).abs() / s.pdf);
            let Some(next) = self.next_layer(v.layer, s.wi, ng) else {
                break;
            };
            v = Vertex {
                layer: next,
                dir: -s.wi,
                throughput: v.throughput * w,
                pdf_fwd: s.pdf,
                pdf_back: back,
                specular: s.specular,
            };
        }
        out
    }

    /// The estimate of the stack's BSDF for the pair.
    pub fn f(&self, parent: &Bsdf, wo: Vec3A, wi: Vec3A) -> Rgb {
        let ng = parent.ng;
        let mut rng = Rng(hash_dirs(self.seed, wo, wi));
        let from_wo = self.walk(wo, ng, &mut rng);
        let from_wi = self.walk(wi, ng, &mut rng);
        let mut sum = Rgb::BLACK;
        let mut fwd = Vec::new();
        let mut back = Vec::new();
        let mut spec = Vec::new();
        for (i, e) in from_wi.iter().enumerate() {
            for (j, l) in from_wo.iter().enumerate() {
                if e.layer != l.layer {
                    continue;
                }
                let Some(b) = self.layers.get(e.layer) else {
                    continue;
                };
                let path = e.throughput * b.f(e.dir, l.dir) * l.throughput;
                if path.is_black() {
                    continue;
                }
                // The chain of events from the wo side (0) to the wi side (i + j).
                fwd.clear();
                back.clear();
                spec.clear();
                for v in &from_wo[1..=j] {
                    fwd.push(v.pdf_fwd);
                    back.push(v.pdf_back);
                    spec.push(v.specular);
                }
                fwd.push(b.pdf(l.dir, e.dir));
                back.push(b.pdf(e.dir, l.dir));
                spec.push(false);
                for v in from_wi[1..=i].iter().rev() {
                    fwd.push(v.pdf_back);
                    back.push(v.pdf_fwd);
                    spec.push(v.specular);
                }
                let weight = balance(&fwd, &back, &spec, j);
                sum += path * weight;
            }
        }
        sum
    }

    pub fn pdf(&self) -> f32 {
        (1.0 - PROB_SPECULAR) / (4.0 * PI)
    }

    pub fn sample_f(&self, parent: &Bsdf, wo: Vec3A, u: f32, u2: Vec2) -> Option<BsdfSample> {
        if u < PROB_SPECULAR {
            return self.sample_specular(parent, wo, u2);
        }
        let v = (u - PROB_SPECULAR) / (1.0 - PROB_SPECULAR);
        let transmit = v < 0.5;
        let z = 1.0 - u2.x;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * PI * u2.y;
        let mut local = Vec3A::new(r * phi.cos(), r * phi.sin(), z);
        let mut wi = parent.frame.to_world(local);
        let same = wi.dot(parent.ng) * wo.dot(parent.ng) > 0.0;
        if same == transmit {
            local.z = -local.z;
            wi = parent.frame.to_world(local);
        }
        Some(BsdfSample {
            wi,
            f: self.f(parent, wo, wi),
            pdf: self.pdf(),
            specular: false,
        })
    }

    /// A chain of specular events through the stack (LuxRender samples each layer's specular
    /// components only; here a non-specular event ends the chain without a sample, which has
    /// the same expectation).
    fn sample_specular(&self, parent: &Bsdf, wo: Vec3A, u2: Vec2) -> Option<BsdfSample> {
        let ng = parent.ng;
        let mut rng = Rng(hash_dirs(
            self.seed ^ 0x5bd1_e995,
            wo,
            Vec3A::new(u2.x, u2.y, 0.0),
        ));
        let mut layer = self.entry(wo, ng);
        let mut dir = wo;
        let mut weight = Rgb::WHITE;
        let mut pdf = PROB_SPECULAR;
        for _ in 0..=2 * self.max_bounces() {
            let b = self.layers.get(layer)?;
            let s = b.sample_f(dir, rng.next(), rng.next2())?;
            if !s.specular {
                return None;
            }
            weight *= s.f * (s.wi.dot(b.frame.n).abs() / s.pdf);
            pdf *= s.pdf;
            match self.next_layer(layer, s.wi, ng) {
                Some(next) => {
                    layer = next;
                    dir = -s.wi;
                }
                None => {
                    let c = s.wi.dot(parent.frame.n).abs();
                    return (c > 0.0 && pdf > 0.0).then(|| BsdfSample {
                        wi: s.wi,
                        f: weight * (pdf / c),
                        pdf,
                        specular: true,
                    });
                }
            }
        }
        None
    }
}

/// Balance-heuristic weight of connecting at event `join` among all non-specular events of
/// the chain: `p_k = Π_{m<k} fwd[m] · Π_{m>k} back[m]`.
fn balance(fwd: &[f32], back: &[f32], spec: &[bool], join: usize) -> f32 {
    let n = fwd.len();
    let mut total = 0.0f64;
    let mut mine = 0.0f64;
    for k in 0..n {
        if spec.get(k).copied().unwrap_or(true) {
            continue;
        }
        let mut p = 1.0f64;
        for (m, (&f, &b)) in fwd.iter().zip(back).enumerate() {
            if m < k {
                p *= f as f64;
            } else if m > k {
                p *= b as f64;
            }
        }
        total += p;
        if k == join {
            mine = p;
        }
    }
    if total > 0.0 && total.is_finite() {
        (mine / total) as f32
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn balance_weights_of_one_chain_sum_to_one() {
        let fwd = [0.3, 0.5, 0.2, 0.9];
        let back = [0.4, 0.1, 0.6, 0.7];
        let spec = [false, true, false, false];
        let sum: f32 = (0..4).map(|j| balance(&fwd, &back, &spec, j)).sum();
        assert!((sum - 1.0).abs() < 1e-6, "{sum}");
        assert_eq!(balance(&fwd, &back, &spec, 1), 0.0);
        // A single event takes the whole weight.
        assert_eq!(balance(&[0.2], &[0.7], &[false], 0), 1.0);
    }
}
