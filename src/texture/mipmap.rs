//! Image lookups as LuxRender's `MIPMapFastImpl` does them: nearest and bilinear on the image
//! itself; for `mipmap_trilinear` and `mipmap_ewa` a pyramid built from the image resampled to
//! power-of-two sides (Lanczos, 4 taps, τ = 2, negative lobes clamped as LuxRender does) and
//! box-filtered level by level, with trilinear (`lookup_width`) and EWA (`lookup_ellipse`,
//! Gaussian weights e^(−2r²) − e^(−2), anisotropy clamped to `maxanisotropy`) filtering over a
//! footprint. LuxRender 1.x evaluates image textures at a point (no ray differentials), which
//! is a bilinear lookup in the finest level for both mipmap kinds: [`MipMap::lookup`] does the
//! same. Wrap modes: `repeat`, `black`, `white`, `clamp`. Texel (0, 0) is the top-left corner;
//! (s, t) = (0, 0) is its top-left edge.
//!
//! [`MipMap::differentials`] gives the image's slope at (s, t) for bump mapping, LuxRender's
//! `GetDifferentials`: differences of the neighbouring texels on the finest level, weighted
//! by the position within the texel, times the resolution.

/// How lookups filter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FilterType {
    Nearest,
    Bilinear,
    Trilinear,
    Ewa,
}

/// What lies outside the image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Wrap {
    Repeat,
    Black,
    White,
    Clamp,
}

/// Texel values are RGBA.
pub type Texel = [f32; 4];

/// One level of the pyramid.
#[derive(Debug)]
struct Level {
    w: usize,
    h: usize,
    texels: Vec<Texel>,
}

impl Level {
    fn get(&self, x: usize, y: usize) -> Texel {
        self.texels.get(y * self.w + x).copied().unwrap_or([0.0; 4])
    }
}

/// An image ready for filtered lookups.
#[derive(Debug)]
pub struct MipMap {
    levels: Vec<Level>,
    pub filter: FilterType,
    pub wrap: Wrap,
    pub max_anisotropy: f32,
}

/// Size of the EWA weight table (LuxRender's `WEIGHT_LUT_SIZE`).
const WEIGHT_LUT_SIZE: usize = 128;

fn ewa_weight(r2: f32) -> f32 {
    let i = ((r2 * WEIGHT_LUT_SIZE as f32) as usize).min(WEIGHT_LUT_SIZE - 1);
    let r2 = i as f32 / (WEIGHT_LUT_SIZE - 1) as f32;
    (-2.0 * r2).exp() - (-2.0f32).exp()
}

/// LuxRender's Lanczos-windowed sinc, `x` in [-1, 1].
fn lanczos(x: f32, tau: f32) -> f32 {
    let x = x.abs();
    if x < 1e-5 {
        return 1.0;
    }
    if x > 1.0 {
        return 0.0;
    }
    let x = x * std::f32::consts::PI;
    let s = (x * tau).sin() / (x * tau);
    let l = x.sin() / x;
    s * l
}

/// Resampling weights from `old` to `new` texels (new ≥ old): first texel and 4 weights.
fn resample_weights(old: usize, new: usize) -> Vec<(i64, [f32; 4])> {
    let width = 2.0f32;
    (0..new)
        .map(|i| {
            let center = (i as f32 + 0.5) * old as f32 / new as f32;
            let first = (center - width + 0.5).floor() as i64;
            let mut w = [0.0f32; 4];
            for (j, wj) in w.iter_mut().enumerate() {
                let pos = first as f32 + j as f32 + 0.5;
                *wj = lanczos((pos - center) / width, 2.0);
            }
            let sum: f32 = w.iter().sum();
            if sum != 0.0 {
                for wj in &mut w {
                    *wj /= sum;
                }
            }
            (first, w)
        })
        .collect()
}

fn wrap_index(i: i64, n: usize, wrap: Wrap) -> Option<usize> {
    let n = n as i64;
    match wrap {
        Wrap::Repeat => Some(i.rem_euclid(n) as usize),
        Wrap::Clamp => Some(i.clamp(0, n - 1) as usize),
        Wrap::Black | Wrap::White => (0..n).contains(&i).then_some(i as usize),
    }
}

/// Resamples one axis: rows of `src` (w × h, row major) to `new_w` columns.
fn resample_rows(src: &[Texel], w: usize, h: usize, new_w: usize, wrap: Wrap) -> Vec<Texel> {
    let weights = resample_weights(w, new_w);
    let mut out = vec![[0.0f32; 4]; new_w * h];
    for y in 0..h {
        for (x, (first, wt)) in weights.iter().enumerate() {
            let mut acc = [0.0f32; 4];
            for (j, wj) in wt.iter().enumerate() {
                if let Some(ox) = wrap_index(first + j as i64, w, wrap) {
                    let t = src.get(y * w + ox).copied().unwrap_or([0.0; 4]);
                    for c in 0..4 {
                        acc[c] += wj * t[c];
                    }
                }
            }
            if let Some(o) = out.get_mut(y * new_w + x) {
                *o = acc;
            }
        }
    }
    out
}

fn transpose(src: &[Texel], w: usize, h: usize) -> Vec<Texel> {
    let mut out = vec![[0.0f32; 4]; w * h];
    for y in 0..h {
        for x in 0..w {
            if let (Some(o), Some(s)) = (out.get_mut(x * h + y), src.get(y * w + x)) {
                *o = *s;
            }
        }
    }
    out
}

impl MipMap {
    /// Prepares a `width` × `height` image (rows from the top) for lookups of kind `filter`.
    pub fn new(
        width: usize,
        height: usize,
        texels: &[Texel],
        filter: FilterType,
        wrap: Wrap,
        max_anisotropy: f32,
    ) -> MipMap {
        let base = Level {
            w: width,
            h: height,
            texels: texels.to_vec(),
        };
        let levels = match filter {
            FilterType::Nearest | FilterType::Bilinear => vec![base],
            FilterType::Trilinear | FilterType::Ewa => pyramid(base, wrap),
        };
        MipMap {
            levels,
            filter,
            wrap,
            max_anisotropy,
        }
    }

    /// Drops the `n` finest levels of a pyramid, keeping at least one (LuxRender's
    /// `discardmipmaps`, which saves memory); single-level maps are left alone.
    pub fn discard_levels(&mut self, n: usize) {
        if matches!(self.filter, FilterType::Trilinear | FilterType::Ewa) {
            let n = n.min(self.levels.len().saturating_sub(1));
            self.levels.drain(..n);
        }
    }

    /// Width and height of the finest level.
    pub fn size(&self) -> (usize, usize) {
        self.levels.first().map_or((0, 0), |l| (l.w, l.h))
    }

    pub fn levels(&self) -> usize {
        self.levels.len()
    }

    /// Texel (x, y) of `level` with the wrap mode applied.
    pub fn texel(&self, level: usize, x: i64, y: i64) -> Texel {
        let Some(l) = self.levels.get(level) else {
            return [0.0; 4];
        };
        match (wrap_index(x, l.w, self.wrap), wrap_index(y, l.h, self.wrap)) {
            (Some(x), Some(y)) => l.get(x, y),
            _ => match self.wrap {
                Wrap::White => [1.0; 4],
                _ => [0.0; 4],
            },
        }
    }

    /// Bilinear interpolation on `level`.
    pub fn triangle(&self, level: usize, s: f32, t: f32) -> Texel {
        let level = level.min(self.levels.len().saturating_sub(1));
        let (w, h) = self
            .levels
            .get(level)
            .map_or((1.0, 1.0), |l| (l.w as f32, l.h as f32));
        let (s, t) = (s * w - 0.5, t * h - 0.5);
        let (s0, t0) = (s.floor(), t.floor());
        let (ds, dt) = (s - s0, t - t0);
        let (s0, t0) = (s0 as i64, t0 as i64);
        let mut out = [0.0f32; 4];
        for (dx, dy, wgt) in [
            (0, 0, (1.0 - ds) * (1.0 - dt)),
            (0, 1, (1.0 - ds) * dt),
            (1, 0, ds * (1.0 - dt)),
            (1, 1, ds * dt),
        ] {
            let v = self.texel(level, s0 + dx, t0 + dy);
            for c in 0..4 {
                out[c] += wgt * v[c];
            }
        }
        out
    }

    fn nearest(&self, s: f32, t: f32) -> Texel {
        let (w, h) = self.size();
        let x = (s * w as f32 - 0.5).floor() as i64;
        let y = (t * h as f32 - 0.5).floor() as i64;
        self.texel(0, x, y)
    }

    /// The value at (s, t) as LuxRender 1.x evaluates image textures (no footprint).
    pub fn lookup(&self, s: f32, t: f32) -> Texel {
        if !(s.is_finite() && t.is_finite()) {
            return [0.0; 4];
        }
        match self.filter {
            FilterType::Nearest => self.nearest(s, t),
            _ => self.triangle(0, s, t),
        }
    }

    /// Trilinear lookup over a square footprint of side `width` (in s, t units).
    pub fn lookup_width(&self, s: f32, t: f32, width: f32) -> Texel {
        match self.filter {
            FilterType::Nearest => return self.nearest(s, t),
            FilterType::Bilinear => return self.triangle(0, s, t),
            _ => {}
        }
        let n = self.levels.len();
        let level = (n - 1) as f32 + width.max(1e-8).log2();
        if level < 0.0 || !level.is_finite() {
            self.triangle(0, s, t)
        } else if level >= (n - 1) as f32 {
            let l = &self.levels[n - 1];
            self.texel(
                n - 1,
                (s * l.w as f32).floor() as i64,
                (t * l.h as f32).floor() as i64,
            )
        } else {
            let i = level.floor() as usize;
            let d = level - i as f32;
            let a = self.triangle(i, s, t);
            let b = self.triangle(i + 1, s, t);
            std::array::from_fn(|c| a[c] * (1.0 - d) + b[c] * d)
        }
    }

    /// Filtered lookup over the ellipse with axes (ds0, dt0) and (ds1, dt1): EWA for
    /// `mipmap_ewa`, trilinear over the larger extent for `mipmap_trilinear`.
    pub fn lookup_ellipse(
        &self,
        s: f32,
        t: f32,
        (mut ds0, mut dt0): (f32, f32),
        (mut ds1, mut dt1): (f32, f32),
    ) -> Texel {
        match self.filter {
            FilterType::Trilinear => {
                let w = 2.0 * ds0.abs().max(dt0.abs()).max(ds1.abs().max(dt1.abs()));
                return self.lookup_width(s, t, w);
            }
            FilterType::Ewa => {}
            _ => return self.lookup(s, t),
        }
        if ds0 * ds0 + dt0 * dt0 < ds1 * ds1 + dt1 * dt1 {
            std::mem::swap(&mut ds0, &mut ds1);
            std::mem::swap(&mut dt0, &mut dt1);
        }
        let major = (ds0 * ds0 + dt0 * dt0).sqrt();
        let mut minor = (ds1 * ds1 + dt1 * dt1).sqrt();
        if minor * self.max_anisotropy < major && minor > 0.0 {
            let scale = major / (minor * self.max_anisotropy);
            ds1 *= scale;
            dt1 *= scale;
            minor *= scale;
        }
        let n = self.levels.len();
        let lod = (n - 1) as f32 + minor.log2();
        if lod <= 0.0 || lod.is_nan() {
            return self.triangle(0, s, t);
        }
        if lod >= (n - 1) as f32 {
            let l = &self.levels[n - 1];
            return self.texel(
                n - 1,
                (s * l.w as f32).floor() as i64,
                (t * l.h as f32).floor() as i64,
            );
        }
        let i = lod.floor() as usize;
        let d = lod - i as f32;
        let a = self.ewa(i, s, t, (ds0, dt0), (ds1, dt1));
        let b = self.ewa(i + 1, s, t, (ds0, dt0), (ds1, dt1));
        std::array::from_fn(|c| a[c] * (1.0 - d) + b[c] * d)
    }

    fn ewa(&self, level: usize, s: f32, t: f32, a0: (f32, f32), a1: (f32, f32)) -> Texel {
        let Some(l) = self.levels.get(level) else {
            return [0.0; 4];
        };
        let (w, h) = (l.w as f32, l.h as f32);
        let (s, t) = (s * w, t * h);
        let (ds0, dt0, ds1, dt1) = (a0.0 * w, a0.1 * h, a1.0 * w, a1.1 * h);
        let mut a = dt0 * dt0 + dt1 * dt1 + 1.0;
        let mut b = -2.0 * (ds0 * dt0 + ds1 * dt1);
        let mut c = ds0 * ds0 + ds1 * ds1 + 1.0;
        let f = a * c - b * b * 0.25;
        let (du, dv) = (c.sqrt(), a.sqrt());
        // A footprint is at most the level (the anisotropy clamp keeps it so); cap the scan
        // anyway so that a degenerate ellipse cannot cost more than the level's texels.
        let s0 = (s - du).ceil().max(s - w) as i64;
        let s1 = (s + du).floor().min(s + w) as i64;
        let t0 = (t - dv).ceil().max(t - h) as i64;
        let t1 = (t + dv).floor().min(t + h) as i64;
        if !(f > 0.0 && f.is_finite()) {
            return self.triangle(level, s / w, t / h);
        }
        a /= f;
        b /= f;
        c /= f;
        let mut num = [0.0f32; 4];
        let mut den = 0.0f32;
        for it in t0..=t1 {
            let tt = it as f32 - t;
            for is in s0..=s1 {
                let ss = is as f32 - s;
                let r2 = a * ss * ss + b * ss * tt + c * tt * tt;
                if r2 < 1.0 {
                    let wgt = ewa_weight(r2);
                    let v = self.texel(level, is, it);
                    for k in 0..4 {
                        num[k] += v[k] * wgt;
                    }
                    den += wgt;
                }
            }
        }
        if den > 0.0 {
            num.map(|v| v / den)
        } else {
            self.triangle(level, s / w, t / h)
        }
    }

    /// The image's slope (d/ds, d/dt) at (s, t) of the value `f` gives for a texel, on the
    /// finest level (LuxRender's `GetDifferentials`).
    pub fn differentials(&self, s: f32, t: f32, f: impl Fn(Texel) -> f32) -> (f32, f32) {
        let (w, h) = self.size();
        let (w, h) = (w as f32, h as f32);
        let (s, t) = (s * w, t * h);
        if !(s.is_finite() && t.is_finite()) {
            return (0.0, 0.0);
        }
        let (is, it) = (s.floor(), t.floor());
        let (as_, at) = (s - is, t - it);
        let (is, it) = (is as i64, it as i64);
        let (s0, s1) = if as_ < 0.5 {
            (is - 1, is)
        } else {
            (is, is + 1)
        };
        let (t0, t1) = if at < 0.5 { (it - 1, it) } else { (it, it + 1) };
        let v = |x: i64, y: i64| f(self.texel(0, x, y));
        let ds = ((1.0 - at) * (v(s1, it) - v(s0, it)) + at * (v(s1, it + 1) - v(s0, it + 1))) * w;
        let dt =
            ((1.0 - as_) * (v(is, t1) - v(is, t0)) + as_ * (v(is + 1, t1) - v(is + 1, t0))) * h;
        (ds, dt)
    }
}

/// The power-of-two resampled image and its box-filtered levels.
fn pyramid(base: Level, wrap: Wrap) -> Vec<Level> {
    let (w, h) = (base.w.max(1), base.h.max(1));
    let (pw, ph) = (w.next_power_of_two(), h.next_power_of_two());
    let first = if pw != w || ph != h {
        let rows = resample_rows(&base.texels, w, h, pw, wrap);
        let cols = resample_rows(&transpose(&rows, pw, h), h, pw, ph, wrap);
        let mut texels = transpose(&cols, ph, pw);
        for t in &mut texels {
            for c in t.iter_mut() {
                *c = c.max(0.0);
            }
        }
        Level {
            w: pw,
            h: ph,
            texels,
        }
    } else {
        base
    };
    let n = 1 + (first.w.max(first.h) as f32).log2().floor().max(0.0) as usize;
    let mut levels = vec![first];
    for _ in 1..n {
        let Some(prev) = levels.last() else { break };
        let (w, h) = ((prev.w / 2).max(1), (prev.h / 2).max(1));
        let mut texels = Vec::with_capacity(w * h);
        for y in 0..h {
            for x in 0..w {
                let get = |dx: usize, dy: usize| {
                    prev.get((2 * x + dx).min(prev.w - 1), (2 * y + dy).min(prev.h - 1))
                };
                let (a, b, c, d) = (get(0, 0), get(1, 0), get(0, 1), get(1, 1));
                texels.push(std::array::from_fn(|k| {
                    0.25 * a[k] + 0.25 * b[k] + 0.25 * c[k] + 0.25 * d[k]
                }));
            }
        }
        levels.push(Level { w, h, texels });
    }
    levels
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Img {
        w: usize,
        h: usize,
        texels: Vec<Texel>,
    }

    fn img(w: usize, h: usize, f: impl Fn(usize, usize) -> f32) -> Img {
        let mut texels = Vec::new();
        for y in 0..h {
            for x in 0..w {
                let v = f(x, y);
                texels.push([v, v, v, 1.0]);
            }
        }
        Img { w, h, texels }
    }

    impl MipMap {
        fn of(i: &Img, filter: FilterType, wrap: Wrap, aniso: f32) -> MipMap {
            MipMap::new(i.w, i.h, &i.texels, filter, wrap, aniso)
        }
    }

    #[test]
    fn pyramid_levels_average_and_resample_to_powers_of_two() {
        let m = MipMap::of(
            &img(4, 4, |x, _| x as f32),
            FilterType::Trilinear,
            Wrap::Repeat,
            8.0,
        );
        assert_eq!(m.levels(), 3);
        // Level 1 texel (0, 0) averages columns 0 and 1: 0.5.
        assert_eq!(m.texel(1, 0, 0)[0], 0.5);
        assert_eq!(m.texel(2, 0, 0)[0], 1.5);
        // A 3x3 image is resampled to 4x4; a constant stays constant.
        let c = MipMap::of(&img(3, 3, |_, _| 0.7), FilterType::Ewa, Wrap::Repeat, 8.0);
        assert_eq!(c.size(), (4, 4));
        for (x, y) in [(0, 0), (3, 1), (2, 3)] {
            assert!((c.texel(0, x, y)[0] - 0.7).abs() < 1e-5);
        }
    }

    #[test]
    fn wide_footprints_blur_and_point_lookups_stay_sharp() {
        // Checker of 8x8 texels: a footprint of the whole image gives the mean.
        let m = MipMap::of(
            &img(8, 8, |x, y| ((x + y) % 2) as f32),
            FilterType::Trilinear,
            Wrap::Repeat,
            8.0,
        );
        let wide = m.lookup_width(0.3, 0.3, 1.0)[0];
        assert!((wide - 0.5).abs() < 1e-5, "{wide}");
        let point = m.lookup(1.5 / 8.0, 0.5 / 8.0)[0];
        assert_eq!(point, 1.0);
        let e = MipMap::of(
            &img(8, 8, |x, y| ((x + y) % 2) as f32),
            FilterType::Ewa,
            Wrap::Repeat,
            8.0,
        );
        let v = e.lookup_ellipse(0.4, 0.4, (0.3, 0.0), (0.0, 0.3))[0];
        assert!((v - 0.5).abs() < 0.05, "{v}");
        // Tiny footprint: the finest level.
        let v = e.lookup_ellipse(1.5 / 8.0, 0.5 / 8.0, (1e-4, 0.0), (0.0, 1e-4))[0];
        assert_eq!(v, 1.0);
    }

    #[test]
    fn wraps_and_differentials() {
        let m = MipMap::of(
            &img(2, 1, |x, _| x as f32),
            FilterType::Bilinear,
            Wrap::White,
            8.0,
        );
        assert_eq!(m.texel(0, -1, 0), [1.0; 4]);
        assert_eq!(m.texel(0, 0, 0)[0], 0.0);
        let r = MipMap::of(
            &img(4, 1, |x, _| x as f32),
            FilterType::Bilinear,
            Wrap::Clamp,
            8.0,
        );
        // A ramp of 1 per texel over 4 texels: slope 4 per unit s in the middle.
        let (ds, dt) = r.differentials(0.5, 0.5, |t| t[0]);
        assert_eq!(ds, 4.0);
        assert_eq!(dt, 0.0);
        let n = MipMap::of(
            &img(4, 1, |x, _| x as f32),
            FilterType::Nearest,
            Wrap::Clamp,
            8.0,
        );
        // LuxRender's nearest is half a texel off: s = 0.3 (texel 1.2) reads texel 0.
        assert_eq!(n.lookup(0.3, 0.5)[0], 0.0);
        assert_eq!(n.lookup(0.4, 0.5)[0], 1.0);
    }
}
