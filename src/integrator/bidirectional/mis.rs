//! Multiple importance sampling weights of bidirectional path tracing (power heuristic).
//!
//! A path of k vertices x₀ (on a light) … x_{k−1} (the camera) can be built by strategies
//! s = 0 … k−1: the first s vertices from the light, the other t = k − s from the camera.
//! Strategy s draws the path with density p_s = Π_{j<s} pl_j · Π_{j≥s} pe_j, where pl_j and
//! pe_j are the densities with which the light side and the camera side generate x_j (area
//! measure; solid angle for a vertex at infinity). s = 1 samples x₀ by direct lighting, whose
//! density `pdir0` differs from the light subpath's origin density pl₀, as LuxRender does.
//! The weight of the strategy that found the path is p_s² / Σ p_{s'}² over the strategies
//! that could have found it: within the eye and light depths, connecting two non-delta
//! vertices, reaching the camera only when light paths may (t = 1). s = t = 1 (a path of two
//! vertices: a point on an area light seen by the camera) is the light subpath's origin
//! joined to the camera, as LuxRender's bidirectional joins it: its density is pl₀, and it
//! exists only when x₀ is on an area light ([`PathDensities::area_origin`]).
//!
//! In a scene with media, a subpath may scatter in media at most `max_scatters` times (the
//! volume integrator's limit): a strategy whose light part or eye part holds more medium
//! vertices than that cannot build the path and takes no weight.
//!
//! Densities "through" a delta vertex are stored as 0 and count as 1 in the ratios (they
//! are the same discrete choice on both sides); the ratios p_{s'}/p_s are built one vertex
//! at a time from the current strategy outwards, so the products never overflow.

/// The densities of one path, indexed from the light end.
#[derive(Clone, Debug, Default)]
pub struct PathDensities {
    /// Light-side densities (pl₀ is the subpath origin density).
    pub pl: Vec<f32>,
    /// Camera-side densities.
    pub pe: Vec<f32>,
    /// Vertices whose scattering in this path was a delta distribution.
    pub delta: Vec<bool>,
    /// Vertices that are scattering points in a medium.
    pub medium: Vec<bool>,
    /// Density of x₀ under strategy s = 1: direct lighting's, or in a path of two vertices
    /// the light subpath origin's (s = t = 1).
    pub pdir0: f32,
    /// x₀ is a delta position or direction: no ray can hit it (s = 0 impossible).
    pub light_delta: bool,
    /// x₀ is a point on an area light (the strategy s = t = 1 exists for it).
    pub area_origin: bool,
}

/// Limits on the strategies that exist.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Largest light subpath (vertices, the light included).
    pub max_light: usize,
    /// Largest eye subpath (vertices, the camera included).
    pub max_eye: usize,
    /// Light subpaths may be joined to the camera (t = 1).
    pub camera: bool,
    /// Medium vertices one subpath may hold.
    pub max_scatters: usize,
}

fn remap0(v: f32) -> f32 {
    if v != 0.0 && v.is_finite() {
        v
    } else {
        1.0
    }
}

impl PathDensities {
    /// Sets up for a path of `k` vertices.
    pub fn reset(&mut self, k: usize) {
        self.pl.clear();
        self.pe.clear();
        self.delta.clear();
        self.medium.clear();
        self.pl.resize(k, 0.0);
        self.pe.resize(k, 0.0);
        self.delta.resize(k, false);
        self.medium.resize(k, false);
        self.pdir0 = 0.0;
        self.light_delta = false;
        self.area_origin = false;
    }

    fn k(&self) -> usize {
        self.pl.len()
    }

    /// Whether strategy `s` (light vertices) exists for this path.
    #[cfg(test)]
    fn valid(&self, s: usize, lim: &Limits) -> bool {
        self.valid_given(s, lim, self.scatters())
    }

    /// The path's count of medium vertices.
    fn scatters(&self) -> usize {
        self.medium.iter().filter(|&&m| m).count()
    }

    /// [`Self::valid`] with the path's count of medium vertices already known: every
    /// condition spelled out, against which the tests check the weight's faster split into
    /// [`Self::allowed`] and [`Self::joinable`].
    #[cfg(test)]
    fn valid_given(&self, s: usize, lim: &Limits, scatters: usize) -> bool {
        let k = self.k();
        if s >= k {
            return false;
        }
        let t = k - s;
        if s > lim.max_light || t > lim.max_eye || (s == 1 && t == 1 && !self.area_origin) {
            return false;
        }
        if t == 1 && !lim.camera {
            return false;
        }
        if scatters > lim.max_scatters && !self.within_scatter_limit(s, lim.max_scatters) {
            return false;
        }
        match s {
            0 => !self.light_delta,
            1 => self.pdir0 > 0.0 && !self.delta[1],
            _ => self.pl[0] > 0.0 && !self.delta[s - 1] && !self.delta[s],
        }
    }

    /// Whether neither the light part (x_0..x_{s-1}) nor the eye part holds more medium
    /// vertices than `max`.
    #[cold]
    fn within_scatter_limit(&self, s: usize, max: usize) -> bool {
        let light = self.medium.iter().take(s).filter(|&&m| m).count();
        let eye = self.medium.iter().skip(s).filter(|&&m| m).count();
        light <= max && eye <= max
    }

    /// The range of strategies the depth limits and the camera allow: s ≤ `max_light`,
    /// t = k − s ≤ `max_eye`, t ≥ 1 (t = 1 only when the camera can be joined).
    fn allowed(&self, lim: &Limits) -> std::ops::RangeInclusive<usize> {
        let k = self.k();
        let last = if lim.camera {
            k - 1
        } else {
            k.saturating_sub(2)
        };
        k.saturating_sub(lim.max_eye)..=last.min(lim.max_light)
    }

    /// [`Self::valid_given`] for a strategy inside [`Self::allowed`]: what is left to check
    /// is the vertices the strategy joins and the medium limit (`pl0_ok`: pl₀ > 0).
    #[inline]
    fn joinable(&self, s: usize, lim: &Limits, scatters: usize, pl0_ok: bool) -> bool {
        let joins = match s {
            0 => !self.light_delta,
            1 => self.pdir0 > 0.0 && !self.delta[1] && (self.k() > 2 || self.area_origin),
            _ => pl0_ok && !self.delta[s - 1] && !self.delta[s],
        };
        joins && (scatters <= lim.max_scatters || self.within_scatter_limit(s, lim.max_scatters))
    }

    /// The power-heuristic weight of strategy `s`.
    pub fn weight(&self, s: usize, lim: &Limits) -> f32 {
        let k = self.k();
        if k < 2 || s >= k {
            return 0.0;
        }
        let (pl, pe) = (&self.pl, &self.pe);
        let scatters = self.scatters();
        let allowed = self.allowed(lim);
        let pl0_ok = pl[0] > 0.0;
        let mut sum = 1.0f64;
        // Fewer light vertices: x_j moves to the camera side.
        let mut r = 1.0f64;
        for j in (*allowed.start()..s).rev() {
            let den = if j == 0 { self.pdir0 } else { pl[j] };
            r *= f64::from(remap0(pe[j])) / f64::from(remap0(den));
            if j == 1 {
                r *= f64::from(remap0(self.pdir0)) / f64::from(remap0(pl[0]));
            }
            if j <= *allowed.end() && self.joinable(j, lim, scatters, pl0_ok) {
                sum += r * r;
            }
        }
        // More light vertices: x_{s'-1} moves to the light side.
        let mut r = 1.0f64;
        for sp in s + 1..=*allowed.end() {
            let j = sp - 1;
            let num = if j == 0 { self.pdir0 } else { pl[j] };
            r *= f64::from(remap0(num)) / f64::from(remap0(pe[j]));
            if sp == 2 {
                r *= f64::from(remap0(pl[0])) / f64::from(remap0(self.pdir0));
            }
            if sp >= *allowed.start() && self.joinable(sp, lim, scatters, pl0_ok) {
                sum += r * r;
            }
        }
        let w = (1.0 / sum) as f32;
        if w.is_finite() {
            w
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Explicit p_s = Π pl · Π pe over valid strategies, against the incremental ratios.
    fn brute(d: &PathDensities, s: usize, lim: &Limits) -> f32 {
        let k = d.pl.len();
        let p = |sp: usize| -> f64 {
            let mut v = 1.0f64;
            for j in 0..k {
                let x = if j < sp {
                    if j == 0 && sp == 1 {
                        d.pdir0
                    } else {
                        d.pl[j]
                    }
                } else {
                    d.pe[j]
                };
                v *= f64::from(remap0(x));
            }
            v
        };
        let ps = p(s);
        let mut sum = 0.0;
        for sp in 0..k {
            if sp == s || d.valid(sp, lim) {
                sum += (p(sp) / ps).powi(2);
            }
        }
        (1.0 / sum) as f32
    }

    fn densities(k: usize, seed: u32) -> PathDensities {
        let mut d = PathDensities::default();
        d.reset(k);
        let mut x = seed.wrapping_mul(2_654_435_761);
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            0.05 + (x % 1000) as f32 / 100.0
        };
        for j in 0..k {
            d.pl[j] = next();
            d.pe[j] = next();
        }
        d.pdir0 = next();
        d
    }

    #[test]
    fn weights_match_explicit_products_and_sum_to_one() {
        for (camera, max_scatters) in [(true, usize::MAX), (false, usize::MAX), (true, 1)] {
            let lim = Limits {
                max_light: 4,
                max_eye: 5,
                camera,
                max_scatters,
            };
            weights_match(&lim);
        }
    }

    /// Random densities, delta vertices, medium vertices and origins under `lim`.
    fn weights_match(lim: &Limits) {
        let lim = *lim;
        for k in 2..=9 {
            for seed in 1..20 {
                let mut d = densities(k, seed * 31 + k as u32);
                if seed % 3 == 0 && k > 3 {
                    d.delta[k / 2] = true;
                    d.pl[k / 2 + 1] = 0.0;
                    d.pe[k / 2 - 1] = 0.0;
                }
                d.light_delta = seed % 5 == 0;
                d.area_origin = seed % 2 == 0;
                if seed % 4 == 1 && k > 4 {
                    d.medium[1] = true;
                    d.medium[k - 2] = true;
                }
                let mut total = 0.0f64;
                for s in 0..k {
                    // Every strategy's weight against the spelled-out sum (an invalid one's
                    // too: the weight must not depend on its own validity).
                    let w = d.weight(s, &lim);
                    let b = brute(&d, s, &lim);
                    assert!(
                        (w - b).abs() < 1e-4 * b.max(1e-3),
                        "k {k} s {s}: {w} vs {b}"
                    );
                    if d.valid(s, &lim) {
                        total += f64::from(w);
                    }
                }
                let any = (0..k).any(|s| d.valid(s, &lim));
                if any {
                    assert!((total - 1.0).abs() < 1e-4, "k {k} seed {seed}: {total}");
                }
            }
        }
    }

    #[test]
    fn two_vertex_paths_weigh_the_origin_join_only_on_area_lights() {
        let lim = Limits {
            max_light: 8,
            max_eye: 8,
            camera: true,
            max_scatters: usize::MAX,
        };
        // x0 on a light, x1 the camera: s = 0 (the eye ray meets it), s = 1 (x0 joined to
        // the camera) only when x0 lies on an area light.
        let mut d = densities(2, 5);
        assert!(d.valid(0, &lim) && !d.valid(1, &lim));
        assert!((d.weight(0, &lim) - 1.0).abs() < 1e-6);
        d.area_origin = true;
        d.pdir0 = d.pl[0];
        assert!(d.valid(0, &lim) && d.valid(1, &lim));
        let (w0, w1) = (d.weight(0, &lim), d.weight(1, &lim));
        assert!((w0 + w1 - 1.0).abs() < 1e-5, "{w0} + {w1}");
        assert!((w1 - brute(&d, 1, &lim)).abs() < 1e-5);
        // The camera cannot be joined: s = 0 alone again.
        let no_cam = Limits {
            camera: false,
            ..lim
        };
        assert!(!d.valid(1, &no_cam) && (d.weight(0, &no_cam) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn delta_light_and_unconnectable_camera_drop_strategies() {
        let lim = Limits {
            max_light: 8,
            max_eye: 8,
            camera: false,
            max_scatters: usize::MAX,
        };
        let mut d = densities(3, 7);
        d.light_delta = true;
        // k = 3: s = 0 (delta light: no), s = 1 (direct), s = 2 (t = 1: no camera).
        assert!(!d.valid(0, &lim) && d.valid(1, &lim) && !d.valid(2, &lim));
        assert!((d.weight(1, &lim) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn scatter_limit_drops_strategies_with_too_many_medium_vertices_on_one_side() {
        let lim = Limits {
            max_light: 8,
            max_eye: 8,
            camera: true,
            max_scatters: 1,
        };
        // x0 light, x1 and x2 medium points, x3 camera.
        let mut d = densities(4, 3);
        d.medium[1] = true;
        d.medium[2] = true;
        // s = 0, 1: both medium vertices on the eye side; s = 3: both on the light side.
        assert!(!d.valid(0, &lim) && !d.valid(1, &lim) && !d.valid(3, &lim));
        assert!(d.valid(2, &lim));
        assert!((d.weight(2, &lim) - 1.0).abs() < 1e-6);
        let multi = Limits {
            max_scatters: usize::MAX,
            ..lim
        };
        assert!((0..4).all(|s| d.valid(s, &multi)));
    }
}
