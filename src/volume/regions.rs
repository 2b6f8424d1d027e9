//! The region volumes of a scene together, as LuxRender 1.x's `AggregateRegion` combines
//! them: every `Volume` statement adds a region, and where regions overlap their absorption,
//! scattering and emission add up. The aggregate is one medium — the one wherever no medium
//! is named — whose coefficients at a point are the sums over the regions containing it.
//!
//! Along a ray every region yields its pieces of constant coefficients ([`Region::pieces`]);
//! [`Walk`] merges them into pieces of the summed coefficients, and transmittance, distance
//! sampling and emission all run over those merged pieces. So the union renders as a single
//! medium with the summed coefficients would: two coincident homogeneous boxes give exactly
//! the transmittance and free-flight distribution of one box with the sums.
//!
//! The phase function at a scattering point is the mixture of the regions' Henyey–Greenstein
//! lobes weighted by their sigma_s there (the physical mixture; LuxRender 1.x's
//! `AggregateRegion::P` weighs by sigma_a / sigma_t instead). When the regions share one `g`
//! the mixture is that lobe. Otherwise one region's lobe is chosen with probability
//! proportional to its channel-averaged sigma_s (from the unused fraction of the sample's
//! channel choice) and the weight carries that region's sigma_s over the choice probability:
//! an unbiased one-sample estimate of the mixture, valid for bidirectional weights too since
//! every strategy that creates the point chooses its lobe with the same probabilities.
//!
//! Emission: [`Regions::emission`] is ∫ Tr(t)·Le(t) dt over the segment, computed in closed
//! form on every merged piece (Le·(1 − e^(−σt·h))/σt times the transmittance to the piece,
//! Le·h where σt = 0). It is exact for homogeneous regions and, for marched ones, exact for
//! the same piecewise-constant medium their transmittance uses (no random offset: LuxRender's
//! emission and single integrators march with a random offset within the first step and
//! sum Tr·Le·step, which converges to the same integral).

use super::heterogeneous::{Coeffs, OPAQUE};
use super::region::{Piece, Pieces, Region};
use super::{channel_avg, HenyeyGreenstein, MediumSample};
use crate::geometry::Ray;
use crate::spectrum::Rgb;
use glam::Vec3A;

/// Regions walked with cursors on the stack (more use a heap vector).
const INLINE: usize = 4;

/// All region volumes of a scene.
#[derive(Debug)]
pub struct Regions {
    members: Vec<Region>,
    emits: bool,
    scatters: bool,
    /// The asymmetry every member shares, if they share one.
    common_g: Option<f32>,
}

impl Regions {
    /// The aggregate of `members`; `None` when there are none or none acts on light.
    pub fn new(members: Vec<Region>) -> Option<Regions> {
        let members: Vec<Region> = members.into_iter().filter(|r| !r.is_vacuum()).collect();
        let first_g = members.first()?.g();
        let common_g = members.iter().all(|r| r.g() == first_g).then_some(first_g);
        Some(Regions {
            emits: members.iter().any(Region::emits),
            scatters: members.iter().any(Region::scatters),
            common_g,
            members,
        })
    }

    /// The world-space box around every member.
    pub fn world_bounds(&self) -> (Vec3A, Vec3A) {
        let mut b = (Vec3A::INFINITY, Vec3A::NEG_INFINITY);
        for r in &self.members {
            let (lo, hi) = r.world_bounds();
            b = (b.0.min(lo), b.1.max(hi));
        }
        b
    }

    /// How many regions the aggregate holds.
    pub fn len(&self) -> usize {
        self.members.len()
    }

    /// Whether the aggregate is empty (never: [`Regions::new`] refuses that).
    pub fn is_empty(&self) -> bool {
        self.members.is_empty()
    }

    /// Whether some region emits light.
    pub fn emits(&self) -> bool {
        self.emits
    }

    /// Whether some region scatters light.
    pub fn scatters(&self) -> bool {
        self.scatters
    }

    /// The summed extinction sigma_a + sigma_s at world point `p`.
    pub fn sigma_t(&self, p: Vec3A) -> Rgb {
        self.members
            .iter()
            .fold(Rgb::BLACK, |s, r| s + r.coeffs(p).sigma_t())
    }

    /// Runs `f` on a walk of the merged pieces along [0, `t_max`] of `ray`.
    fn walk<R>(&self, ray: &Ray, t_max: f32, f: impl FnOnce(&mut Walk) -> R) -> R {
        let cursor = |r| cursor(r, ray, t_max);
        if self.members.len() <= INLINE {
            let mut cur: [Option<Cursor>; INLINE] =
                std::array::from_fn(|i| self.members.get(i).and_then(cursor));
            f(&mut Walk {
                cur: &mut cur,
                t: 0.0,
            })
        } else {
            let mut cur: Vec<Option<Cursor>> = self.members.iter().map(cursor).collect();
            f(&mut Walk {
                cur: &mut cur,
                t: 0.0,
            })
        }
    }

    /// Transmittance over [0, `t_max`]: e^(−Σ σt·h) over the merged pieces.
    pub fn tr(&self, ray: &Ray, t_max: f32) -> Rgb {
        let len = ray.d.length();
        let tau = self.walk(ray, t_max, |w| {
            let mut tau = Rgb::BLACK;
            while let Some((t0, t1, c)) = w.next() {
                tau += c.sigma_t() * ((t1 - t0) * len);
                if opaque(tau) {
                    return None;
                }
            }
            Some(tau)
        });
        tau.map_or(Rgb::BLACK, |t| t.map(|v| (-v).exp()))
    }

    /// ∫ Tr(t)·Le(t) dt over [0, `t_max`] (distance units), Tr from the segment's start.
    pub fn emission(&self, ray: &Ray, t_max: f32) -> Rgb {
        let len = ray.d.length();
        self.walk(ray, t_max, |w| {
            let (mut tau, mut sum) = (Rgb::BLACK, Rgb::BLACK);
            while let Some((t0, t1, c)) = w.next() {
                let h = (t1 - t0) * len;
                let st = c.sigma_t();
                if !c.le.is_black() {
                    sum += piece_emission(tau, st, c.le, h);
                }
                tau += st * h;
                if opaque(tau) {
                    break;
                }
            }
            sum
        })
    }

    /// Samples where along [0, `t_max`] the ray scatters (or that it passes), as one
    /// medium of the summed coefficients: the optical depth of the channel `u_channel` picks
    /// is followed over the merged pieces until it reaches −ln(1 − u).
    pub fn sample(&self, ray: &Ray, t_max: f32, u: f32, u_channel: f32) -> MediumSample {
        let len = ray.d.length();
        let scaled = (u_channel * 3.0).clamp(0.0, 2.999_999);
        let ch = scaled as usize;
        let u_lobe = scaled - ch as f32;
        let target = -(1.0 - u).max(f32::MIN_POSITIVE).ln();
        let phase = HenyeyGreenstein::new(self.common_g.unwrap_or(0.0));
        self.walk(ray, t_max, |w| {
            let mut tau = Rgb::BLACK;
            while let Some((t0, t1, c)) = w.next() {
                let st = c.sigma_t();
                let h = (t1 - t0) * len;
                let (s_ch, before) = (st.to_array()[ch], tau.to_array()[ch]);
                if s_ch > 0.0 && before + s_ch * h >= target {
                    // Within the stretch, whatever the rounding.
                    let d = ((target - before) / s_ch).min(h);
                    let tr = (tau + st * d).map(|v| (-v).exp());
                    let pdf = channel_avg(st * tr);
                    let (ss, phase) = match self.common_g {
                        Some(_) => (c.sigma_s, phase),
                        None => self.choose_lobe(w, t0, c.sigma_s, u_lobe),
                    };
                    return MediumSample {
                        scatter_t: Some(t0 + d / len),
                        weight: if pdf > 0.0 { ss * tr / pdf } else { Rgb::BLACK },
                        phase,
                    };
                }
                tau += st * h;
            }
            let tr = tau.map(|v| (-v).exp());
            let pdf = channel_avg(tr);
            MediumSample {
                scatter_t: None,
                weight: if pdf > 0.0 { tr / pdf } else { Rgb::BLACK },
                phase,
            }
        })
    }

    /// Picks the region whose lobe scatters at the merged piece starting at `t0` (summed
    /// sigma_s `total`) with probability ∝ its channel-averaged sigma_s: its sigma_s over
    /// that probability, and its lobe.
    fn choose_lobe(&self, w: &Walk, t0: f32, total: Rgb, u: f32) -> (Rgb, HenyeyGreenstein) {
        let sum = channel_avg(total);
        let mut acc = 0.0;
        let mut last = None;
        for (i, p) in w.active(t0) {
            let share = channel_avg(p.c.sigma_s);
            if share <= 0.0 {
                continue;
            }
            let g = self.members.get(i).map_or(0.0, Region::g);
            last = Some((p.c.sigma_s * (sum / share), HenyeyGreenstein::new(g)));
            acc += share / sum;
            if u < acc {
                break;
            }
        }
        last.unwrap_or((total, HenyeyGreenstein::new(0.0)))
    }
}

/// ∫₀ʰ e^(−τ − σt·x)·Le dx per channel: the emission of one piece of length `h` seen through
/// optical depth `tau`.
fn piece_emission(tau: Rgb, st: Rgb, le: Rgb, h: f32) -> Rgb {
    let f = |tau: f32, s: f32, le: f32| {
        if le == 0.0 {
            return 0.0;
        }
        let through = if s > 0.0 { -(-s * h).exp_m1() / s } else { h };
        (-tau).exp() * le * through
    };
    Rgb::new(
        f(tau.r, st.r, le.r),
        f(tau.g, st.g, le.g),
        f(tau.b, st.b, le.b),
    )
}

/// Whether every channel's transmittance is below [`OPAQUE`].
fn opaque(tau: Rgb) -> bool {
    tau.to_array().iter().all(|&t| t > -OPAQUE.ln())
}

/// A cursor on `r`'s pieces along the ray, if it crosses the region.
fn cursor<'a>(r: &'a Region, ray: &Ray, t_max: f32) -> Option<Cursor<'a>> {
    r.pieces(ray, t_max).map(Cursor::new)
}

/// One region's place in a walk: its pieces and the current one (`None`: done).
struct Cursor<'a> {
    pieces: Pieces<'a>,
    piece: Option<Piece>,
}

impl<'a> Cursor<'a> {
    fn new(mut pieces: Pieces<'a>) -> Cursor<'a> {
        let piece = pieces.next();
        Cursor { pieces, piece }
    }
}

/// The merged pieces of several regions along one ray, in order: each is a stretch where
/// no region's piece begins or ends, with the sum of the coefficients of the pieces over it
/// (stretches no region covers are skipped).
struct Walk<'c, 'a> {
    cur: &'c mut [Option<Cursor<'a>>],
    t: f32,
}

impl Walk<'_, '_> {
    /// The next merged piece: (t0, t1, summed coefficients).
    fn next(&mut self) -> Option<(f32, f32, Coeffs)> {
        let t = self.t;
        let mut lo = f32::INFINITY;
        for c in self.cur.iter_mut().flatten() {
            while c.piece.is_some_and(|p| p.t1 <= t) {
                c.piece = c.pieces.next();
            }
            if let Some(p) = c.piece {
                lo = lo.min(p.t0.max(t));
            }
        }
        if lo == f32::INFINITY {
            return None;
        }
        let mut hi = f32::INFINITY;
        let mut sum = Coeffs::default();
        for p in self.cur.iter().flatten().filter_map(|c| c.piece) {
            if p.t0 <= lo {
                hi = hi.min(p.t1);
                sum = sum + p.c;
            } else {
                hi = hi.min(p.t0);
            }
        }
        self.t = hi;
        Some((lo, hi, sum))
    }

    /// The regions (index, piece) whose current piece covers the merged piece at `t0`.
    fn active(&self, t0: f32) -> impl Iterator<Item = (usize, Piece)> + '_ {
        self.cur.iter().enumerate().filter_map(move |(i, c)| {
            let p = c.as_ref()?.piece?;
            (p.t0 <= t0 && t0 < p.t1).then_some((i, p))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grey(v: f32) -> Rgb {
        Rgb::splat(v)
    }

    /// A box spanning x in [x0, x1] (and −1..1 in y and z) of the given coefficients.
    fn slab(x0: f32, x1: f32, sa: Rgb, ss: Rgb, le: Rgb, g: f32) -> Region {
        let c = Coeffs {
            sigma_a: sa,
            sigma_s: ss,
            le,
        };
        Region::uniform(Vec3A::new(x0, -1.0, -1.0), Vec3A::new(x1, 1.0, 1.0), c, g)
    }

    /// The ray from x = −1 along +x (direction of length 2: ray parameters are half
    /// distances).
    fn ray() -> Ray {
        Ray {
            o: Vec3A::new(-1.0, 0.0, 0.0),
            d: Vec3A::new(2.0, 0.0, 0.0),
            t_max: f32::INFINITY,
            time: 0.0,
        }
    }

    fn close(a: Rgb, b: Rgb, rel: f32) -> bool {
        let (a, b) = (a.to_array(), b.to_array());
        (0..3).all(|i| (a[i] - b[i]).abs() <= rel * a[i].abs().max(b[i].abs()).max(1e-6))
    }

    /// Boxes [0, 2] and [1, 3] with sigma_t 0.3 and 0.5 (per channel different): along the
    /// whole ray the optical depth is 2·0.3 + 2·0.5, by hand.
    #[test]
    fn transmittance_of_overlapping_boxes_adds_their_optical_depths() {
        let a = slab(
            0.0,
            2.0,
            Rgb::new(0.1, 0.2, 0.3),
            grey(0.1),
            Rgb::BLACK,
            0.0,
        );
        let b = slab(
            1.0,
            3.0,
            Rgb::new(0.4, 0.2, 0.0),
            grey(0.1),
            Rgb::BLACK,
            0.0,
        );
        let r = Regions::new(vec![a, b]).expect("regions");
        let want = |s1: f32, s2: f32| (-(2.0 * s1 + 2.0 * s2)).exp();
        let tr = r.tr(&ray(), 10.0);
        let expect = Rgb::new(want(0.2, 0.5), want(0.3, 0.3), want(0.4, 0.1));
        assert!(close(tr, expect, 1e-5), "{tr:?} vs {expect:?}");
        // Up to x = 1.5 (t = 1.25): 1.5·sigma_a + 0.5·sigma_b.
        let tr = r.tr(&ray(), 1.25);
        let expect = (-(1.5 * 0.2 + 0.5 * 0.5f32)).exp();
        assert!((tr.r - expect).abs() < 1e-6, "{} vs {expect}", tr.r);
    }

    /// Two coincident boxes and one box of the summed coefficients: the same
    /// transmittance, the same sampled distances and weights for every (u, channel).
    #[test]
    fn coincident_boxes_sample_as_one_box_of_the_sums() {
        let (sa1, ss1) = (Rgb::new(0.1, 0.3, 0.2), Rgb::new(0.5, 0.2, 0.4));
        let (sa2, ss2) = (Rgb::new(0.2, 0.1, 0.0), Rgb::new(0.3, 0.6, 0.1));
        let two = Regions::new(vec![
            slab(0.0, 2.0, sa1, ss1, Rgb::BLACK, 0.3),
            slab(0.0, 2.0, sa2, ss2, Rgb::BLACK, 0.3),
        ])
        .expect("regions");
        let one = Regions::new(vec![slab(0.0, 2.0, sa1 + sa2, ss1 + ss2, Rgb::BLACK, 0.3)])
            .expect("regions");
        assert!(close(two.tr(&ray(), 10.0), one.tr(&ray(), 10.0), 1e-6));
        for i in 0..64 {
            for ch in 0..3 {
                let u = (i as f32 + 0.5) / 64.0;
                let uc = (ch as f32 + 0.5) / 3.0;
                let (a, b) = (
                    two.sample(&ray(), 10.0, u, uc),
                    one.sample(&ray(), 10.0, u, uc),
                );
                match (a.scatter_t, b.scatter_t) {
                    (Some(x), Some(y)) => assert!((x - y).abs() < 1e-5, "u={u}: {x} vs {y}"),
                    (None, None) => {}
                    other => panic!("u={u} ch={ch}: {other:?}"),
                }
                assert!(close(a.weight, b.weight, 1e-4), "{a:?} vs {b:?}");
                assert_eq!(a.phase, b.phase);
            }
        }
    }

    /// More regions than a walk keeps on the stack (six staggered slabs [k/2, k/2 + 1],
    /// sigma_a 0.1·(k + 1)): the transmittance is the product over the slabs, by hand, and
    /// emission and free flight agree with one medium of the sums on every piece.
    #[test]
    fn six_staggered_slabs_add_up_as_two_do() {
        let slabs: Vec<Region> = (0..6)
            .map(|k| {
                let x0 = k as f32 * 0.5;
                let sa = grey(0.1 * (k + 1) as f32);
                slab(x0, x0 + 1.0, sa, grey(0.05), grey(0.2), 0.0)
            })
            .collect();
        let r = Regions::new(slabs).expect("regions");
        // Every slab is crossed over its whole unit length: τ = Σ (0.1·(k + 1) + 0.05).
        let tau: f32 = (0..6).map(|k| 0.1 * (k + 1) as f32 + 0.05).sum();
        let tr = r.tr(&ray(), 10.0);
        assert!(
            (tr.g - (-tau).exp()).abs() < 1e-6,
            "{} vs {}",
            tr.g,
            (-tau).exp()
        );
        // Free flight: the sample for u lands where the summed depth reaches −ln(1 − u).
        for i in 0..32 {
            let u = (i as f32 + 0.5) / 32.0;
            let target = -(1.0 - u).ln();
            let s = r.sample(&ray(), 10.0, u, 0.5);
            match s.scatter_t {
                Some(t) => {
                    let x = -1.0 + 2.0 * t;
                    let tr_x = r.tr(&ray(), t);
                    let depth = -tr_x.g.ln();
                    assert!((depth - target).abs() < 1e-4, "u={u}: x={x}, τ={depth}");
                }
                None => assert!(target >= tau - 1e-5, "u={u}: no scattering before τ={tau}"),
            }
        }
    }

    /// Distance sampling in overlapping boxes [0, 2] (sigma_t 1) and [1, 3] (sigma_t 2),
    /// along x from −1: the optical depth τ(x) is x on [0, 1], 1 + 3(x − 1) on [1, 2],
    /// 4 + 2(x − 2) on [2, 3]; the sample for u lands where τ = −ln(1 − u).
    #[test]
    fn free_flight_follows_the_summed_optical_depth() {
        let r = Regions::new(vec![
            slab(0.0, 2.0, grey(0.5), grey(0.5), Rgb::BLACK, 0.0),
            slab(1.0, 3.0, grey(1.0), grey(1.0), Rgb::BLACK, 0.0),
        ])
        .expect("regions");
        let x_of = |tau: f32| {
            if tau <= 1.0 {
                tau
            } else if tau <= 4.0 {
                1.0 + (tau - 1.0) / 3.0
            } else {
                2.0 + (tau - 4.0) / 2.0
            }
        };
        for u in [0.1f32, 0.5, 0.7, 0.95, 0.99] {
            let s = r.sample(&ray(), 10.0, u, 0.5);
            let tau = -(1.0 - u).ln();
            let want_t = (x_of(tau) + 1.0) / 2.0;
            let t = s.scatter_t.expect("scatters");
            assert!((t - want_t).abs() < 1e-5, "u={u}: t {t} vs {want_t}");
            // Scattering weight: sigma_s·Tr / (sigma_t·Tr) = the albedo 1/2.
            assert!(close(s.weight, grey(0.5), 1e-5), "{:?}", s.weight);
        }
        // Past τ = 6 the ray leaves the last box: it passes with weight 1 (grey).
        let s = r.sample(&ray(), 10.0, 1.0 - (-6.5f32).exp(), 0.5);
        assert_eq!(s.scatter_t, None);
        assert!(close(s.weight, Rgb::WHITE, 1e-5));
    }

    /// An emitting homogeneous box seen along its length L = 2: Le·(1 − e^(−σt·L))/σt, and
    /// Le·L without extinction; overlapping emitters add.
    #[test]
    fn emission_through_a_box_is_the_closed_form() {
        let le = Rgb::new(1.0, 2.0, 0.5);
        let r = Regions::new(vec![slab(0.0, 2.0, grey(0.3), grey(0.2), le, 0.0)]).unwrap();
        let e = r.emission(&ray(), 10.0);
        let want = le * ((1.0 - (-0.5f32 * 2.0).exp()) / 0.5);
        assert!(close(e, want, 1e-5), "{e:?} vs {want:?}");
        let r = Regions::new(vec![slab(0.0, 2.0, grey(0.0), grey(0.0), le, 0.0)]).unwrap();
        assert!(close(r.emission(&ray(), 10.0), le * 2.0, 1e-6));
        // Ending inside the box (x = 1): half the length.
        assert!(close(r.emission(&ray(), 1.0), le, 1e-6));
        // Emitters [0, 2] and [1, 3] without extinction: Le over 4 units of length.
        let r = Regions::new(vec![
            slab(0.0, 2.0, grey(0.0), grey(0.0), le, 0.0),
            slab(1.0, 3.0, grey(0.0), grey(0.0), le, 0.0),
        ])
        .unwrap();
        assert!(close(r.emission(&ray(), 10.0), le * 4.0, 1e-6));
        // An absorbing box in front of an emitting one dims it by its transmittance.
        let r = Regions::new(vec![
            slab(0.0, 1.0, grey(0.7), grey(0.0), Rgb::BLACK, 0.0),
            slab(1.0, 2.0, grey(0.0), grey(0.0), le, 0.0),
        ])
        .unwrap();
        assert!(close(r.emission(&ray(), 10.0), le * (-0.7f32).exp(), 1e-5));
    }

    /// Coincident boxes of g 0.6 (sigma_s 1) and −0.4 (sigma_s 3): lobes are chosen a
    /// quarter and three quarters of the time, each weighted by its sigma_s over that share,
    /// so the expected weight·phase is the sigma_s-weighted mixture.
    #[test]
    fn different_lobes_are_chosen_by_their_scattering() {
        let r = Regions::new(vec![
            slab(0.0, 2.0, grey(0.0), grey(1.0), Rgb::BLACK, 0.6),
            slab(0.0, 2.0, grey(0.0), grey(3.0), Rgb::BLACK, -0.4),
        ])
        .unwrap();
        let n = 3000;
        let (mut forward, mut mix) = (0, 0.0f64);
        let cos = 0.3;
        for i in 0..n {
            let uc = (i as f32 + 0.5) / n as f32;
            let s = r.sample(&ray(), 10.0, 0.5, uc);
            assert!(s.scatter_t.is_some());
            if s.phase.g > 0.0 {
                forward += 1;
            }
            mix += f64::from(s.weight.r * s.phase.p(cos)) / n as f64;
        }
        assert!((forward as f64 / n as f64 - 0.25).abs() < 0.01, "{forward}");
        let hg = |g: f32| f64::from(HenyeyGreenstein::new(g).p(cos));
        // Albedo 1: the expected weight is 1, split as 1/4 and 3/4 of the mixture.
        let want = 0.25 * hg(0.6) + 0.75 * hg(-0.4);
        assert!((mix - want).abs() < 1e-3 * want, "{mix} vs {want}");
    }
}
